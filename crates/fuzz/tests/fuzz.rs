//! The fuzzing budget CI runs: every target for `FUZZ_SECONDS` seconds (default 8) from the
//! fixed seed `FUZZ_SEED` (default 1), each case under a 2-second limit in a worker capped at
//! `FUZZ_MEMORY_MB` (default 3072); then every reproducer in `regressions/`. A failure prints
//! the target, the case index, what happened and the reproducer file (under
//! `target/fuzz-crashers/`), which becomes a regression case once fixed.

use nearfield_fuzz::{Outcome, Target, Worker, fuzz};
use std::path::{Path, PathBuf};
use std::time::Duration;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn worker() -> Worker {
    Worker::start(
        Path::new(env!("CARGO_BIN_EXE_nearfield-fuzz-worker")),
        env_or("FUZZ_MEMORY_MB", 3072),
    )
    .expect("start the fuzz worker")
}

const LIMIT: Duration = Duration::from_secs(2);

fn crashers() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("../fuzz-crashers")
}

fn run(target: Target) {
    let secs: f64 = env_or("FUZZ_SECONDS", 8.0);
    let seed: u64 = env_or("FUZZ_SEED", 1);
    let mut w = worker();
    let t = fuzz(
        &mut w,
        target,
        seed,
        Duration::from_secs_f64(secs),
        LIMIT,
        &crashers(),
    );
    println!(
        "\nfuzz {}: {} cases ({} accepted, {} refused), {} failures, {:.1} s",
        target.name(),
        t.cases,
        t.accepted,
        t.refused,
        t.failures.len(),
        t.seconds
    );
    assert!(t.cases > 0);
    assert!(
        t.failures.is_empty(),
        "fuzz {} (seed {seed}): {} failures:\n{}",
        target.name(),
        t.failures.len(),
        t.failures
            .iter()
            .map(|(i, why, file)| format!("  case {i}: {why}\n    reproducer: {}", file.display()))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

macro_rules! targets {
    ($($name:ident => $target:expr),* $(,)?) => {
        $(#[test] fn $name() { run($target) })*
    };
}

targets! {
    fuzz_gltf_json => Target::GltfJson,
    fuzz_glb => Target::Glb,
    fuzz_obj => Target::Obj,
    fuzz_mtl => Target::Mtl,
    fuzz_ply_ascii => Target::PlyAscii,
    fuzz_ply_binary => Target::PlyBinary,
    fuzz_hdr => Target::Hdr,
    fuzz_exr => Target::Exr,
    fuzz_camera_json => Target::CameraJson,
    fuzz_view_script => Target::ViewScript,
    fuzz_method_specs => Target::MethodSpec,
    fuzz_set_values => Target::SetValues,
}

/// Every seed is accepted unchanged (a seed the loader refuses would test only its first check).
#[test]
fn every_seed_is_accepted() {
    let mut w = worker();
    for target in Target::ALL {
        for (i, seed) in nearfield_fuzz::seeds::seeds(target).iter().enumerate() {
            let out = w.run(target, seed, LIMIT);
            assert_eq!(out, Outcome::Accepted, "{} seed {i}", target.name());
        }
    }
}

/// Every input that once failed (found by this harness, or reported) runs without a failure:
/// `regressions/TARGET/FILE`.
#[test]
fn regressions_stay_fixed() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut w = worker();
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap().flatten() {
        let Some(target) = Target::from_name(&entry.file_name().to_string_lossy()) else {
            continue;
        };
        for file in std::fs::read_dir(entry.path()).unwrap().flatten() {
            let bytes = std::fs::read(file.path()).unwrap();
            let out = w.run(target, &bytes, LIMIT);
            assert!(
                !matches!(out, Outcome::Failed(_)),
                "{}: {out:?}",
                file.path().display()
            );
            count += 1;
        }
    }
    assert!(count > 0, "no regression cases in {}", dir.display());
    println!("\n{count} regression cases");
}

/// The harness catches what it promises to: a panic, a hang past the limit and an allocation
/// past the memory cap each are a failure, and the next case runs in a fresh worker.
#[test]
fn the_harness_reports_panics_hangs_and_allocations_past_the_cap() {
    use nearfield_fuzz::SELF_TEST;
    let mut w = worker();
    let out = w.run(Target::MethodSpec, b"magic", LIMIT);
    assert!(
        matches!(out, Outcome::Refused(ref m) if m.contains("unknown technique")),
        "{out:?}"
    );
    let out = w.run_raw(SELF_TEST, b"panic", LIMIT);
    assert!(
        matches!(out, Outcome::Failed(ref m) if m.contains("told to panic")),
        "{out:?}"
    );
    assert_eq!(
        w.run(Target::MethodSpec, b"ssdo:samples=8", LIMIT),
        Outcome::Accepted
    );
    let out = w.run_raw(SELF_TEST, b"hang", Duration::from_millis(500));
    assert!(
        matches!(out, Outcome::Failed(ref m) if m.contains("hang")),
        "{out:?}"
    );
    assert_eq!(w.run(Target::MethodSpec, b"gtao", LIMIT), Outcome::Accepted);
    let out = w.run_raw(SELF_TEST, b"alloc", LIMIT);
    assert!(
        matches!(out, Outcome::Failed(ref m) if m.contains("worker died")),
        "{out:?}"
    );
    assert_eq!(w.run(Target::MethodSpec, b"none", LIMIT), Outcome::Accepted);
}

//! Long runs show their progress on stderr; with stderr not a terminal (as here) as plain
//! lines, at most one per interval (NEARFIELD_PROGRESS_SECONDS, default 5 s), none for a run
//! shorter than the interval.

use std::process::Command;

fn stderr_of(args: &[&str], every: Option<&str>) -> String {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_nearfield"));
    cmd.args(args);
    match every {
        Some(s) => cmd.env("NEARFIELD_PROGRESS_SECONDS", s),
        None => cmd.env_remove("NEARFIELD_PROGRESS_SECONDS"),
    };
    let out = cmd.output().expect("run nearfield");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    if err.contains("no GPU adapter") {
        assert!(
            std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
            "REQUIRE_GPU=1 but: {err}"
        );
        return String::new();
    }
    assert!(out.status.success(), "{err}");
    err
}

#[test]
fn render_and_bench_report_progress_in_plain_lines() {
    let dir = std::env::temp_dir().join(format!("nearfield-progress-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("p.png");
    let render = [
        "render",
        "builtin:plane",
        "--size",
        "32x18",
        "--frames",
        "24",
        "-o",
        png.to_str().unwrap(),
    ];
    let err = stderr_of(&render, Some("0"));
    if err.is_empty() {
        return;
    }
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("nearfield: render none:") && l.contains("/24 frames"))
        .collect();
    // Every frame but the last prints with a zero interval.
    assert_eq!(lines.len(), 23, "{err}");
    assert!(
        lines[0].contains("1/24 frames") && lines[0].contains("ETA"),
        "{}",
        lines[0]
    );
    // The default interval (5 s) prints nothing for this short run.
    let quiet = stderr_of(&render, None);
    assert!(!quiet.contains("/24 frames"), "{quiet}");

    let bench = [
        "bench",
        "builtin:plane",
        "--size",
        "32x18",
        "--methods",
        "none,ssao",
        "--frames",
        "3",
        "--warmup",
        "1",
    ];
    let err = stderr_of(&bench, Some("0"));
    let n = err
        .lines()
        .filter(|l| l.starts_with("nearfield: bench") && l.contains("/8 frames"))
        .count();
    assert_eq!(n, 7, "{err}");
}

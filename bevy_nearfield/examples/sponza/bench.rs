//! `--bench`: every configuration in turn, A B A B, each frame's interval and each effect's GPU
//! time as Bevy's render diagnostics record it (its `ssao` span, the plugin's `nearfield` and
//! `nearfield add` spans), then one table. `--headless` runs it without a window, into an image
//! (scripts/device-bench.sh on a machine without a display).

use super::{Options, Run, TheCamera, configure};
use bevy::diagnostic::DiagnosticsStore;
use bevy::prelude::*;
use std::time::Instant;

/// The configurations timed, in turn (`--technique` takes any of them; `bevy-ssao` is High).
pub const BENCH: [&str; 9] = [
    "off",
    "bevy-ssao-low",
    "bevy-ssao-medium",
    "bevy-ssao",
    "bevy-ssao-ultra",
    "gtao",
    "hbil",
    "vbgi",
    "gtao-budget",
];

/// Untimed frames after each switch, and rounds after the untimed round 0 (pipelines compile
/// on first use).
const WARMUP: u32 = 10;
const ROUNDS: usize = 2;

/// The diagnostics spans of configuration `name`'s effect.
fn spans(name: &str) -> &'static [&'static str] {
    match name {
        "off" => &[],
        s if s.starts_with("bevy-ssao") => &["ssao"],
        _ => &["nearfield", "nearfield add"],
    }
}

/// The latest GPU time (ms) of the diagnostics span `span` and when it was synced.
fn span_gpu(store: &DiagnosticsStore, span: &str) -> Option<(Instant, f64)> {
    store.iter().find_map(|d| {
        let c: Vec<&str> = d.path().components().collect();
        let [.., name, "elapsed_gpu"] = c.as_slice() else {
            return None;
        };
        (*name == span)
            .then(|| d.measurement().map(|m| (m.time, m.value)))
            .flatten()
    })
}

fn median(v: &mut [f64]) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

/// One frame of the benchmark: switch configuration at each phase's start, record the frame's
/// interval and the effect's GPU time in timed frames, print the table after the last phase.
pub fn step(
    mut commands: Commands,
    mut run: ResMut<Run>,
    options: Res<Options>,
    store: Res<DiagnosticsStore>,
    camera: Single<Entity, With<TheCamera>>,
    mut exit: MessageWriter<AppExit>,
) {
    run.frame += 1;
    let now = Instant::now();
    let per_phase = WARMUP + options.bench_frames;
    let phase = (run.frame / per_phase) as usize;
    let in_phase = run.frame % per_phase;
    if phase >= BENCH.len() * (ROUNDS + 1) {
        print_table(&run);
        exit.write(AppExit::Success);
        return;
    }
    let name = BENCH[phase % BENCH.len()];
    if phase != run.phase || run.frame == 1 {
        run.phase = phase;
        configure(&mut commands, *camera, name, &options);
        run.last = None;
        run.span_seen = Some(now);
    }
    let timed = phase >= BENCH.len() && in_phase >= WARMUP;
    if let Some(last) = run.last
        && timed
    {
        let ms = (now - last).as_secs_f64() * 1e3;
        run.times.push((name.to_string(), ms));
        // The effect's GPU time, once per measurement synced since this phase began.
        let measured: Vec<(Instant, f64)> = spans(name)
            .iter()
            .filter_map(|s| span_gpu(&store, s))
            .collect();
        if let Some(&(time, _)) = measured.first()
            && run.span_seen.is_none_or(|seen| time > seen)
        {
            run.span_seen = Some(time);
            let gpu = measured.iter().map(|(_, ms)| ms).sum();
            run.gpu.push((name.to_string(), gpu));
        }
    }
    run.last = Some(now);
}

fn print_table(run: &Run) {
    let of = |list: &[(String, f64)], name: &str| {
        let mut v: Vec<f64> = list
            .iter()
            .filter(|(n, _)| n == name)
            .map(|(_, t)| *t)
            .collect();
        median(&mut v)
    };
    let frame = |name| of(&run.times, name).unwrap_or(f64::NAN);
    let off = frame("off");
    let ssao = frame("bevy-ssao") - off;
    println!(
        "| configuration | median frame (ms) | overhead (ms) | overhead / Bevy SSAO High | \
         effect's GPU time (ms, median) |"
    );
    println!("|---|---:|---:|---:|---:|");
    for name in BENCH {
        let t = frame(name);
        let gpu = match of(&run.gpu, name) {
            Some(ms) => format!("{ms:.3}"),
            None if spans(name).is_empty() => "".into(),
            None => "n/a".into(),
        };
        println!(
            "| {name} | {t:.2} | {:.2} | {:.2} | {gpu} |",
            t - off,
            (t - off) / ssao
        );
    }
}

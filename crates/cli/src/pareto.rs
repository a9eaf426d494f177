//! `nearfield pareto`: error against time for every technique's quality presets and count
//! settings → pareto.json, pareto.svg (one curve per technique, the front of all of them drawn
//! thick) and a table.
//!
//! Each configuration is measured as `compare` measures (the AOV after `--frames` frames from a
//! restart, the same mask, the relative error against the reference) and timed as `bench`
//! times (after `--warmup` untimed frames, the median of `--timed` frames: wall clock on CPU
//! adapters, whose timestamps are not trustworthy, else the sum of the GPU passes). One
//! renderer serves every configuration of a technique; settings that only change numbers are
//! written in place.
//!
//! The sweep of a technique (unless `--vary` names its settings): its defaults, each `quality`
//! preset, each count setting (samples, slices, steps, sectors, …) at ¼, ½ and 2× its default,
//! and each other value of its denoising settings (denoise, temporal, blur).

use crate::BadInput;
use crate::fit::{Metric, Target, Truth};
use crate::options::{SceneOpts, TechniqueOpts};
use crate::reference::{ReferenceOpts, parse_aov};
use anyhow::{Context, Result};
use clap::Args;
use nearfield_render::settings::SettingKind;
use nearfield_render::technique::TechniqueDesc;
use nearfield_render::{Aov, GpuContext, Renderer};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct ParetoArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    #[command(flatten)]
    pub reference: ReferenceOpts,
    /// Techniques to sweep, comma-separated, each a name or NAME:key=value+… (the sweep varies
    /// settings on top of those). Default: every technique but `none`.
    #[arg(long)]
    pub methods: Option<String>,
    /// AOV whose error is measured (as `compare --aov`).
    #[arg(long, default_value = "ao")]
    pub aov: String,
    /// Near-field radius R in metres, for the techniques and the reference (finite, > 0).
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    pub radius: String,
    /// Frames rendered from a restart before the AOV is measured (1..=10000).
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Untimed frames before the timed ones.
    #[arg(long, default_value_t = 3)]
    pub warmup: u32,
    /// Timed frames per configuration (1..=10000); the median is its time.
    #[arg(long, default_value_t = 10)]
    pub timed: u32,
    /// Instead of the automatic sweep, KEY=V1,V2,… (repeatable): every technique that has KEY
    /// is measured at each value (one setting at a time, the others at their defaults).
    #[arg(long = "vary", value_name = "KEY=V1,V2,...")]
    pub vary: Vec<String>,
    /// Seed of the per-pixel noise and the reference.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Output folder (pareto.json, pareto.svg).
    #[arg(long, default_value = "pareto")]
    pub out: PathBuf,
}

/// One configuration of a technique: what it is called in the plot and its spec.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub label: String,
    pub spec: String,
}

/// Count settings the automatic sweep scales.
const COUNTS: &[&str] = &[
    "samples",
    "slices",
    "steps",
    "sectors",
    "light_samples",
    "vpls",
    "cameras",
];
/// Denoising settings whose every value the automatic sweep tries.
const DENOISE: &[&str] = &["denoise", "temporal", "blur"];

/// `name:key=value+key=value` with `extra` appended.
fn spec_plus(base: &str, extra: &str) -> String {
    if base.contains(':') {
        format!("{base}+{extra}")
    } else {
        format!("{base}:{extra}")
    }
}

/// The values `key` takes in the base spec, or its default.
fn current(desc: &TechniqueDesc, base: &str, key: &str) -> Option<String> {
    let (_, pairs) = nearfield_render::technique::split_spec(base);
    pairs
        .iter()
        .rev()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.clone())
        .or_else(|| {
            desc.settings
                .iter()
                .find(|s| s.key == key)
                .map(|s| s.default.to_string())
        })
}

/// `--vary KEY=V1,V2`: the keys and their values, checked for emptiness.
pub fn parse_vary(vary: &[String]) -> Result<Vec<(String, Vec<String>)>> {
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for v in vary {
        let (k, list) = v
            .split_once('=')
            .ok_or_else(|| BadInput(format!("--vary {v}: expected KEY=V1,V2,...")))?;
        let k = k.trim();
        let values: Vec<String> = list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        if k.is_empty() || values.is_empty() {
            return Err(
                BadInput(format!("--vary {v}: empty sweep (expected KEY=V1,V2,...)")).into(),
            );
        }
        if out.iter().any(|(o, _)| o == k) {
            return Err(BadInput(format!("--vary: {k} is named twice")).into());
        }
        out.push((k.to_string(), values));
    }
    Ok(out)
}

/// Whether setting `doc` applies to technique `name`: a setting whose description names
/// techniques (`(ssdo-vpl, instant-radiosity)`, `hbil: …`) applies to those only.
fn applies(name: &str, doc: &str) -> bool {
    let names = nearfield_render::technique::names();
    let mut named = doc
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .filter(|w| names.contains(w))
        .peekable();
    named.peek().is_none()
        || doc
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .any(|w| w == name)
}

/// The configurations of technique spec `base` (defaults first).
pub fn sweep(base: &str, vary: &[(String, Vec<String>)]) -> Result<Vec<Config>> {
    let desc = nearfield_render::technique::find(base)?;
    let mut configs = vec![Config {
        label: "default".into(),
        spec: base.to_string(),
    }];
    let mut push = |label: String, spec: String| {
        if !configs.iter().any(|c| c.spec == spec) {
            configs.push(Config { label, spec });
        }
    };
    let has = |key: &str| desc.settings.iter().any(|s| s.key == key);
    if !vary.is_empty() {
        for (key, values) in vary {
            if !has(key) {
                continue;
            }
            for v in values {
                push(format!("{key}={v}"), spec_plus(base, &format!("{key}={v}")));
            }
        }
    } else {
        for p in desc.presets {
            push(
                format!("quality={}", p.name),
                spec_plus(base, &format!("quality={}", p.name)),
            );
        }
        for s in desc.settings.iter().filter(|s| applies(desc.name, s.doc)) {
            let Some(now) = current(desc, base, s.key) else {
                continue;
            };
            match s.kind {
                SettingKind::Number {
                    lo,
                    hi,
                    integer: true,
                    ..
                } if COUNTS.contains(&s.key) => {
                    let Ok(d) = now.parse::<f64>() else { continue };
                    for f in [0.25, 0.5, 2.0] {
                        let v = (d * f).round().clamp(lo as f64, hi as f64);
                        if v != d && v >= 1.0 {
                            push(
                                format!("{}={v}", s.key),
                                spec_plus(base, &format!("{}={v}", s.key)),
                            );
                        }
                    }
                }
                SettingKind::Toggle if DENOISE.contains(&s.key) => {
                    let other = if now == "on" { "off" } else { "on" };
                    push(
                        format!("{}={other}", s.key),
                        spec_plus(base, &format!("{}={other}", s.key)),
                    );
                }
                SettingKind::Choice(values) if DENOISE.contains(&s.key) => {
                    for v in values.iter().filter(|v| **v != now) {
                        push(
                            format!("{}={v}", s.key),
                            spec_plus(base, &format!("{}={v}", s.key)),
                        );
                    }
                }
                _ => {}
            }
        }
    }
    if configs.len() < 2 {
        return Err(BadInput(format!(
            "{}: empty sweep: {} has no quality presets, count or denoising settings{}",
            base,
            desc.name,
            if vary.is_empty() {
                ""
            } else {
                " named by --vary"
            }
        ))
        .into());
    }
    Ok(configs)
}

/// Every setting of technique spec `spec` with its value (defaults, then the preset's and the
/// spec's own values; numbers compared as numbers): what two specs must share to be one
/// configuration.
fn effective_settings(
    spec: &str,
    params: &nearfield_render::TechniqueParams,
) -> Result<Vec<(String, String)>> {
    let (desc, resolved) = nearfield_render::technique::resolve_params(spec, params)?;
    let mut values: Vec<(String, String)> = desc
        .settings
        .iter()
        .map(|s| (s.key.to_string(), s.default.to_string()))
        .collect();
    for (k, v) in &resolved.set {
        if let Some(slot) = values.iter_mut().find(|(key, _)| key == k) {
            slot.1 = v.clone();
        } else {
            values.push((k.clone(), v.clone()));
        }
    }
    if let Some(n) = resolved.samples {
        values.push(("--samples".into(), n.to_string()));
    }
    for (_, v) in &mut values {
        if let Ok(x) = v.parse::<f64>() {
            *v = format!("{x}");
        }
    }
    Ok(values)
}

/// A measured configuration.
#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct Point {
    pub label: String,
    pub spec: String,
    /// Median frame time (ms).
    pub ms: f64,
    /// Frame time minus the `none` technique's (ms): what the technique costs.
    pub cost_ms: f64,
    pub error: f64,
    /// On the front of all techniques / of its own technique.
    pub front: bool,
    pub technique_front: bool,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct MethodFront {
    pub name: String,
    pub points: Vec<Point>,
    /// The default's time over the fastest configuration of this technique that is at least as
    /// accurate, minus 1 (0: the default is on its front).
    pub default_slack: f64,
    /// `default_slack` ≤ 0.1: the default is on or near its front.
    pub default_near_front: bool,
}

#[derive(Serialize)]
struct ParetoFile {
    scene: String,
    aov: String,
    metric: &'static str,
    size: [u32; 2],
    radius: f32,
    frames: u32,
    warmup: u32,
    timed: u32,
    spp: u32,
    adapter: String,
    timing: &'static str,
    none_ms: f64,
    methods: Vec<MethodFront>,
    command: String,
    seconds: f64,
}

/// Marks the points no other point beats in both time and error (ties keep both).
pub fn mark_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

/// The default (point 0)'s slack: its time over the fastest point at least as accurate, − 1.
pub fn default_slack(points: &[(f64, f64)]) -> f64 {
    let (t0, e0) = points[0];
    let best = points
        .iter()
        .filter(|p| p.1 <= e0)
        .map(|p| p.0)
        .fold(f64::INFINITY, f64::min);
    t0 / best - 1.0
}

fn median(v: &mut [f64]) -> f64 {
    crate::bench::stat(v).median_ms
}

/// Renders `warmup` then `timed` frames and returns the median time (ms).
fn time_frames(r: &mut Renderer, warmup: u32, timed: u32, gpu: bool) -> Result<f64> {
    for _ in 0..warmup {
        r.render_frame();
    }
    r.wait();
    let mut v = Vec::with_capacity(timed as usize);
    for _ in 0..timed {
        let t0 = Instant::now();
        r.render_frame();
        r.wait();
        let wall = t0.elapsed().as_secs_f64() * 1e3;
        v.push(if gpu {
            r.timings().iter().map(|(_, ms)| ms).sum()
        } else {
            wall
        });
    }
    r.check_device()?;
    Ok(median(&mut v))
}

pub fn run(args: ParetoArgs) -> Result<()> {
    let t0 = Instant::now();
    let ref_name = if args.aov == "lambertian" {
        "radiance"
    } else {
        args.aov.as_str()
    };
    let ref_aov = parse_aov(ref_name)?;
    let aov = Aov::parse(&args.aov).expect("every reference AOV is a renderer AOV");
    for (name, v) in [("--frames", args.frames), ("--timed", args.timed)] {
        if v == 0 || v > 10_000 {
            return Err(BadInput(format!("{name} {v}: must be in 1..=10000")).into());
        }
    }
    if args.warmup > 10_000 {
        return Err(BadInput(format!("--warmup {}: must be at most 10000", args.warmup)).into());
    }
    let (technique, params, radius) = TechniqueOpts::measured(&args.radius, &[], args.seed)?;
    let methods: Vec<String> = match &args.methods {
        Some(m) => m
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect(),
        None => nearfield_render::technique::names()
            .into_iter()
            .filter(|n| *n != "none")
            .map(String::from)
            .collect(),
    };
    if methods.is_empty() {
        return Err(BadInput("--methods: no technique named".into()).into());
    }
    let vary = parse_vary(&args.vary)?;
    let mut sweeps = Vec::new();
    // Said once every argument is known to be good (a bad one gets one line).
    let mut notes = Vec::new();
    for m in &methods {
        nearfield_render::technique::check_spec(m, &params)?;
        let configs = sweep(m, &vary)?;
        // Every configuration is checked before anything is loaded; one that comes to the same
        // settings as an earlier one (a preset equal to the defaults) is measured once.
        let mut kept: Vec<Config> = Vec::new();
        let mut seen = Vec::new();
        for c in configs {
            match nearfield_render::technique::check_spec(&c.spec, &params) {
                Ok(()) => {
                    let effective = effective_settings(&c.spec, &params)?;
                    if let Some(k) = seen.iter().position(|s| *s == effective) {
                        notes.push(format!(
                            "nearfield: {} left out: the same settings as {}",
                            c.spec, kept[k].spec
                        ));
                        continue;
                    }
                    seen.push(effective);
                    kept.push(c);
                }
                Err(e) if kept.is_empty() => return Err(e.into()),
                Err(e) => notes.push(format!("nearfield: {} left out: {e}", c.spec)),
            }
        }
        sweeps.push((m.clone(), kept));
    }
    let size = crate::options::parse_size(&args.scene.size)?;
    let settings = technique.settings(size)?;
    let ref_settings = args.reference.settings(ref_aov, size, radius, args.seed)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    args.far.precheck()?;
    let loaded = args.scene.load()?;
    let volume = args
        .far
        .resolve(&args.scene, &loaded, Some(args.aov.as_str()))?;
    for n in &notes {
        eprintln!("{n}");
    }
    let ctx = GpuContext::new(args.scene.adapter.as_deref())?;
    let info = ctx.adapter_info();
    let gpu = ctx.timestamps && info.device_type != nearfield_render::wgpu::DeviceType::Cpu;
    let (img, _) = crate::reference::compute(&args.scene, &args.reference, &loaded, &ref_settings)?;
    let truth = Truth::new(aov, img.value, img.depth, size);
    if truth.is_zero() {
        return Err(BadInput(format!(
            "{}: the reference {} is zero everywhere: its relative error is undefined",
            args.scene.scene, args.aov
        ))
        .into());
    }
    let total: usize = sweeps.iter().map(|(_, c)| c.len()).sum();
    let progress = nearfield_scene::progress::Progress::new(
        "pareto",
        total as u64 + 1,
        "configurations",
        true,
    );
    // The frame without a technique: what every technique's cost is measured from.
    progress.set_message("none");
    let none_ms = {
        let mut r = Renderer::new(
            &ctx,
            &loaded.scene,
            &loaded.env,
            loaded.camera,
            "none",
            &params,
            settings,
        )?;
        r.set_far_field(volume.as_ref())?;
        time_frames(&mut r, args.warmup, args.timed, gpu)?
    };
    progress.inc(1);
    loaded.report_sun();
    let mut fronts = Vec::new();
    let mut truth = Some(truth);
    for (method, configs) in &sweeps {
        let mut renderer = Renderer::new(
            &ctx,
            &loaded.scene,
            &loaded.env,
            loaded.camera,
            &configs[0].spec,
            &params,
            settings,
        )?;
        renderer.set_far_field(volume.as_ref())?;
        let mut target = Target {
            name: method.clone(),
            renderer,
            truths: vec![truth.take().expect("returned after each method")],
        };
        let mut points = Vec::new();
        for c in configs {
            progress.set_message(&c.spec);
            let error = target.evaluate(&c.spec, &params, args.frames, Metric::Relative)?;
            let ms = time_frames(&mut target.renderer, args.warmup, args.timed, gpu)?;
            progress.inc(1);
            points.push(Point {
                label: c.label.clone(),
                spec: c.spec.clone(),
                ms,
                cost_ms: ms - none_ms,
                error,
                front: false,
                technique_front: false,
            });
        }
        let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.ms, p.error)).collect();
        for (p, f) in points.iter_mut().zip(mark_front(&xy)) {
            p.technique_front = f;
        }
        let slack = default_slack(&xy);
        fronts.push(MethodFront {
            name: method.clone(),
            points,
            default_slack: slack,
            default_near_front: slack <= 0.1,
        });
        truth = target.truths.pop();
    }
    progress.finish();
    let all: Vec<(f64, f64)> = fronts
        .iter()
        .flat_map(|m| m.points.iter().map(|p| (p.ms, p.error)))
        .collect();
    let mut marks = mark_front(&all).into_iter();
    for m in &mut fronts {
        for p in &mut m.points {
            p.front = marks.next().expect("one mark per point");
        }
    }
    print_table(&fronts, none_ms, gpu);
    let file = ParetoFile {
        scene: args.scene.scene.clone(),
        aov: args.aov.clone(),
        metric: "rel",
        size: [size.0, size.1],
        radius,
        frames: args.frames,
        warmup: args.warmup,
        timed: args.timed,
        spp: ref_settings.spp,
        adapter: nearfield_render::context::describe(&info),
        timing: if gpu { "gpu" } else { "wall" },
        none_ms,
        methods: fronts,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        seconds: t0.elapsed().as_secs_f64(),
    };
    let json = serde_json::to_string_pretty(&file)?;
    let svg = svg(
        &file.methods,
        &format!(
            "{} · {} · {}×{} · R {} m · {} frame{}",
            short_scene(&file.scene),
            file.aov,
            size.0,
            size.1,
            radius,
            args.frames,
            if args.frames == 1 { "" } else { "s" }
        ),
        if gpu {
            "GPU time per frame (ms)"
        } else {
            "wall time per frame (ms)"
        },
    );
    nearfield_scene::atomic::write_bytes(&args.out.join("pareto.json"), json.as_bytes())
        .map_err(anyhow::Error::msg)?;
    nearfield_scene::atomic::write_bytes(&args.out.join("pareto.svg"), svg.as_bytes())
        .map_err(anyhow::Error::msg)?;
    eprintln!(
        "nearfield: wrote {}/pareto.json and pareto.svg ({} configurations, {:.1} s)",
        args.out.display(),
        total,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

fn print_table(fronts: &[MethodFront], none_ms: f64, gpu: bool) {
    println!(
        "{:<44} {:>9} {:>9} {:>8}  front (* all, + technique)   [{} time; none {none_ms:.2} ms]",
        "configuration",
        "ms",
        "cost ms",
        "rel err",
        if gpu { "GPU" } else { "wall" }
    );
    for m in fronts {
        for p in &m.points {
            println!(
                "{:<44} {:>9.2} {:>9.2} {:>8.4}  {}{}",
                p.spec,
                p.ms,
                p.cost_ms,
                p.error,
                if p.front { "*" } else { " " },
                if p.technique_front { "+" } else { " " }
            );
        }
        println!(
            "  {}: default {} (slack {:+.1} % in time)",
            m.name,
            if m.default_near_front {
                "on or near its front"
            } else {
                "off its front"
            },
            100.0 * m.default_slack
        );
    }
}

const PALETTE: &[&str] = &[
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// Ticks of a log axis between `lo` and `hi`: 1, 2, 5 × powers of ten.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = decade * m;
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
        decade *= 10.0;
    }
    out
}

fn fmt_tick(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').to_string()
    }
}

/// Error (log) against time (log): every configuration a dot, each technique's own front a
/// line, the front of all techniques thick and dashed, defaults ringed.
pub fn svg(methods: &[MethodFront], title: &str, x_label: &str) -> String {
    use std::fmt::Write;
    let (w, h) = (760.0, 500.0);
    let (left, right, top, bottom) = (70.0, 190.0, 40.0, 55.0);
    let pts = || methods.iter().flat_map(|m| m.points.iter());
    let finite = |v: f64| v.is_finite() && v > 0.0;
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in pts().filter(|p| finite(p.ms) && finite(p.error)) {
        t0 = t0.min(p.ms);
        t1 = t1.max(p.ms);
        e0 = e0.min(p.error);
        e1 = e1.max(p.error);
    }
    if t0 > t1 {
        (t0, t1, e0, e1) = (1.0, 10.0, 0.01, 1.0);
    }
    // A margin of 10 % (in log) on each side.
    let pad = |a: f64, b: f64| {
        let (la, lb) = (a.log10(), b.log10().max(a.log10() + 0.3));
        let m = 0.1 * (lb - la);
        (10f64.powf(la - m), 10f64.powf(lb + m))
    };
    let (t0, t1) = pad(t0, t1);
    let (e0, e1) = pad(e0, e1);
    let x =
        |t: f64| left + (w - left - right) * (t.log10() - t0.log10()) / (t1.log10() - t0.log10());
    let y = |e: f64| {
        h - bottom - (h - top - bottom) * (e.log10() - e0.log10()) / (e1.log10() - e0.log10())
    };
    let mut s = String::new();
    let _ = write!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">
<rect width="100%" height="100%" fill="white"/>
<text x="{}" y="22" text-anchor="middle" font-size="14">{}</text>
"##,
        (left + w - right) / 2.0,
        xml(title)
    );
    for t in log_ticks(t0, t1) {
        let _ = writeln!(
            s,
            r##"<line x1="{0:.1}" y1="{1}" x2="{0:.1}" y2="{2}" stroke="#ddd"/><text x="{0:.1}" y="{3}" text-anchor="middle">{4}</text>"##,
            x(t),
            top,
            h - bottom,
            h - bottom + 16.0,
            fmt_tick(t)
        );
    }
    for e in log_ticks(e0, e1) {
        let _ = writeln!(
            s,
            r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="#ddd"/><text x="{3}" y="{4:.1}" text-anchor="end">{5}</text>"##,
            left,
            y(e),
            w - right,
            left - 6.0,
            y(e) + 4.0,
            fmt_tick(e)
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{left}" y="{top}" width="{}" height="{}" fill="none" stroke="#444"/>
<text x="{}" y="{}" text-anchor="middle">{}</text>
<text transform="translate(18 {}) rotate(-90)" text-anchor="middle">relative error</text>"##,
        w - left - right,
        h - top - bottom,
        (left + w - right) / 2.0,
        h - 14.0,
        xml(x_label),
        (top + h - bottom) / 2.0
    );
    let line = |points: Vec<(f64, f64)>| -> String {
        let mut points: Vec<(f64, f64)> = points
            .into_iter()
            .filter(|(t, e)| finite(*t) && finite(*e))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points
            .iter()
            .map(|(t, e)| format!("{:.1},{:.1}", x(*t), y(*e)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let global: Vec<(f64, f64)> = pts().filter(|p| p.front).map(|p| (p.ms, p.error)).collect();
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#000" stroke-width="4" stroke-dasharray="8 5" opacity="0.35"/>"##,
        line(global)
    );
    for (i, m) in methods.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        let own: Vec<(f64, f64)> = m
            .points
            .iter()
            .filter(|p| p.technique_front)
            .map(|p| (p.ms, p.error))
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.8"/>"##,
            line(own)
        );
        for (k, p) in m.points.iter().enumerate() {
            if !(finite(p.ms) && finite(p.error)) {
                continue;
            }
            let _ = writeln!(
                s,
                r##"<circle cx="{:.1}" cy="{:.1}" r="{}" fill="{}" stroke="{c}" stroke-width="1.5"><title>{} — {:.2} ms, rel {:.4}</title></circle>"##,
                x(p.ms),
                y(p.error),
                if k == 0 { 6.0 } else { 3.5 },
                if k == 0 { "white" } else { c },
                xml(&p.spec),
                p.ms,
                p.error
            );
        }
        let ly = top + 10.0 + 18.0 * i as f64;
        let _ = writeln!(
            s,
            r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="{c}" stroke-width="2"/><circle cx="{3}" cy="{1:.1}" r="3.5" fill="{c}"/><text x="{4}" y="{5:.1}">{6}</text>"##,
            w - right + 14.0,
            ly,
            w - right + 38.0,
            w - right + 26.0,
            w - right + 44.0,
            ly + 4.0,
            xml(&m.name)
        );
    }
    let ly = top + 10.0 + 18.0 * methods.len() as f64;
    let _ = writeln!(
        s,
        r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="#000" stroke-width="4" stroke-dasharray="8 5" opacity="0.35"/><text x="{3}" y="{4:.1}">front of all</text>
<circle cx="{5}" cy="{6:.1}" r="6" fill="white" stroke="#000" stroke-width="1.5"/><text x="{3}" y="{7:.1}">default</text>
</svg>"##,
        w - right + 14.0,
        ly,
        w - right + 38.0,
        w - right + 44.0,
        ly + 4.0,
        w - right + 26.0,
        ly + 18.0,
        ly + 22.0
    );
    s
}

/// `builtin:cornell` → cornell, a path → its file name.
pub(crate) fn short_scene(s: &str) -> String {
    s.strip_prefix("builtin:")
        .map(String::from)
        .unwrap_or_else(|| {
            std::path::Path::new(s)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| s.to_string())
        })
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_keeps_exactly_the_undominated_points() {
        let p = [
            (1.0, 0.5),
            (2.0, 0.3),
            (3.0, 0.4),
            (4.0, 0.1),
            (2.0, 0.3),
            (5.0, 0.1),
        ];
        assert_eq!(mark_front(&p), vec![true, true, false, true, true, false]);
    }

    #[test]
    fn the_default_slack_is_measured_from_the_fastest_point_as_accurate() {
        // Default 3 ms at 0.3; a 2 ms point reaches 0.25: slack 50 %.
        let s = default_slack(&[(3.0, 0.3), (2.0, 0.25), (1.0, 0.5)]);
        assert!((s - 0.5).abs() < 1e-12);
        // On its front: 0.
        assert_eq!(default_slack(&[(1.0, 0.3), (2.0, 0.2)]), 0.0);
    }

    #[test]
    fn the_automatic_sweep_scales_counts_and_tries_the_denoisers() {
        let c = sweep("gtao", &[]).unwrap();
        let specs: Vec<&str> = c.iter().map(|c| c.spec.as_str()).collect();
        assert_eq!(specs[0], "gtao");
        for want in [
            "gtao:quality=low",
            "gtao:quality=fitted",
            "gtao:slices=1",
            "gtao:slices=4",
            "gtao:steps=4",
            "gtao:steps=8",
            "gtao:steps=32",
            "gtao:denoise=off",
            "gtao:denoise=svgf",
            "gtao:temporal=off",
        ] {
            assert!(specs.contains(&want), "{want} missing from {specs:?}");
        }
        // slices=2 × ½ = 1 and × ¼ = 0.5 → 1 (once); nothing equals the default.
        assert_eq!(specs.iter().filter(|s| **s == "gtao:slices=1").count(), 1);
        assert!(!specs.contains(&"gtao:slices=2"));
        // On top of a base spec.
        let c = sweep("gtao:denoise=off", &[]).unwrap();
        assert!(c.iter().any(|c| c.spec == "gtao:denoise=off+slices=4"));
        assert!(
            c.iter()
                .any(|c| c.spec == "gtao:denoise=off+denoise=bilateral")
        );
    }

    #[test]
    fn settings_of_other_techniques_are_not_swept() {
        let specs: Vec<String> = sweep("ssao", &[])
            .unwrap()
            .into_iter()
            .map(|c| c.spec)
            .collect();
        assert!(specs.contains(&"ssao:samples=8".to_string()), "{specs:?}");
        assert!(
            !specs
                .iter()
                .any(|s| s.contains("vpls") || s.contains("light_samples")),
            "{specs:?}"
        );
        let specs: Vec<String> = sweep("ssdo-vpl", &[])
            .unwrap()
            .into_iter()
            .map(|c| c.spec)
            .collect();
        assert!(specs.iter().any(|s| s.contains("vpls=")), "{specs:?}");
    }

    #[test]
    fn a_preset_equal_to_the_defaults_is_one_configuration() {
        let p = nearfield_render::TechniqueParams::default();
        // gtao's medium preset is its defaults (2 slices × 16 steps).
        assert_eq!(
            effective_settings("gtao", &p).unwrap(),
            effective_settings("gtao:quality=medium", &p).unwrap()
        );
        assert_eq!(
            effective_settings("gtao:steps=16.0", &p).unwrap(),
            effective_settings("gtao", &p).unwrap()
        );
        assert_ne!(
            effective_settings("gtao:quality=low", &p).unwrap(),
            effective_settings("gtao", &p).unwrap()
        );
    }

    #[test]
    fn vary_replaces_the_sweep_and_an_empty_sweep_is_refused() {
        let vary = parse_vary(&["steps=2,3".into()]).unwrap();
        let c = sweep("gtao", &vary).unwrap();
        let specs: Vec<&str> = c.iter().map(|c| c.spec.as_str()).collect();
        assert_eq!(specs, ["gtao", "gtao:steps=2", "gtao:steps=3"]);
        assert!(sweep("none", &[]).is_err());
        let other = parse_vary(&["nosuch=1".into()]).unwrap();
        assert!(sweep("gtao", &other).is_err(), "gtao has no setting nosuch");
        assert!(parse_vary(&["steps=".into()]).is_err());
        assert!(parse_vary(&["steps".into()]).is_err());
    }

    #[test]
    fn the_plot_draws_every_point_and_the_front() {
        let m = MethodFront {
            name: "a<b".into(),
            points: vec![
                Point {
                    label: "default".into(),
                    spec: "a".into(),
                    ms: 2.0,
                    cost_ms: 1.0,
                    error: 0.2,
                    front: true,
                    technique_front: true,
                },
                Point {
                    label: "x".into(),
                    spec: "a:x=1".into(),
                    ms: 5.0,
                    cost_ms: 4.0,
                    error: 0.3,
                    front: false,
                    technique_front: false,
                },
            ],
            default_slack: 0.0,
            default_near_front: true,
        };
        let s = svg(&[m], "t", "ms");
        assert_eq!(
            s.matches("<circle").count(),
            2 + 1 + 1,
            "two points, legend dot and ring"
        );
        assert!(s.contains("a&lt;b") && !s.contains("a<b"));
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
    }
}

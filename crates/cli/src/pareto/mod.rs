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
use crate::measure::schema::{MethodFront, ParetoFile, Point};
use crate::measure::{Metric, Target, Truth};
use crate::options::{SceneOpts, TechniqueOpts};
use crate::reference::{ReferenceOpts, parse_aov};
use anyhow::{Context, Result};
use clap::Args;
pub use front::{default_slack, mark_front};
use nearfield_render::{Aov, GpuContext, Renderer, TechniqueParams};
use std::path::PathBuf;
use std::time::Instant;
use sweep::effective_settings;
pub use sweep::{Config, parse_vary, sweep};

mod front;
mod sweep;

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
            nearfield_render::profiler::frame_total(&r.timings())
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
    check_counts(&args)?;
    let (technique, params, radius) = TechniqueOpts::measured(&args.radius, &[], args.seed)?;
    let methods = methods_of(args.methods.as_deref())?;
    let (sweeps, notes) = checked_sweeps(&methods, &parse_vary(&args.vary)?, &params)?;
    let size = crate::options::parse_size(&args.scene.size)?;
    let settings = technique.settings(size)?;
    let ref_settings = args.reference.settings(ref_aov, size, radius, args.seed)?;
    args.far.precheck()?;
    // The adapter first: a machine that cannot run the passes hears so before a bake.
    let ctx = GpuContext::new(args.scene.adapter.as_deref())?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let loaded = args.scene.load()?;
    let volume = args
        .far
        .resolve(&args.scene, &loaded, Some(args.aov.as_str()))?;
    for n in &notes {
        eprintln!("{n}");
    }
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
            volume.as_ref(),
            loaded.camera,
            &nearfield_render::technique::Spec::resolve("none", &params)?,
            settings,
        )?;
        time_frames(&mut r, args.warmup, args.timed, gpu)?
    };
    progress.inc(1);
    loaded.report_sun();
    let mut fronts = Vec::new();
    let mut truth = Some(truth);
    let measure = Measure {
        ctx: &ctx,
        loaded: &loaded,
        volume: volume.as_ref(),
        params: &params,
        settings,
        args: &args,
        gpu,
        none_ms,
        progress: &progress,
    };
    for (method, configs) in &sweeps {
        let t = truth.take().expect("returned after each method");
        let (front, t) = measure.front(method, configs, t)?;
        fronts.push(front);
        truth = Some(t);
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
        dir: String::new(),
        scene: args.scene.scene.clone(),
        aov: args.aov.clone(),
        metric: "rel".into(),
        size: [size.0, size.1],
        radius,
        frames: args.frames,
        warmup: args.warmup,
        timed: args.timed,
        spp: ref_settings.spp,
        adapter: nearfield_render::context::describe(&info),
        timing: if gpu { "gpu" } else { "wall" }.into(),
        none_ms,
        methods: fronts,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        seconds: t0.elapsed().as_secs_f64(),
    };
    write(&args.out, &file, args.frames, total, t0)
}

/// Writes pareto.json and pareto.svg into `out`.
fn write(
    out: &std::path::Path,
    file: &ParetoFile,
    frames: u32,
    total: usize,
    t0: Instant,
) -> Result<()> {
    let json = serde_json::to_string_pretty(file)?;
    let svg = svg(
        &file.methods,
        &format!(
            "{} · {} · {}×{} · R {} m · {} frame{}",
            short_scene(&file.scene),
            file.aov,
            file.size[0],
            file.size[1],
            file.radius,
            frames,
            if frames == 1 { "" } else { "s" }
        ),
        if file.timing == "gpu" {
            "GPU time per frame (ms)"
        } else {
            "wall time per frame (ms)"
        },
    );
    nearfield_scene::atomic::write_bytes(&out.join("pareto.json"), json.as_bytes())
        .map_err(anyhow::Error::msg)?;
    nearfield_scene::atomic::write_bytes(&out.join("pareto.svg"), svg.as_bytes())
        .map_err(anyhow::Error::msg)?;
    eprintln!(
        "nearfield: wrote {}/pareto.json and pareto.svg ({} configurations, {:.1} s)",
        out.display(),
        total,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `--frames`, `--timed` and `--warmup`.
fn check_counts(args: &ParetoArgs) -> Result<()> {
    for (name, v) in [("--frames", args.frames), ("--timed", args.timed)] {
        if v == 0 || v > 10_000 {
            return Err(BadInput(format!("{name} {v}: must be in 1..=10000")).into());
        }
    }
    if args.warmup > 10_000 {
        return Err(BadInput(format!("--warmup {}: must be at most 10000", args.warmup)).into());
    }
    Ok(())
}

/// `--methods`, or every registered technique but `none`.
fn methods_of(list: Option<&str>) -> Result<Vec<String>> {
    let methods: Vec<String> = match list {
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
    Ok(methods)
}

/// Each technique's configurations, every one checked before anything is loaded; one that comes
/// to the same settings as an earlier one (a preset equal to the defaults) is measured once. The
/// notes say which were left out, once every argument is known to be good.
#[allow(clippy::type_complexity)]
fn checked_sweeps(
    methods: &[String],
    vary: &[(String, Vec<String>)],
    params: &TechniqueParams,
) -> Result<(Vec<(String, Vec<Config>)>, Vec<String>)> {
    let mut sweeps = Vec::new();
    let mut notes = Vec::new();
    for m in methods {
        nearfield_render::technique::check_spec(m, params)?;
        let mut kept: Vec<Config> = Vec::new();
        let mut seen = Vec::new();
        for c in sweep(m, vary)? {
            match nearfield_render::technique::check_spec(&c.spec, params) {
                Ok(()) => {
                    let effective = effective_settings(&c.spec, params)?;
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
    Ok((sweeps, notes))
}

/// What a technique's front is measured with.
struct Measure<'a> {
    ctx: &'a GpuContext,
    loaded: &'a crate::options::Loaded,
    volume: Option<&'a nearfield_scene::probes::ProbeVolume>,
    params: &'a TechniqueParams,
    settings: nearfield_render::RenderSettings,
    args: &'a ParetoArgs,
    gpu: bool,
    none_ms: f64,
    progress: &'a nearfield_scene::progress::Progress,
}

impl Measure<'_> {
    /// Every configuration of `method` on one renderer: its error against `truth` and its time;
    /// the technique's own front marked. Gives the truth back.
    fn front(
        &self,
        method: &str,
        configs: &[Config],
        truth: Truth,
    ) -> Result<(MethodFront, Truth)> {
        let (args, params) = (self.args, self.params);
        let renderer = Renderer::new(
            self.ctx,
            &self.loaded.scene,
            &self.loaded.env,
            self.volume,
            self.loaded.camera,
            &nearfield_render::technique::Spec::resolve(&configs[0].spec, params)?,
            self.settings,
        )?;
        let mut target = Target {
            name: method.to_string(),
            renderer,
            truths: vec![truth],
        };
        let mut points = Vec::new();
        for c in configs {
            self.progress.set_message(&c.spec);
            let error = target.evaluate(&c.spec, params, args.frames, Metric::Relative)?;
            let ms = time_frames(&mut target.renderer, args.warmup, args.timed, self.gpu)?;
            self.progress.inc(1);
            points.push(Point {
                label: c.label.clone(),
                spec: c.spec.clone(),
                ms,
                cost_ms: ms - self.none_ms,
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
        let front = MethodFront {
            name: method.to_string(),
            points,
            default_slack: slack,
            default_near_front: slack <= 0.1,
        };
        Ok((front, target.truths.pop().expect("the truth it was given")))
    }
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

/// The SVG plot of `methods` ([`nearfield_eval::plot::pareto_svg`]).
pub fn svg(methods: &[MethodFront], title: &str, x_label: &str) -> String {
    let series: Vec<nearfield_eval::plot::Series> = methods
        .iter()
        .map(|m| nearfield_eval::plot::Series {
            name: &m.name,
            points: m
                .points
                .iter()
                .map(|p| nearfield_eval::plot::Point {
                    x: p.ms,
                    y: p.error,
                    front: p.front,
                    own_front: p.technique_front,
                    label: &p.spec,
                })
                .collect(),
        })
        .collect();
    nearfield_eval::plot::pareto_svg(&series, title, x_label)
}

#[cfg(test)]
mod tests {
    use super::*;

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

//! `nearfield bench`: per-pass GPU timings (timestamp queries) of one or more techniques.

use crate::options::{SceneOpts, TechniqueOpts};
use anyhow::Result;
use clap::Args;
use nearfield_render::{GpuContext, Renderer};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub technique: TechniqueOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    /// Techniques to time, comma-separated (default: every registered one).
    #[arg(long)]
    pub methods: Option<String>,
    /// Timed frames per technique (1..=100000).
    #[arg(long, default_value_t = 30)]
    pub frames: u32,
    /// Untimed frames first (shader compilation, caches).
    #[arg(long, default_value_t = 5)]
    pub warmup: u32,
    /// Degrees the camera turns about its target before every frame after the first (timings
    /// then include reprojection of a moving view). A moving scene plays its animation in a
    /// loop at 30 frames a second, as in the viewer (timings then include posing the objects
    /// and redrawing the shadow maps they move through).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub orbit: f32,
    /// Also write the results as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Profile one method's frame by ablation: time it whole and with each pass left out in
    /// turn (gbuffer, shadows, direct, technique, composite, tonemap), the configurations taking
    /// turns frame by frame; a pass's cost is the wall time its absence saves (what a CPU
    /// adapter's unreliable timestamps cannot tell). A moving scene stands at its first pose
    /// (every configuration renders the same frame).
    #[arg(long)]
    pub ablate: bool,
}

/// Median and 90th percentile (nearest rank) of a sample, in ms.
#[derive(Serialize, Clone, Copy, Debug)]
pub struct Stat {
    pub median_ms: f64,
    pub p90_ms: f64,
}

pub fn stat(values: &mut [f64]) -> Stat {
    values.sort_by(|a, b| a.total_cmp(b));
    let rank = |q: f64| {
        let i = ((q * values.len() as f64).ceil() as usize).clamp(1, values.len()) - 1;
        values[i]
    };
    let n = values.len();
    let median = if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    };
    Stat {
        median_ms: median,
        p90_ms: rank(0.9),
    }
}

#[derive(Serialize)]
struct MethodResult {
    /// Pass name → timing, in frame order.
    passes: BTreeMap<String, Stat>,
    pass_order: Vec<String>,
    /// Sum of the passes per frame.
    gpu_total: Option<Stat>,
    /// CPU wall time per frame: encode, submit and wait.
    wall: Stat,
}

#[derive(Serialize)]
struct Adapter {
    name: String,
    backend: String,
    device_type: String,
    timestamps: bool,
}

#[derive(Serialize)]
struct Settings {
    scene: String,
    triangles: usize,
    size: [u32; 2],
    env: String,
    frames: u32,
    warmup: u32,
    shadow_size: u32,
}

#[derive(Serialize)]
struct Report {
    adapter: Adapter,
    settings: Settings,
    methods: BTreeMap<String, MethodResult>,
    /// Methods in the order given.
    method_order: Vec<String>,
    /// Per method: median frame time (GPU total; wall on CPU adapters or without timestamps)
    /// relative to the first method, in percent (the paper's "overhead relative to SSAO" when
    /// SSAO is listed first).
    overhead_pct_vs_first: BTreeMap<String, f64>,
    /// Which timing the overheads use: "gpu" or "wall".
    overhead_from: String,
}

/// The report of a run: the adapter, the settings, each method's timings and its frame time
/// relative to the first method's.
fn report(
    args: &BenchArgs,
    ctx: &GpuContext,
    loaded: &crate::options::Loaded,
    settings: nearfield_render::RenderSettings,
    methods: &[String],
    results: BTreeMap<String, MethodResult>,
) -> Report {
    let info = ctx.adapter_info();
    // A CPU adapter (lavapipe) runs dispatches on worker threads and writes timestamps out of
    // step with them: its per-pass numbers (and their sum) are not trustworthy, its wall clock
    // is. Frame-time ratios then come from the wall clock.
    let cpu = info.device_type == nearfield_render::wgpu::DeviceType::Cpu;
    let frame_ms = |m: &MethodResult| match (cpu, m.gpu_total) {
        (false, Some(t)) => t.median_ms,
        _ => m.wall.median_ms,
    };
    let first = frame_ms(&results[&methods[0]]);
    let overhead = methods
        .iter()
        .map(|m| (m.clone(), 100.0 * (frame_ms(&results[m]) / first - 1.0)))
        .collect();
    Report {
        adapter: Adapter {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            timestamps: ctx.timestamps,
        },
        settings: Settings {
            scene: args.scene.scene.clone(),
            triangles: loaded.scene.triangle_count(),
            size: [settings.size.0, settings.size.1],
            env: loaded.env_source.to_string(),
            frames: args.frames,
            warmup: args.warmup,
            shadow_size: settings.shadows.size,
        },
        methods: results,
        method_order: methods.to_vec(),
        overhead_pct_vs_first: overhead,
        overhead_from: if cpu || !ctx.timestamps {
            "wall"
        } else {
            "gpu"
        }
        .into(),
    }
}

/// A method's renderer and its timings so far.
struct Timed {
    renderer: Renderer,
    per_pass: BTreeMap<String, Vec<f64>>,
    /// Passes in the order the frame runs them.
    order: Vec<String>,
    totals: Vec<f64>,
    walls: Vec<f64>,
}

impl Timed {
    /// Renders and times frame `index` (of the orbit and the scene's clock).
    fn frame(&mut self, scene: &nearfield_scene::Scene, index: u32, orbit: f32) {
        let t0 = Instant::now();
        bench_frame(&mut self.renderer, scene, index, orbit);
        self.renderer.wait();
        self.walls.push(t0.elapsed().as_secs_f64() * 1e3);
        let timings = self.renderer.timings();
        for &(pass, ms) in &timings {
            if !self.order.iter().any(|o| o == pass) {
                self.order.push(pass.to_string());
            }
            self.per_pass.entry(pass.to_string()).or_default().push(ms);
        }
        self.totals
            .push(nearfield_render::profiler::frame_total(&timings));
    }

    /// The statistics of the frames timed (the GPU total only with `timestamps`).
    fn result(mut self, timestamps: bool) -> MethodResult {
        let passes: BTreeMap<String, Stat> = self
            .per_pass
            .into_iter()
            .map(|(k, mut v)| (k, stat(&mut v)))
            .collect();
        MethodResult {
            gpu_total: timestamps.then(|| stat(&mut self.totals)),
            passes,
            pass_order: self.order,
            wall: stat(&mut self.walls),
        }
    }
}

/// Renders frame `index` of the benchmark: the camera turned by `orbit` (after the first) and a
/// moving scene posed at the frame's time on a looping clock at
/// [`nearfield_scene::animation::LOOP_FPS`].
fn bench_frame(r: &mut Renderer, scene: &nearfield_scene::Scene, index: u32, orbit: f32) {
    if r.moves() {
        r.set_time(
            scene
                .animation
                .looped(index, nearfield_scene::animation::LOOP_FPS),
        );
    }
    crate::options::orbit_frame(r, index, orbit);
}

pub fn run(args: BenchArgs) -> Result<()> {
    let methods = crate::options::methods_and_frames(args.methods.as_deref(), args.frames)?;
    crate::options::check_orbit(args.orbit)?;
    if args.ablate && methods.len() != 1 {
        return Err(crate::BadInput(format!(
            "--ablate times one method's frame; give one with --methods (got {})",
            methods.len()
        ))
        .into());
    }
    if let Some(p) = &args.json {
        crate::output::check_parent_dir(p)?;
    }
    let mut params = args.technique.params()?;
    let size = crate::options::parse_size(&args.scene.size)?;
    let settings = args.technique.settings(size)?;
    args.far.precheck()?;
    // The adapter first: a machine that cannot run the passes hears so before a bake.
    let ctx = GpuContext::new(args.scene.adapter.as_deref())?;
    let loaded = args.scene.load()?;
    let plan = args.far.plan(&loaded, None)?;
    crate::far::apply_auto_radius(&mut params, &plan);
    for m in &methods {
        nearfield_render::technique::check_spec(m, &params)?;
    }
    let volume = plan.volume(&args.scene, &loaded)?;
    if args.ablate {
        return ablate(
            &args,
            &ctx,
            &loaded,
            volume.as_ref(),
            &methods[0],
            &params,
            settings,
        );
    }
    let mut timed = Vec::with_capacity(methods.len());
    let progress = nearfield_scene::progress::Progress::new(
        "bench",
        (methods.len() as u64) * u64::from(args.warmup + args.frames),
        "frames",
        true,
    );
    // Every method's renderer is made and warmed first; then the timed frames go round the
    // methods in turn, so that a slow drift of the machine (thermal, other load) touches all of
    // them alike and their ratios stay fair.
    for method in &methods {
        progress.set_message(&format!("{method}, warm-up"));
        let mut r = Renderer::new(
            &ctx,
            &loaded.scene,
            &loaded.env,
            volume.as_ref(),
            loaded.camera,
            &nearfield_render::technique::Spec::resolve(method, &params)?,
            settings,
        )?;
        loaded.report_sun();
        for i in 0..args.warmup {
            bench_frame(&mut r, &loaded.scene, i, args.orbit);
            progress.inc(1);
        }
        r.wait();
        timed.push(Timed {
            renderer: r,
            per_pass: BTreeMap::new(),
            order: Vec::new(),
            totals: Vec::new(),
            walls: Vec::new(),
        });
    }
    progress.set_message("timed frames");
    for i in 0..args.frames {
        for t in &mut timed {
            progress.inc(1);
            t.frame(&loaded.scene, args.warmup + i, args.orbit);
        }
        if let Some(t) = timed.first() {
            t.renderer.check_device()?;
        }
    }
    progress.finish();
    let results: BTreeMap<String, MethodResult> = methods
        .iter()
        .zip(timed)
        .map(|(method, t)| (method.clone(), t.result(ctx.timestamps)))
        .collect();
    let report = report(&args, &ctx, &loaded, settings, &methods, results);
    print_table(&report);
    if let Some(p) = &args.json {
        let text = serde_json::to_string_pretty(&report)?;
        crate::output::save_atomically(p, |tmp| std::fs::write(tmp, &text).map_err(Into::into))?;
        eprintln!("nearfield: wrote {}", p.display());
    }
    Ok(())
}

/// One configuration of `--ablate`: the pass left out (none: the whole frame) and its frame time.
#[derive(Serialize)]
struct AblationRow {
    left_out: Option<String>,
    wall: Stat,
    /// Median wall time the absence of the pass saves against the whole frame (ms).
    saved_ms: f64,
}

/// `bench --ablate`: the whole frame and the frame without each pass, in turns.
fn ablate(
    args: &BenchArgs,
    ctx: &GpuContext,
    loaded: &crate::options::Loaded,
    volume: Option<&nearfield_scene::probes::ProbeVolume>,
    method: &str,
    params: &nearfield_render::TechniqueParams,
    settings: nearfield_render::RenderSettings,
) -> Result<()> {
    use nearfield_render::FramePass;
    let mut r = Renderer::new(
        ctx,
        &loaded.scene,
        &loaded.env,
        volume,
        loaded.camera,
        &nearfield_render::technique::Spec::resolve(method, params)?,
        settings,
    )?;
    let configs: Vec<Option<FramePass>> = std::iter::once(None)
        .chain(FramePass::ALL.into_iter().map(Some))
        .collect();
    let progress = nearfield_scene::progress::Progress::new(
        "bench --ablate",
        u64::from(args.warmup + args.frames) * configs.len() as u64,
        "frames",
        true,
    );
    let mut walls = vec![Vec::new(); configs.len()];
    for i in 0..args.warmup + args.frames {
        for (k, c) in configs.iter().enumerate() {
            r.leave_out(*c);
            let t0 = Instant::now();
            crate::options::orbit_frame(&mut r, i, args.orbit);
            r.wait();
            if i >= args.warmup {
                walls[k].push(t0.elapsed().as_secs_f64() * 1e3);
            }
            progress.inc(1);
        }
        r.check_device()?;
    }
    progress.finish();
    let stats: Vec<Stat> = walls.iter_mut().map(|w| stat(w)).collect();
    let whole = stats[0].median_ms;
    let rows: Vec<AblationRow> = configs
        .iter()
        .zip(&stats)
        .map(|(c, s)| AblationRow {
            left_out: c.map(|p| p.name().to_string()),
            wall: *s,
            saved_ms: whole - s.median_ms,
        })
        .collect();
    let info = ctx.adapter_info();
    println!(
        "adapter: {} ({:?})  scene: {}  size: {}  method: {method}  frames: {} per configuration after {} warm-up, in turns",
        info.name, info.backend, args.scene.scene, args.scene.size, args.frames, args.warmup
    );
    println!(
        "{:<18} {:>11} {:>11} {:>11} {:>8}",
        "left out", "median ms", "p90 ms", "saved ms", "share"
    );
    for row in &rows {
        println!(
            "{:<18} {:>11.2} {:>11.2} {:>11.2} {:>7.1}%",
            row.left_out.as_deref().unwrap_or("(whole frame)"),
            row.wall.median_ms,
            row.wall.p90_ms,
            row.saved_ms,
            100.0 * row.saved_ms / whole
        );
    }
    if let Some(p) = &args.json {
        let text = serde_json::to_string_pretty(&rows)?;
        crate::output::save_atomically(p, |tmp| std::fs::write(tmp, &text).map_err(Into::into))?;
        eprintln!("nearfield: wrote {}", p.display());
    }
    Ok(())
}

fn print_table(r: &Report) {
    println!(
        "adapter: {} ({}, {})  scene: {} ({} triangles)  size: {}x{}  frames: {} after {} warm-up",
        r.adapter.name,
        r.adapter.backend,
        r.adapter.device_type,
        r.settings.scene,
        r.settings.triangles,
        r.settings.size[0],
        r.settings.size[1],
        r.settings.frames,
        r.settings.warmup
    );
    println!(
        "{:<10} {:<12} {:>11} {:>11}",
        "method", "pass", "median ms", "p90 ms"
    );
    for name in &r.method_order {
        let m = &r.methods[name];
        for pass in &m.pass_order {
            let s = m.passes[pass];
            println!(
                "{:<10} {:<12} {:>11.3} {:>11.3}",
                name, pass, s.median_ms, s.p90_ms
            );
        }
        if let Some(t) = m.gpu_total {
            println!(
                "{:<10} {:<12} {:>11.3} {:>11.3}",
                name, "gpu total", t.median_ms, t.p90_ms
            );
        }
        println!(
            "{:<10} {:<12} {:>11.3} {:>11.3}",
            name, "wall", m.wall.median_ms, m.wall.p90_ms
        );
    }
    if r.adapter.device_type == "Cpu" {
        println!(
            "note: a CPU adapter's per-pass timestamps are not reliable; frame times below use the wall clock"
        );
    }
    if r.method_order.len() > 1 {
        for name in &r.method_order {
            println!(
                "{:<24} frame time {:+.1} % vs {} ({})",
                name, r.overhead_pct_vs_first[name], r.method_order[0], r.overhead_from
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_p90() {
        let mut v: Vec<f64> = (1..=10).map(|x| x as f64).collect();
        let s = stat(&mut v);
        assert_eq!(s.median_ms, 5.5);
        assert_eq!(s.p90_ms, 9.0);
        let mut v = vec![3.0, 1.0, 2.0];
        assert_eq!(stat(&mut v).median_ms, 2.0);
    }
}

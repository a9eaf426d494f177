//! `nearfield fit`: a technique's numeric settings fitted against the reference over training
//! scenes, with the error on held-out scenes before and after → FIT.json, a table and the
//! fitted spec for `--methods`.
//!
//! Every scene keeps one renderer and one reference (from the cache) for the whole search; an
//! evaluation writes the settings in place ([`Renderer::set_technique`]; only counts rebuild),
//! restarts the frame count so that equal settings draw equal noise, renders `--frames`
//! frames and measures the AOVs as `compare` does.

pub mod optimise;

use crate::BadInput;
use crate::measure::schema::{FitFile, FitScene, FitSide};
use crate::measure::{Metric, Target, Truth, mean};
use crate::options::{SceneOpts, TechniqueOpts};
use crate::reference::{ReferenceOpts, parse_aov};
use anyhow::{Context, Result};
use clap::Args;
use nearfield_render::{Aov, GpuContext, Renderer};
use optimise::{Dimension, Optimum};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args, Debug)]
pub struct FitArgs {
    /// Technique: a name, or NAME:key=value+… whose settings stay fixed while the others are
    /// fitted (the start is the spec's value of each fitted setting, else its default).
    pub method: String,
    /// Settings to fit, comma-separated: KEY searches its declared range, KEY=LO..HI a
    /// narrower one. Numeric settings only; `uniform`: every number the technique's
    /// declarations mark as a uniform (its settings table's role column).
    #[arg(long)]
    pub params: String,
    /// Training scenes, comma-separated: SCENE (a file or builtin:NAME, with its default
    /// camera), SCENE@CAMERA.json, SCENE:env=ENV, or SCENE@CAMERA.json:env=ENV.
    #[arg(long)]
    pub scenes: String,
    /// Held-out scenes (same form): measured before and after, never fitted. Default: every
    /// built-in scene not in training; `none` for none.
    #[arg(long)]
    pub holdout: Option<String>,
    /// AOV(s) measured: one name, or several joined by `+` (the error is their mean), e.g.
    /// ao+indirect-irradiance. As in compare; `lambertian` against the path tracer.
    #[arg(long, default_value = "ao")]
    pub aov: String,
    /// What is minimised, averaged over scenes and AOVs: rel (mean relative error Σ|e|/Σ|ref|),
    /// rmse, or flip (mean FLIP of the tonemapped images).
    #[arg(long, default_value = "rel")]
    pub metric: String,
    /// Image size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "96x54")]
    pub size: String,
    /// Frames rendered per evaluation before the AOVs are read (temporal techniques converge
    /// over frames; every evaluation starts from the first frame).
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Near-field radius R in metres (> 0) of both the technique and the reference.
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    pub radius: String,
    /// A fixed technique setting KEY=VALUE (repeatable), as in render.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Seed of the technique's noise and of the reference.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Evaluations at most (distinct settings rendered on every training scene), at least one
    /// more than the number of fitted settings.
    #[arg(long, default_value_t = 30)]
    pub budget: u32,
    /// The search has converged when the errors of its simplex's corners spread by less than
    /// this fraction of the start's error.
    #[arg(long, default_value_t = 1e-4)]
    pub tolerance: f64,
    /// Environment of every scene without its own `:env=` (as --env of render).
    #[arg(long)]
    pub env: Option<String>,
    /// The environment's sun: auto or off (as in render).
    #[arg(long, default_value = "auto")]
    pub sun: String,
    /// Use the GPU adapter whose name contains this text (case-insensitive).
    #[arg(long)]
    pub adapter: Option<String>,
    #[command(flatten)]
    pub reference: ReferenceOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    /// Output JSON.
    #[arg(long, default_value = "fit.json")]
    pub out: PathBuf,
}

/// A scene as written in `--scenes`: `SCENE[@CAMERA.json][:env=ENV]`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSpec {
    pub scene: String,
    pub camera: Option<String>,
    pub env: Option<String>,
}

impl SceneSpec {
    pub fn parse(s: &str) -> Result<Self> {
        let (rest, env) = match s.split_once(":env=") {
            Some((r, e)) if !e.is_empty() => (r, Some(e.to_string())),
            Some(_) => {
                return Err(BadInput(format!("scene {s}: ':env=' names no environment")).into());
            }
            None => (s, None),
        };
        let (scene, camera) = match rest.rsplit_once('@') {
            Some((sc, cam)) if !cam.is_empty() && !sc.is_empty() => {
                (sc.to_string(), Some(cam.to_string()))
            }
            Some(_) => {
                return Err(BadInput(format!("scene {s}: expected SCENE@CAMERA.json")).into());
            }
            None => (rest.to_string(), None),
        };
        if scene.is_empty() {
            return Err(BadInput(format!("scene '{s}': empty name")).into());
        }
        Ok(SceneSpec { scene, camera, env })
    }
}

/// How tables name a scene: `builtin:NAME`, a file's name (camera and environment named in
/// the JSON's `scenes`).
fn short_name(spec: &SceneSpec) -> String {
    if spec.scene.starts_with("builtin:") {
        return spec.scene.clone();
    }
    std::path::Path::new(&spec.scene)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| spec.scene.clone())
}

/// The non-empty items of a comma-separated list, trimmed.
fn list_items(s: &str) -> Vec<&str> {
    s.split(',')
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .collect()
}

/// A comma-separated scene list; `what` names the option in errors.
fn parse_scene_list(what: &str, s: &str) -> Result<Vec<(String, SceneSpec)>> {
    let names = list_items(s);
    if names.is_empty() {
        return Err(BadInput(format!("{what} '{s}': names no scene")).into());
    }
    let mut out = Vec::new();
    for n in names {
        if out.iter().any(|(m, _)| m == n) {
            return Err(BadInput(format!("{what}: {n} is named twice")).into());
        }
        out.push((n.to_string(), SceneSpec::parse(n)?));
    }
    Ok(out)
}

/// `--params k1,k2=lo..hi`: the fitted settings of technique `desc`, starting from their value
/// in the resolved parameters (else the declared default). `--params uniform`: every number the
/// declarations mark `uniform` that applies to the technique.
pub fn parse_params(
    text: &str,
    desc: &nearfield_render::technique::TechniqueDesc,
    resolved: &nearfield_render::TechniqueParams,
) -> Result<Vec<Dimension>> {
    use nearfield_render::settings::{Role, SettingKind};
    let uniforms: Vec<&str> = desc
        .settings
        .iter()
        .filter(|s| {
            s.role == Role::Uniform
                && s.applies(desc.name)
                && matches!(s.kind, SettingKind::Number { .. })
        })
        .map(|s| s.key)
        .collect();
    let items = if text.trim() == "uniform" {
        uniforms
    } else {
        list_items(text)
    };
    if items.is_empty() {
        return Err(BadInput(format!("--params '{text}': names no setting")).into());
    }
    let mut dims: Vec<Dimension> = Vec::new();
    for item in items {
        let (key, range) = match item.split_once('=') {
            None => (item, None),
            Some((k, r)) => {
                let bad = || BadInput(format!("--params {item}: expected KEY or KEY=LO..HI"));
                let (a, b) = r.split_once("..").ok_or_else(bad)?;
                let a: f64 = a.trim().parse().map_err(|_| bad())?;
                let b: f64 = b.trim().parse().map_err(|_| bad())?;
                (k.trim(), Some((a, b)))
            }
        };
        let setting = desc.settings.iter().find(|s| s.key == key).ok_or_else(|| {
            BadInput(format!(
                "--params: {} has no setting '{key}' (known: {})",
                desc.name,
                nearfield_render::settings::keys(desc.settings)
            ))
        })?;
        if dims.iter().any(|d| d.key == key) {
            return Err(BadInput(format!("--params: '{key}' is named twice")).into());
        }
        if !setting.applies(desc.name) {
            return Err(BadInput(format!(
                "--params: {key} does not change {} (it applies to {})",
                desc.name,
                setting.only.join(", ")
            ))
            .into());
        }
        let start_text = resolved
            .set
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .or_else(|| match key {
                "radius" => resolved.radius.map(|r| r.to_string()),
                "samples" | "steps" => resolved.samples.map(|s| s.to_string()),
                _ => None,
            })
            .unwrap_or_else(|| setting.default.to_string());
        let start: f64 = start_text.parse().unwrap_or(0.0);
        dims.push(
            Dimension::new(setting, range, start)
                .map_err(|e| BadInput(format!("--params: {e}")))?,
        );
    }
    Ok(dims)
}

/// The spec `base` with `values` of `dims` appended (after the base's own settings, so they
/// win): `ssdo:strength=6.8`.
pub fn spec_with(base: &str, dims: &[Dimension], values: &[f64]) -> String {
    let sets: Vec<String> = dims
        .iter()
        .zip(values)
        .map(|(d, &x)| format!("{}={}", d.key, d.text(x)))
        .collect();
    let sep = if base.contains(':') { '+' } else { ':' };
    format!("{base}{sep}{}", sets.join("+"))
}

fn json_number(d: &Dimension, x: f64) -> serde_json::Value {
    if d.integer {
        serde_json::Value::from(x as i64)
    } else {
        serde_json::Value::from(x)
    }
}

pub fn run(args: FitArgs) -> Result<()> {
    let t0 = Instant::now();
    // Everything that can be checked without loading, first.
    let metric = Metric::parse(&args.metric).ok_or_else(|| {
        BadInput(format!(
            "--metric {}: expected rel, rmse or flip",
            args.metric
        ))
    })?;
    let size = crate::options::parse_size(&args.size)?;
    let aov_names: Vec<&str> = args.aov.split('+').map(str::trim).collect();
    let mut aovs = Vec::new();
    for name in &aov_names {
        let ref_name = if *name == "lambertian" {
            "radiance"
        } else {
            name
        };
        let ref_aov = parse_aov(ref_name)?;
        let gpu = Aov::parse(name).expect("every reference AOV is a renderer AOV");
        if aovs.iter().any(|(a, _)| *a == gpu) {
            return Err(BadInput(format!("--aov {}: {name} is named twice", args.aov)).into());
        }
        aovs.push((gpu, ref_aov));
    }
    if args.frames == 0 || args.frames > 10_000 {
        return Err(BadInput(format!("--frames {}: must be in 1..=10000", args.frames)).into());
    }
    if !(args.tolerance.is_finite() && args.tolerance >= 0.0) {
        return Err(BadInput(format!("--tolerance {}: must be ≥ 0", args.tolerance)).into());
    }
    let (technique, params, radius) = TechniqueOpts::measured(&args.radius, &args.set, args.seed)?;
    let settings = technique.settings(size)?;
    let desc = nearfield_render::technique::find(&args.method)?;
    nearfield_render::technique::check_spec(&args.method, &params)?;
    let (_, resolved) = nearfield_render::technique::resolve_params(&args.method, &params)?;
    let dims = parse_params(&args.params, desc, &resolved)?;
    if (args.budget as usize) <= dims.len() {
        return Err(BadInput(format!(
            "--budget {}: at least {} evaluations (the start and one step per fitted setting)",
            args.budget,
            dims.len() + 1
        ))
        .into());
    }
    let start_values: Vec<f64> = dims.iter().map(|d| d.round(d.start)).collect();
    let start_spec = spec_with(&args.method, &dims, &start_values);
    nearfield_render::technique::check_spec(&start_spec, &params)?;
    let train = parse_scene_list("--scenes", &args.scenes)?;
    let holdout = match args.holdout.as_deref() {
        Some("none") => Vec::new(),
        Some(list) => parse_scene_list("--holdout", list)?,
        None => nearfield_scene::builtin::NAMES
            .iter()
            .map(|n| format!("builtin:{n}"))
            .filter(|n| !train.iter().any(|(_, s)| s.scene == *n))
            .map(|n| (n.clone(), SceneSpec::parse(&n).expect("a built-in name")))
            .collect(),
    };
    if let Some((n, _)) = holdout
        .iter()
        .find(|(n, _)| train.iter().any(|(m, _)| m == n))
    {
        return Err(BadInput(format!("--holdout: {n} is also a training scene")).into());
    }
    let ref_settings: Vec<_> = aovs
        .iter()
        .map(|(_, r)| args.reference.settings(*r, size, radius, args.seed))
        .collect::<Result<_>>()?;
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(BadInput(format!(
            "--out {}: the folder {} does not exist",
            args.out.display(),
            parent.display()
        ))
        .into());
    }

    args.far.precheck()?;
    let ctx = GpuContext::new(args.adapter.as_deref())?;
    let load = |list: &[(String, SceneSpec)]| -> Result<Vec<Target>> {
        let mut targets = Vec::new();
        for (name, spec) in list {
            let opts = SceneOpts {
                scene: spec.scene.clone(),
                size: args.size.clone(),
                env: spec.env.clone().or_else(|| args.env.clone()),
                env_intensity: 1.0,
                env_rotation: 0.0,
                camera: spec.camera.clone(),
                eye: None,
                target: None,
                fov: None,
                sun: args.sun.clone(),
                adapter: args.adapter.clone(),
                dynamic: Vec::new(),
                add: Vec::new(),
            };
            let loaded = opts.load().with_context(|| format!("scene {name}"))?;
            let mut truths = Vec::new();
            for ((gpu, _), rs) in aovs.iter().zip(&ref_settings) {
                let (img, _) = crate::reference::compute(&opts, &args.reference, &loaded, rs)?;
                truths.push(Truth::new(*gpu, img.value, img.depth, size));
            }
            // A relative error of nothing is undefined: such a scene says nothing of the fit.
            if metric == Metric::Relative
                && let Some(t) = truths.iter().find(|t| t.is_zero())
            {
                eprintln!(
                    "nearfield: {name} left out: its {} is zero everywhere, its relative error is undefined",
                    t.aov.name()
                );
                continue;
            }
            let volume = args.far.resolve(&opts, &loaded, Some(args.aov.as_str()))?;
            let renderer = Renderer::new(
                &ctx,
                &loaded.scene,
                &loaded.env,
                volume.as_ref(),
                loaded.camera,
                &nearfield_render::technique::Spec::resolve(&start_spec, &params)?,
                settings,
            )?;
            targets.push(Target {
                name: name.clone(),
                renderer,
                truths,
            });
        }
        Ok(targets)
    };
    let mut train_targets = load(&train)?;
    if train_targets.is_empty() {
        return Err(BadInput("--scenes: no training scene is left to fit on".into()).into());
    }
    let mut holdout_targets = load(&holdout)?;
    // What is reported is what was measured.
    let train: Vec<(String, SceneSpec)> = train
        .into_iter()
        .filter(|(n, _)| train_targets.iter().any(|t| &t.name == n))
        .collect();
    let holdout: Vec<(String, SceneSpec)> = holdout
        .into_iter()
        .filter(|(n, _)| holdout_targets.iter().any(|t| &t.name == n))
        .collect();
    let setup = t0.elapsed().as_secs_f64();

    // The search, over the training scenes; every evaluation's per-scene errors are kept.
    let progress = nearfield_scene::progress::Progress::new(
        &format!("fit {}", args.method),
        u64::from(args.budget),
        "evaluations",
        true,
    );
    let mut per_scene: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    let mut best = f64::INFINITY;
    let tolerance = args.tolerance;
    let optimum: Optimum = {
        let mut objective = |values: &[f64]| -> Result<f64> {
            let spec = spec_with(&args.method, &dims, values);
            let errors = train_targets
                .iter_mut()
                .map(|t| t.evaluate(&spec, &params, args.frames, metric))
                .collect::<Result<Vec<f64>>>()?;
            let m = mean(&errors);
            best = best.min(m);
            per_scene.push((values.to_vec(), errors));
            progress.inc(1);
            progress.set_message(&format!("best {best:.4}"));
            Ok(m)
        };
        // The tolerance is relative to the start's error: measure it first (it is the search's
        // first evaluation too, from the same renderers, so it is not rendered twice).
        let start_error = objective(&start_values)?;
        optimise::minimise(
            &dims,
            args.budget as usize,
            tolerance * start_error.abs(),
            |values: &[f64]| {
                if values == start_values.as_slice() {
                    Ok(start_error)
                } else {
                    objective(values)
                }
            },
        )?
    };
    progress.finish();
    let errors_at = |values: &[f64]| -> Vec<f64> {
        per_scene
            .iter()
            .find(|(v, _)| v == values)
            .map(|(_, e)| e.clone())
            .expect("every evaluated point was recorded")
    };
    let train_before = errors_at(&start_values);
    let train_after = errors_at(&optimum.best.values);
    let best_spec = spec_with(&args.method, &dims, &optimum.best.values);
    let mut holdout_before = Vec::new();
    let mut holdout_after = Vec::new();
    for t in &mut holdout_targets {
        holdout_before.push(t.evaluate(&start_spec, &params, args.frames, metric)?);
        holdout_after.push(t.evaluate(&best_spec, &params, args.frames, metric)?);
    }
    let side = |names: &[(String, SceneSpec)], before: &[f64], after: &[f64]| FitSide {
        before: mean(before),
        after: mean(after),
        per_scene: names
            .iter()
            .zip(before.iter().zip(after))
            .map(|((_, spec), (&b, &a))| {
                (
                    short_name(spec),
                    FitScene {
                        before: b,
                        after: a,
                    },
                )
            })
            .collect(),
    };
    let seconds = t0.elapsed().as_secs_f64();
    let file = FitFile {
        method: args.method.clone(),
        params: dims
            .iter()
            .zip(&optimum.best.values)
            .map(|(d, &x)| (d.key.clone(), json_number(d, x)))
            .collect(),
        start: dims
            .iter()
            .zip(&start_values)
            .map(|(d, &x)| (d.key.clone(), json_number(d, x)))
            .collect(),
        spec: best_spec.clone(),
        metric: metric.name().into(),
        aov: args.aov.clone(),
        size: [size.0, size.1],
        frames: args.frames,
        radius,
        spp: args.reference.spp,
        train: side(&train, &train_before, &train_after),
        holdout: side(&holdout, &holdout_before, &holdout_after),
        evaluations: optimum.history.len(),
        history: optimum
            .history
            .iter()
            .map(|e| (e.values.clone(), e.cost))
            .collect(),
        stopped: optimum.stopped.into(),
        scenes: train
            .iter()
            .chain(&holdout)
            .map(|(n, spec)| (short_name(spec), n.clone()))
            .collect(),
        seconds,
        command: std::env::args()
            .skip(1)
            .map(|a| if a.contains(' ') { format!("'{a}'") } else { a })
            .collect::<Vec<_>>()
            .join(" "),
        adapter: nearfield_render::context::describe(&ctx.adapter_info()),
    };
    let json = serde_json::to_string_pretty(&file).expect("plain data");
    crate::output::save_atomically(&args.out, |tmp| {
        std::fs::write(tmp, json.as_bytes()).map_err(Into::into)
    })?;

    println!("{:<8} {:<28} {:>10} {:>10}", "", "scene", "before", "after");
    for (what, names, before, after) in [
        ("train", &train, &train_before, &train_after),
        ("holdout", &holdout, &holdout_before, &holdout_after),
    ] {
        for ((_, spec), (b, a)) in names.iter().zip(before.iter().zip(after.iter())) {
            let n = short_name(spec);
            println!("{what:<8} {n:<28} {b:>10.4} {a:>10.4}");
        }
        if !names.is_empty() {
            println!(
                "{what:<8} {:<28} {:>10.4} {:>10.4}",
                "mean",
                mean(before),
                mean(after)
            );
        }
    }
    println!(
        "{} {} of {} over {} evaluation(s) ({}), {:.1} s ({:.1} s setup)",
        metric.name(),
        args.aov,
        args.method,
        optimum.history.len(),
        optimum.stopped,
        seconds,
        setup
    );
    let (lo, hi) = optimum
        .history
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
            (lo.min(e.cost), hi.max(e.cost))
        });
    if optimum.history.len() > 1 && hi - lo <= 1e-9 * hi.abs().max(1e-12) {
        eprintln!(
            "nearfield: warning: the error was the same at all {} settings tried: {} of {} does not depend on {} here",
            optimum.history.len(),
            args.aov,
            args.method,
            dims.iter()
                .map(|d| d.key.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    println!("fitted: {best_spec}");
    eprintln!("nearfield: wrote {}", args.out.display());
    Ok(())
}

//! `nearfield fit`: a technique's numeric settings fitted against the reference over training
//! scenes, with the error on held-out scenes before and after → FIT.json, a table and the
//! fitted spec for `--methods`.
//!
//! Every scene keeps one renderer and one reference (from the cache) for the whole search; an
//! evaluation writes the settings in place ([`Renderer::set_technique`]; only counts rebuild),
//! restarts the frame count so that equal settings draw equal noise, renders `--frames`
//! frames and measures the AOVs as `compare` does.

pub mod optimise;
mod run;

use crate::BadInput;
use crate::measure::Metric;
use crate::options::TechniqueOpts;
use crate::reference::ReferenceOpts;
use anyhow::Result;
use clap::Args;
use nearfield_render::GpuContext;
use nearfield_render::technique::Spec;
use optimise::Dimension;
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
    let aovs = run::parse_aovs(&args.aov)?;
    run::check_counts(&args)?;
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
    let holdout = run::holdout(&args, &train)?;
    let ref_settings: Vec<_> = aovs
        .iter()
        .map(|(_, r)| args.reference.settings(*r, size, radius, args.seed))
        .collect::<Result<_>>()?;
    run::check_out(&args.out)?;
    args.far.precheck()?;
    let ctx = GpuContext::new(args.adapter.as_deref())?;
    let scenes = run::Scenes {
        args: &args,
        ctx: &ctx,
        aovs: &aovs,
        ref_settings: &ref_settings,
        metric,
        technique: Spec::resolve(&start_spec, &params)?,
        settings,
    };
    let (train, mut train_targets) = scenes.load(train)?;
    if train_targets.is_empty() {
        return Err(BadInput("--scenes: no training scene is left to fit on".into()).into());
    }
    let (holdout, mut holdout_targets) = scenes.load(holdout)?;
    let setup = t0.elapsed().as_secs_f64();
    let fit = run::Fit {
        args: &args,
        dims: &dims,
        params: &params,
        metric,
    };
    let (optimum, per_scene) = fit.search(&mut train_targets, &start_values)?;
    let errors_at = |values: &[f64]| -> Vec<f64> {
        per_scene
            .iter()
            .find(|(v, _)| v == values)
            .map(|(_, e)| e.clone())
            .expect("every evaluated point was recorded")
    };
    let train_errors = [errors_at(&start_values), errors_at(&optimum.best.values)];
    let best_spec = spec_with(&args.method, &dims, &optimum.best.values);
    let mut holdout_errors = [Vec::new(), Vec::new()];
    for t in &mut holdout_targets {
        holdout_errors[0].push(t.evaluate(&start_spec, &params, args.frames, metric)?);
        holdout_errors[1].push(t.evaluate(&best_spec, &params, args.frames, metric)?);
    }
    let seconds = t0.elapsed().as_secs_f64();
    let file = fit.file(
        &optimum,
        &start_values,
        [(&train, &train_errors), (&holdout, &holdout_errors)],
        (size, radius, seconds),
        nearfield_render::context::describe(&ctx.adapter_info()),
    );
    let json = serde_json::to_string_pretty(&file).expect("plain data");
    crate::output::save_atomically(&args.out, |tmp| {
        std::fs::write(tmp, json.as_bytes()).map_err(Into::into)
    })?;
    fit.print(
        &optimum,
        [(&train, &train_errors), (&holdout, &holdout_errors)],
        (seconds, setup),
    );
    println!("fitted: {best_spec}");
    eprintln!("nearfield: wrote {}", args.out.display());
    Ok(())
}

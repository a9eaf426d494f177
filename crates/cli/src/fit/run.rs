//! The stages of `nearfield fit`: the checks of its arguments, the scenes it fits on with their
//! truths, the search, and what it writes and prints.

use super::optimise::{self, Dimension, Optimum};
use super::{FitArgs, SceneSpec, json_number, parse_scene_list, short_name, spec_with};
use crate::BadInput;
use crate::measure::schema::{FitFile, FitScene, FitSide};
use crate::measure::{Metric, Target, Truth, mean};
use crate::options::SceneOpts;
use crate::reference::parse_aov;
use anyhow::{Context, Result};
use nearfield_reference::ReferenceAov;
use nearfield_render::technique::Spec;
use nearfield_render::{Aov, GpuContext, RenderSettings, Renderer, TechniqueParams};

/// A named scene list.
type SceneList = Vec<(String, SceneSpec)>;

/// `--aov A+B`: each as the renderer and the reference name it (`lambertian` is the
/// reference's radiance), none twice.
pub(super) fn parse_aovs(list: &str) -> Result<Vec<(Aov, ReferenceAov)>> {
    let mut aovs = Vec::new();
    for name in list.split('+').map(str::trim) {
        let ref_name = if name == "lambertian" {
            "radiance"
        } else {
            name
        };
        let ref_aov = parse_aov(ref_name)?;
        let gpu = Aov::parse(name).expect("every reference AOV is a renderer AOV");
        if aovs.iter().any(|(a, _)| *a == gpu) {
            return Err(BadInput(format!("--aov {list}: {name} is named twice")).into());
        }
        aovs.push((gpu, ref_aov));
    }
    Ok(aovs)
}

/// `--frames` and `--tolerance`.
pub(super) fn check_counts(args: &FitArgs) -> Result<()> {
    if args.frames == 0 || args.frames > 10_000 {
        return Err(BadInput(format!("--frames {}: must be in 1..=10000", args.frames)).into());
    }
    if !(args.tolerance.is_finite() && args.tolerance >= 0.0) {
        return Err(BadInput(format!("--tolerance {}: must be ≥ 0", args.tolerance)).into());
    }
    Ok(())
}

/// `--out`: its folder must exist.
pub(super) fn check_out(out: &std::path::Path) -> Result<()> {
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(BadInput(format!(
            "--out {}: the folder {} does not exist",
            out.display(),
            parent.display()
        ))
        .into());
    }
    Ok(())
}

/// `--holdout`: a list, `none`, or by default every built-in scene not trained on.
pub(super) fn holdout(args: &FitArgs, train: &SceneList) -> Result<SceneList> {
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
    Ok(holdout)
}

/// What a scene of the fit is loaded with.
pub(super) struct Scenes<'a> {
    pub args: &'a FitArgs,
    pub ctx: &'a GpuContext,
    pub aovs: &'a [(Aov, ReferenceAov)],
    pub ref_settings: &'a [nearfield_reference::ReferenceSettings],
    pub metric: Metric,
    /// The technique at the search's start.
    pub technique: Spec,
    pub settings: RenderSettings,
}

impl Scenes<'_> {
    /// Loads each scene with its truths and a renderer; the list of those kept (a scene whose
    /// truth is zero everywhere says nothing of a relative error) and their targets.
    pub fn load(&self, list: SceneList) -> Result<(SceneList, Vec<Target>)> {
        let mut kept = Vec::new();
        let mut targets = Vec::new();
        for (name, spec) in list {
            if let Some(target) = self.target(&name, &spec)? {
                targets.push(target);
                kept.push((name, spec));
            }
        }
        Ok((kept, targets))
    }

    fn target(&self, name: &str, spec: &SceneSpec) -> Result<Option<Target>> {
        let args = self.args;
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
        let size = self.settings.size;
        let mut truths = Vec::new();
        for ((gpu, _), rs) in self.aovs.iter().zip(self.ref_settings) {
            let (img, _) = crate::reference::compute(&opts, &args.reference, &loaded, rs)?;
            truths.push(Truth::new(*gpu, img.value, img.depth, size));
        }
        // A relative error of nothing is undefined: such a scene says nothing of the fit.
        if self.metric == Metric::Relative
            && let Some(t) = truths.iter().find(|t| t.is_zero())
        {
            eprintln!(
                "nearfield: {name} left out: its {} is zero everywhere, its relative error is undefined",
                t.aov.name()
            );
            return Ok(None);
        }
        let volume = args.far.resolve(&opts, &loaded, Some(args.aov.as_str()))?;
        let renderer = Renderer::new(
            self.ctx,
            &loaded.scene,
            &loaded.env,
            volume.as_ref(),
            loaded.camera,
            &self.technique,
            self.settings,
        )?;
        Ok(Some(Target {
            name: name.to_string(),
            renderer,
            truths,
        }))
    }
}

/// The fit: what it searches and how it measures.
pub(super) struct Fit<'a> {
    pub args: &'a FitArgs,
    pub dims: &'a [Dimension],
    pub params: &'a TechniqueParams,
    pub metric: Metric,
}

/// Scene lists with their errors before and after the fit.
type Sides<'a> = [(&'a SceneList, &'a [Vec<f64>; 2]); 2];

impl Fit<'_> {
    /// The search over the training scenes, from `start`; every evaluation's per-scene errors.
    #[allow(clippy::type_complexity)]
    pub fn search(
        &self,
        targets: &mut [Target],
        start: &[f64],
    ) -> Result<(Optimum, Vec<(Vec<f64>, Vec<f64>)>)> {
        let args = self.args;
        let progress = nearfield_scene::progress::Progress::new(
            &format!("fit {}", args.method),
            u64::from(args.budget),
            "evaluations",
            true,
        );
        let mut per_scene: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        let mut best = f64::INFINITY;
        let optimum = {
            let mut objective = |values: &[f64]| -> Result<f64> {
                let spec = spec_with(&args.method, self.dims, values);
                let errors = targets
                    .iter_mut()
                    .map(|t| t.evaluate(&spec, self.params, args.frames, self.metric))
                    .collect::<Result<Vec<f64>>>()?;
                let m = mean(&errors);
                best = best.min(m);
                per_scene.push((values.to_vec(), errors));
                progress.inc(1);
                progress.set_message(&format!("best {best:.4}"));
                Ok(m)
            };
            // The tolerance is relative to the start's error: measure it first (it is the
            // search's first evaluation too, from the same renderers, so it is not rendered
            // twice).
            let start_error = objective(start)?;
            optimise::minimise(
                self.dims,
                args.budget as usize,
                args.tolerance * start_error.abs(),
                |values: &[f64]| {
                    if values == start {
                        Ok(start_error)
                    } else {
                        objective(values)
                    }
                },
            )?
        };
        progress.finish();
        Ok((optimum, per_scene))
    }

    /// The fit's file: the fitted and start values, and the errors per scene.
    pub fn file(
        &self,
        optimum: &Optimum,
        start: &[f64],
        [train, holdout]: Sides,
        (size, radius, seconds): ((u32, u32), f32, f64),
        adapter: String,
    ) -> FitFile {
        let args = self.args;
        let values = |values: &[f64]| {
            self.dims
                .iter()
                .zip(values)
                .map(|(d, &x)| (d.key.clone(), json_number(d, x)))
                .collect()
        };
        let side = |(names, [before, after]): (&SceneList, &[Vec<f64>; 2])| FitSide {
            before: mean(before),
            after: mean(after),
            per_scene: names
                .iter()
                .zip(before.iter().zip(after))
                .map(|((_, spec), (&before, &after))| {
                    (short_name(spec), FitScene { before, after })
                })
                .collect(),
        };
        FitFile {
            method: args.method.clone(),
            params: values(&optimum.best.values),
            start: values(start),
            spec: spec_with(&args.method, self.dims, &optimum.best.values),
            metric: self.metric.name().into(),
            aov: args.aov.clone(),
            size: [size.0, size.1],
            frames: args.frames,
            radius,
            spp: args.reference.spp,
            train: side(train),
            holdout: side(holdout),
            evaluations: optimum.history.len(),
            history: optimum
                .history
                .iter()
                .map(|e| (e.values.clone(), e.cost))
                .collect(),
            stopped: optimum.stopped.into(),
            scenes: train
                .0
                .iter()
                .chain(holdout.0)
                .map(|(n, spec)| (short_name(spec), n.clone()))
                .collect(),
            seconds,
            command: std::env::args()
                .skip(1)
                .map(|a| if a.contains(' ') { format!("'{a}'") } else { a })
                .collect::<Vec<_>>()
                .join(" "),
            adapter,
        }
    }

    /// The table of errors before and after, the search's length, and a warning where the
    /// error did not depend on the settings fitted.
    pub fn print(&self, optimum: &Optimum, sides: Sides, (seconds, setup): (f64, f64)) {
        let args = self.args;
        println!("{:<8} {:<28} {:>10} {:>10}", "", "scene", "before", "after");
        for (what, (names, [before, after])) in ["train", "holdout"].into_iter().zip(sides) {
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
            self.metric.name(),
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
                self.dims
                    .iter()
                    .map(|d| d.key.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
}

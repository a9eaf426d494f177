//! What `compare` measures against, made once before any technique runs: the scene and the
//! camera's motion, the radius every method shares, the far field, the reference (and a path's
//! references), the footprint's truth.

use super::{CompareArgs, common_radius, file_name, frames, judge};
use anyhow::Result;
use nearfield_reference::{ReferenceAov, ReferenceImage};
use nearfield_render::{GpuContext, TechniqueParams};
use std::path::PathBuf;

/// What the comparison runs against: the scene (its camera the last frame's), the motion, the
/// radius, the far field, the reference and a path's references, the footprint's truth.
pub(super) struct Truths {
    pub loaded: crate::options::Loaded,
    pub run: frames::Run,
    pub radius: f32,
    pub ref_settings: nearfield_reference::ReferenceSettings,
    pub ctx: GpuContext,
    pub volume: Option<nearfield_scene::probes::ProbeVolume>,
    pub footprint: Option<(crate::footprint::Truth, crate::options::Loaded)>,
    pub reference: ReferenceImage,
    pub ref_info: nearfield_eval::report::ReferenceInfo,
    pub along: frames::Along,
}

impl Truths {
    /// Loads the scene, settles the radius (checking every method's settings against it), makes
    /// the GPU context, bakes or reads the far field and traces (or reads) the references.
    pub(super) fn new(
        args: &CompareArgs,
        (path_file, reference_file): (
            Option<nearfield_scene::CameraPath>,
            Option<(ReferenceImage, PathBuf)>,
        ),
        (methods, params): (&[String], &mut TechniqueParams),
        (ref_aov, size): (ReferenceAov, (u32, u32)),
    ) -> Result<Self> {
        let mut loaded = args.scene.load()?;
        let motion = args
            .motion
            .motion(path_file, &mut loaded, (args.orbit, true))?;
        let run = frames::Run::new(motion, args.frames, loaded.camera, &loaded.scene);
        // The reference sees what the last frame sees.
        loaded.camera = run.camera(run.frames - 1);
        loaded.scene.pose(run.time(run.frames - 1));
        if args.footprint {
            crate::footprint::check(&args.scene, &loaded)?;
        }
        let plan = args.far.plan(&loaded, Some(args.aov.as_str()))?;
        let radius = settle_radius(methods, params, &plan)?;
        let ref_settings = args
            .reference
            .settings(ref_aov, size, radius, args.technique.seed)?;
        let ctx = GpuContext::new(args.scene.adapter.as_deref())?;
        let volume = plan.volume(&args.scene, &loaded)?;
        // With --footprint: the truth's footprint, and the scene without its dynamic objects.
        let footprint = args
            .footprint
            .then(|| footprint_truth(args, &loaded, size, radius))
            .transpose()?;
        let (reference, ref_info) = reference_of(args, &loaded, &ref_settings, reference_file)?;
        let along = frames::path_truth(args, &mut loaded, &run, &ref_settings)?;
        Ok(Truths {
            loaded,
            run,
            radius,
            ref_settings,
            ctx,
            volume,
            footprint,
            reference,
            ref_info,
            along,
        })
    }
}

/// One radius for both sides and one seed: `--radius`, or auto (the volume's spacing; under the
/// sky the techniques' own, which must then agree), set in `params`. Every technique's settings
/// are checked against it before anything is baked or traced.
fn settle_radius(
    methods: &[String],
    params: &mut TechniqueParams,
    plan: &crate::far::FarPlan,
) -> Result<f32> {
    crate::far::apply_auto_radius(params, plan);
    let radius = common_radius(methods, params)?;
    params.radius = Some(radius);
    for m in methods {
        nearfield_render::technique::check_spec(m, params)?;
    }
    Ok(radius)
}

/// The truth's footprint of the dynamic objects, and the scene without them.
fn footprint_truth(
    args: &CompareArgs,
    loaded: &crate::options::Loaded,
    size: (u32, u32),
    radius: f32,
) -> Result<(crate::footprint::Truth, crate::options::Loaded)> {
    let truth = crate::footprint::truth(
        &args.scene,
        &args.reference,
        loaded,
        size,
        radius,
        args.technique.seed,
    )?;
    Ok((truth, crate::footprint::without_object(loaded)))
}

/// The reference: read from `--reference-file`, or traced (from the cache where it is there).
fn reference_of(
    args: &CompareArgs,
    loaded: &crate::options::Loaded,
    settings: &nearfield_reference::ReferenceSettings,
    file: Option<(ReferenceImage, PathBuf)>,
) -> Result<(ReferenceImage, nearfield_eval::report::ReferenceInfo)> {
    Ok(match file {
        Some((img, p)) => (img, judge::file_info(&file_name(&p))),
        None => {
            let (img, cached) =
                crate::reference::compute(&args.scene, &args.reference, loaded, settings)?;
            let path = cached
                .map(|p| format!("reference cache entry {}", file_name(&p)))
                .unwrap_or_else(|| "computed, not cached".into());
            (img, judge::traced_info(path, settings))
        }
    })
}

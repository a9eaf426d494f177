//! `nearfield render`: one image or AOV.

use crate::BadInput;
use crate::options::{SceneOpts, TechniqueOpts};
use crate::output::{check_output, save_atomically, write_exr};
use anyhow::Result;
use clap::Args;
use nearfield_render::{Aov, GpuContext, Renderer};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub technique: TechniqueOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    /// Near-field technique (every one is listed in the book's Techniques; `none` = no occlusion).
    #[arg(long, default_value = "none")]
    pub method: String,
    /// Frames to render before output (temporal techniques converge over frames; ≥ 1).
    /// Default: 1, or a camera path's frames.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Degrees the camera turns about its target (around its up axis) before every frame after
    /// the first.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub orbit: f32,
    #[command(flatten)]
    pub motion: crate::options::MotionOpts,
    /// What to write: final (PNG) or a float AOV (EXR): radiance, albedo, normal, depth, ao,
    /// env-irradiance, light-irradiance, indirect-irradiance, diffuse, lambertian, motion,
    /// specular, direct-radiance, or one of the technique's own images (e.g. hbil's
    /// reprojected, radiance-source, bent-cone, near-history, feedback; all four channels).
    #[arg(long, default_value = "final")]
    pub aov: String,
    /// Output file: .png for `final`, .exr for the others. Default: final.png or AOV.exr.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn run(args: RenderArgs) -> Result<()> {
    // An unknown name may still be one of the technique's own images, checked once it exists.
    let aov = Aov::parse(&args.aov);
    nearfield_render::technique::find(&args.method)?;
    if let Some(n) = args.frames
        && (n == 0 || n > 100_000)
    {
        return Err(BadInput(format!("--frames {n}: must be in 1..=100000")).into());
    }
    let path_file = args.motion.check(args.orbit)?;
    let output = args.output.clone().unwrap_or_else(|| {
        PathBuf::from(if aov == Some(Aov::Final) {
            "final.png".to_string()
        } else {
            format!("{}.exr", args.aov)
        })
    });
    check_output(aov.unwrap_or(Aov::Radiance), &output)?;
    let mut params = args.technique.params()?;
    let size = crate::options::parse_size(&args.scene.size)?;
    let settings = args.technique.settings(size)?;
    args.far.precheck()?;
    let mut loaded = args.scene.load()?;
    let motion = args
        .motion
        .motion(path_file, &mut loaded, (args.orbit, false))?;
    let frames = args.frames.unwrap_or(match &motion {
        crate::options::Motion::Path(p) => p.frames(),
        crate::options::Motion::Orbit { .. } => 1,
    });
    let far_aov = (aov != Some(Aov::Final)).then_some(args.aov.as_str());
    let plan = args.far.plan(&loaded, far_aov)?;
    crate::far::apply_auto_radius(&mut params, &plan);
    let technique = nearfield_render::technique::Spec::resolve(&args.method, &params)?;
    let ctx = GpuContext::new(args.scene.adapter.as_deref())?;
    let new = |volume: Option<&nearfield_scene::probes::ProbeVolume>| {
        Renderer::new(
            &ctx,
            &loaded.scene,
            &loaded.env,
            volume,
            loaded.camera,
            &technique,
            settings,
        )
    };
    let mut renderer = if aov.is_some() {
        new(plan.volume(&args.scene, &loaded)?.as_ref())?
    } else {
        // A technique's own images are known once it is built: a name that is none of them
        // answers before the far field (a bake takes seconds), which then comes in as a change.
        let mut renderer = new(None)?;
        if !renderer.extra_names().contains(&args.aov.as_str()) {
            let mut known = Aov::names();
            known.extend(renderer.extra_names());
            return Err(BadInput(format!(
                "--aov {}: unknown AOV for {} (known: {})",
                args.aov,
                args.method,
                known.join(", ")
            ))
            .into());
        }
        if let Some(volume) = plan.volume(&args.scene, &loaded)? {
            renderer.set_far_field(Some(&volume))?;
        }
        renderer
    };
    loaded.report_sun();
    let progress = nearfield_scene::progress::Progress::new(
        &format!("render {}", args.method),
        u64::from(frames),
        "frames",
        frames > 1,
    );
    for i in 0..frames {
        motion.frame(&mut renderer, i);
        // Progress counts finished frames, not queued ones.
        if i % 8 == 7 {
            renderer.wait();
        }
        progress.inc(1);
    }
    progress.finish();
    let Some(aov) = aov else {
        let img = renderer
            .read_extra(&args.aov)
            .expect("the name was checked above");
        renderer.check_device()?;
        write_exr(&img, &output)?;
        eprintln!(
            "nearfield: wrote {} ({} {})",
            output.display(),
            args.method,
            args.aov
        );
        return Ok(());
    };
    if aov == Aov::Final {
        let img = renderer.read_final();
        renderer.check_device()?;
        save_atomically(&output, |tmp| {
            img.save_with_format(tmp, image::ImageFormat::Png)
                .map_err(anyhow::Error::from)
        })?;
    } else {
        let img = renderer.read_aov(aov);
        renderer.check_device()?;
        write_exr(&img, &output)?;
    }
    eprintln!(
        "nearfield: wrote {} ({}, {}×{}, {} triangles, {})",
        output.display(),
        args.method,
        size.0,
        size.1,
        loaded.scene.triangle_count(),
        nearfield_render::context::describe(&ctx.adapter_info())
    );
    Ok(())
}

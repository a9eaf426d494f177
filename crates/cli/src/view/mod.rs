//! `nearfield view`: the interactive viewer (winit + egui) on the same renderer library as the
//! other commands. Everything it can change goes through [`session::Session::apply`], which the
//! panel, dropped files, the keyboard and `--script` share.

mod camera_control;
mod panel;
pub mod script;
pub mod session;
#[cfg(test)]
mod settings_reach;
mod technique_state;
mod window;

use crate::BadInput;
use crate::options::{SceneOpts, TechniqueOpts};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub technique: TechniqueOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    /// Technique of the view (A side); `name` or `name:key=value+…`.
    #[arg(long, default_value = "none")]
    pub method: String,
    /// Open an A/B split view with this technique on the right (B side).
    #[arg(long, value_name = "METHOD")]
    pub split_with: Option<String>,
    /// Image shown: final, any AOV of `render --aov`, or one of the technique's own images.
    #[arg(long, default_value = "final")]
    pub aov: String,
    /// Render this many frames, then exit (with --screenshot: save the view first; 1..=100000).
    #[arg(long)]
    pub frames: Option<u32>,
    /// PNG to save the 3D view to (without the interface) after --frames.
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,
    /// Run a script of viewer commands, one per frame (see the book's viewer page).
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Present without waiting for vertical sync.
    #[arg(long)]
    pub no_vsync: bool,
}

pub fn run(args: ViewArgs) -> Result<()> {
    // Everything the user typed is checked before a window opens.
    if let Some(n) = args.frames
        && !(1..=100_000).contains(&n)
    {
        return Err(BadInput(format!("--frames {n}: must be in 1..=100000")).into());
    }
    if let Some(path) = &args.screenshot {
        if args.frames.is_none() {
            return Err(BadInput("--screenshot needs --frames N".into()).into());
        }
        crate::output::check_output(nearfield_render::Aov::Final, path)?;
    }
    let script = match &args.script {
        Some(path) => {
            let size = nearfield_scene::limits::check_regular_file(path)
                .map_err(|e| BadInput(format!("--script: {e}")))?;
            if size > 1 << 20 {
                return Err(
                    BadInput(format!("--script {}: larger than 1 MiB", path.display())).into(),
                );
            }
            let text = std::fs::read_to_string(path)
                .map_err(|e| BadInput(format!("--script {}: {e}", path.display())))?;
            script::parse(&text)
                .map_err(|e| BadInput(format!("--script {}: {e}", path.display())))?
        }
        None => Vec::new(),
    };
    let mut params = args.technique.params()?;
    // Both techniques are checked before anything loads; they are made again below with the
    // far field's radius.
    technique_state::TechniqueState::from_command_line(&args.method, &params)
        .map_err(|e| BadInput(format!("--method {}: {e}", args.method)))?;
    if let Some(m) = args.split_with.as_deref() {
        technique_state::TechniqueState::from_command_line(m, &Default::default())
            .map_err(|e| BadInput(format!("--split-with {m}: {e}")))?;
    }
    let size = crate::options::parse_size(&args.scene.size)?;
    let settings = args.technique.settings(size)?;
    args.far.precheck()?;
    // A machine that cannot run the passes hears so before the scene loads.
    nearfield_render::GpuContext::check_adapter(args.scene.adapter.as_deref())?;
    let loaded = args.scene.load()?;
    loaded.report_sun();
    // The frame's far field as `render` has it for the image shown. A bake is not waited for:
    // the window opens with the sky, and the volume comes in when the background bake (or the
    // cache) has it.
    let shown = (args.aov != "final").then_some(args.aov.as_str());
    let plan = args.far.plan(&loaded, shown)?;
    crate::far::apply_auto_radius(&mut params, &plan);
    let a = technique_state::TechniqueState::from_command_line(&args.method, &params)
        .map_err(|e| BadInput(format!("--method {}: {e}", args.method)))?;
    let b_params = nearfield_render::TechniqueParams {
        radius: params.radius,
        ..Default::default()
    };
    let b = args
        .split_with
        .as_deref()
        .map(|m| {
            technique_state::TechniqueState::from_command_line(m, &b_params)
                .map_err(|e| BadInput(format!("--split-with {m}: {e}")))
        })
        .transpose()?;
    let far = match plan {
        crate::far::FarPlan::Sky => session::StartFar::Sky,
        crate::far::FarPlan::File(v) => session::StartFar::Volume(v),
        crate::far::FarPlan::Bake(_) => session::StartFar::Bake,
    };
    let env_name = args
        .scene
        .env
        .clone()
        .unwrap_or_else(|| session::env_name(&loaded.env_source));
    let mut extra_compare_args = Vec::new();
    if let Some(adapter) = &args.scene.adapter {
        extra_compare_args.extend(["--adapter".to_string(), adapter.clone()]);
    }
    window::run(window::Plan {
        start: session::Start {
            scene_name: args.scene.scene.clone(),
            scene: loaded.scene,
            env_name,
            env: loaded.env,
            camera: loaded.camera,
            settings,
            a,
            b,
            aov: args.aov.clone(),
            sun: nearfield_scene::SunMode::parse(&args.scene.sun)?,
            far,
            grid: args.far.grid.clone(),
        },
        adapter: args.scene.adapter.clone(),
        vsync: !args.no_vsync,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        script,
        extra_compare_args,
    })
}

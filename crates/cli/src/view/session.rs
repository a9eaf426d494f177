//! What the viewer shows, without the window: the scene, environment, camera, one or two
//! renderers (an A/B view), the image being shown and the display pass. Every change — from
//! the panel, a dropped file, the keyboard or a script — goes through [`Session::apply`], which
//! validates it and leaves the session as it was when it fails.

use super::technique_state::TechniqueState;
use anyhow::Result;
use display::{display_side, source, wgpu_encoder_label};
use far::Bake;
pub use files::{env_name, save_camera};
use nearfield_render::passes::display::{DisplayPass, DisplayPost};
use nearfield_render::technique::Spec;
use nearfield_render::{Aov, GpuContext, RenderSettings, Renderer};
use nearfield_scene::animation::LOOP_FPS;
use nearfield_scene::probes::ProbeVolume;
use nearfield_scene::{Camera, CameraFile, Environment, Scene, SunMode};
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod changes;
mod display;
mod far;
mod files;
pub mod recording;

/// Which side of the A/B view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    A,
    B,
}

/// One change to the session. The script syntax of each is given beside it.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// `method [b] NAME[:key=value+…]`: switch technique (settings from the spec, others default).
    Method(Side, String),
    /// `set [b] KEY VALUE`: one setting of the side's technique.
    Setting(Side, String, String),
    /// `quality [b] NAME`: a quality preset.
    Preset(Side, String),
    /// `aov NAME`: the image shown (an AOV or one of the technique's own images).
    Aov(String),
    /// `size WxH`: the render resolution.
    Size(u32, u32),
    /// `scene SCENE`: a file or builtin:NAME (environment and camera become the scene's).
    Scene(String),
    /// `env ENV`: sky, constant:R,G,B or an .hdr/.exr file.
    Env(String),
    /// `env-intensity K`
    EnvIntensity(f32),
    /// `env-rotation DEG`
    EnvRotation(f32),
    /// `exposure EV`
    Exposure(f32),
    /// `tonemap aces|neutral|linear`
    Tonemap(String),
    /// `light INDEX on|off`
    Light(usize, bool),
    /// `split off` or `split FRACTION` (0..=1: where the divider is).
    Split(Option<f32>),
    /// `camera FILE.json` loads, `save-camera FILE.json` writes ([`Change::SaveCamera`]).
    Camera(Camera),
    LoadCamera(PathBuf),
    SaveCamera(PathBuf),
    /// `orbit DEG`: turns the camera about its target.
    Orbit(f32),
    /// `frame`: the scene's default view.
    FrameScene,
    /// `far sky|volume`: the far field. With `volume` the scene's probe volume is baked (or taken
    /// from the cache) in the background; until it is ready the frame keeps its far field.
    Far(String),
    /// `record-path FILE.json`: records the camera of every frame from now on as a camera path;
    /// `stop-path` writes it.
    RecordPath(PathBuf),
    StopPath,
}

/// Live GPU objects of the device (wgpu's registry), for leak checks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResourceCounts {
    pub buffers: usize,
    pub textures: usize,
    pub texture_views: usize,
    pub bind_groups: usize,
    pub pipelines: usize,
}

impl std::fmt::Display for ResourceCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "buffers={} textures={} texture_views={} bind_groups={} pipelines={}",
            self.buffers, self.textures, self.texture_views, self.bind_groups, self.pipelines
        )
    }
}

/// (pass, GPU milliseconds) of one frame.
pub type PassTimes = Vec<(&'static str, f64)>;

pub struct Session {
    pub ctx: GpuContext,
    pub scene_name: String,
    pub scene: Scene,
    /// The environment as typed (`sky`, `constant:…`, a path).
    pub env_name: String,
    /// `--sun`: how every environment of the session is split.
    pub sun: SunMode,
    pub env_intensity: f32,
    pub env_rotation_deg: f32,
    pub settings: RenderSettings,
    pub camera: Camera,
    pub a: TechniqueState,
    pub b: TechniqueState,
    /// Where the A/B divider is (fraction of the width); `None`: A only.
    pub split: Option<f32>,
    pub aov: String,
    renderer_a: Renderer,
    renderer_b: Option<Renderer>,
    pub display: DisplayPass,
    /// Per-pass GPU milliseconds of the last frame, per side.
    pub timings: (PassTimes, PassTimes),
    /// The far field: the probe volume (`far volume`) or the sky.
    pub far_volume: bool,
    /// The volume the renderers use, and what it was baked for ([`Self::far_key`]).
    volume: Option<(String, Arc<ProbeVolume>)>,
    /// The grid of the session's bakes.
    grid: crate::far::GridOpts,
    bake: Option<Bake>,
    /// `record-path`: the camera path being recorded.
    pub recording: Option<recording::Recording>,
    /// Frames shown: the scene's clock, at [`LOOP_FPS`], playing a moving scene's animation in
    /// a loop.
    clock: u32,
}

/// Everything a session starts from.
pub struct Start {
    pub scene_name: String,
    pub scene: Scene,
    pub env_name: String,
    pub env: Environment,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub a: TechniqueState,
    pub b: Option<TechniqueState>,
    pub aov: String,
    /// `--sun`: environments loaded later are split the same way.
    pub sun: SunMode,
    /// The far field to start with.
    pub far: StartFar,
    /// The grid of the bakes the session makes (`--spacing`, `--probes`, `--rays`, `--bounces`).
    pub grid: crate::far::GridOpts,
}

/// The far field a session starts with.
pub enum StartFar {
    /// The open sky.
    Sky,
    /// `--volume`'s file.
    Volume(ProbeVolume),
    /// The scene's bake, taken from the cache or baked in the background: the first frames
    /// show the sky, and the volume comes in when it is ready.
    Bake,
}

impl Session {
    pub fn new(ctx: GpuContext, start: Start) -> Result<Self> {
        // A GPU error the session did not catch is reported, not fatal: the viewer stays up.
        ctx.device
            .on_uncaptured_error(std::sync::Arc::new(|e: nearfield_render::wgpu::Error| {
                let msg = e.to_string().replace('\n', " ");
                eprintln!("nearfield: view: GPU error: {msg}");
            }));
        let far_volume = !matches!(start.far, StartFar::Sky);
        let bake = matches!(start.far, StartFar::Bake);
        let volume = match start.far {
            StartFar::Volume(v) => Some(v),
            StartFar::Sky | StartFar::Bake => None,
        };
        let renderer_a = Renderer::new(
            &ctx,
            &start.scene,
            &start.env,
            volume.as_ref(),
            start.camera,
            &Spec::resolve(start.a.name(), &start.a.params())?,
            start.settings,
        )?;
        let display = DisplayPass::new(&ctx.device, start.settings.size);
        let mut s = Session {
            scene_name: start.scene_name,
            env_name: start.env_name,
            sun: start.sun,
            env_intensity: start.env.intensity,
            env_rotation_deg: start.env.rotation.to_degrees(),
            settings: start.settings,
            camera: start.camera,
            b: start.b.clone().unwrap_or_else(|| start.a.clone()),
            a: start.a,
            split: None,
            aov: "final".into(),
            renderer_a,
            renderer_b: None,
            display,
            timings: Default::default(),
            far_volume,
            volume: None,
            bake: None,
            recording: None,
            clock: 0,
            grid: start.grid,
            scene: start.scene,
            ctx,
        };
        if let Some(v) = volume {
            s.a.follow_far(true);
            s.b.follow_far(true);
            s.volume = Some((s.far_key(), Arc::new(v)));
        } else if bake {
            s.refresh_far().map_err(crate::BadInput)?;
        }
        if start.b.is_some() {
            s.apply(Change::Split(Some(0.5))).map_err(crate::BadInput)?;
        }
        s.apply(Change::Aov(start.aov)).map_err(crate::BadInput)?;
        Ok(s)
    }

    pub fn adapter(&self) -> String {
        nearfield_render::context::describe(&self.ctx.adapter_info())
    }

    pub fn renderer(&self, side: Side) -> Option<&Renderer> {
        match side {
            Side::A => Some(&self.renderer_a),
            Side::B => self.renderer_b.as_ref(),
        }
    }

    pub fn technique(&self, side: Side) -> &TechniqueState {
        match side {
            Side::A => &self.a,
            Side::B => &self.b,
        }
    }

    /// Names the panel offers for the shown image: every AOV, then the technique's own images.
    pub fn image_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Aov::names().iter().map(|s| s.to_string()).collect();
        names.extend(
            self.renderer_a
                .extra_names()
                .iter()
                .map(|s| format!("extra:{s}")),
        );
        names
    }

    /// Applies one change; on error the session is unchanged and the message says why.
    pub fn apply(&mut self, change: Change) -> Result<(), String> {
        match change {
            Change::Method(side, spec) => {
                let state = TechniqueState::from_command_line(&spec, &Default::default())?;
                self.set_technique(side, state)
            }
            Change::Setting(side, key, value) => {
                let mut state = self.technique(side).clone();
                state.set(&key, &value)?;
                self.set_technique(side, state)
            }
            Change::Preset(side, name) => {
                let mut state = self.technique(side).clone();
                state.apply_preset(&name)?;
                self.set_technique(side, state)
            }
            Change::Aov(name) => self.set_aov(name),
            Change::Size(w, h) => self.resize(w, h),
            Change::Scene(name) => {
                self.load_scene(&name)?;
                self.refresh_far()
            }
            Change::Env(name) => self.set_env(name),
            Change::EnvIntensity(k) => self.set_env_intensity(k),
            Change::EnvRotation(deg) => self.set_env_rotation(deg),
            Change::Exposure(ev) => self.set_exposure(ev),
            Change::Tonemap(name) => self.set_tonemap(name),
            Change::Light(i, on) => self.set_light(i, on),
            Change::Split(None) => {
                self.split = None;
                self.renderer_b = None;
                Ok(())
            }
            Change::Split(Some(f)) => self.split(f),
            Change::Camera(c) => {
                c.validate().map_err(|e| format!("camera: {e}"))?;
                self.camera = c;
                Ok(())
            }
            Change::LoadCamera(path) => {
                let c = CameraFile::load(&path).map_err(|e| e.to_string())?;
                self.camera = c;
                Ok(())
            }
            Change::SaveCamera(path) => save_camera(&self.camera, &path),
            Change::Orbit(deg) => {
                if !(deg.is_finite() && deg.abs() <= 360.0) {
                    return Err(format!("orbit {deg}: must be in -360..=360"));
                }
                self.camera = self.camera.orbit(deg);
                Ok(())
            }
            Change::FrameScene => {
                self.camera = self.scene.default_camera();
                Ok(())
            }
            Change::Far(mode) => self.set_far_mode(mode),
            Change::RecordPath(path) => {
                self.recording = Some(recording::Recording::start(&path)?);
                Ok(())
            }
            Change::StopPath => {
                let r = self
                    .recording
                    .take()
                    .ok_or("stop-path: no path is being recorded")?;
                let (n, path) = (r.frames(), r.finish(self.camera)?);
                eprintln!("nearfield: view: wrote {} ({n} frames)", path.display());
                Ok(())
            }
        }
    }

    /// A technique image the current technique lacks falls back to the frame.
    fn keep_image_valid(&mut self) {
        if Aov::parse(&self.aov).is_none()
            && !self.renderer_a.extra_names().contains(&self.aov.as_str())
        {
            self.aov = "final".into();
        }
    }

    /// Renders one frame of each side and the display image; reads the per-pass timings.
    pub fn frame(&mut self) {
        if let Err(e) = self.poll_bake(false) {
            eprintln!("nearfield: view: {e}");
        }
        let camera = self.camera;
        if let Some(r) = &mut self.recording {
            r.frame(camera);
        }
        let time = self.scene.animation.looped(self.clock, LOOP_FPS);
        self.clock += 1;
        self.for_each_renderer(|r| {
            r.set_camera(camera);
            r.set_time(time);
            r.render_frame();
        });
        let far = {
            let b = self.scene.bounds();
            if b.is_empty() {
                1.0
            } else {
                (camera.eye - b.center()).length() + b.radius()
            }
        };
        let aov = self.aov.clone();
        let a = source(&mut self.renderer_a, &aov);
        let b = self.renderer_b.as_mut().map(|r| source(r, &aov));
        let range = match Aov::parse(&aov) {
            Some(Aov::Depth) => (0.0, far),
            Some(Aov::Motion) => (0.0, 4.0),
            _ => (0.0, 1.0),
        };
        let post = DisplayPost {
            exposure: self.settings.exposure,
            tonemap: self.settings.tonemap,
            range,
        };
        let mut encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu_encoder_label());
        let a_side = display_side(&a);
        let b_side = b.as_ref().map(display_side);
        let split = self
            .split
            .map(|f| (f * self.settings.size.0 as f32).round() as u32);
        self.display.encode(
            &self.ctx.device,
            &self.ctx.queue,
            &mut encoder,
            &a_side,
            b_side.as_ref().zip(split),
            post,
        );
        self.ctx.queue.submit([encoder.finish()]);
        self.timings.0 = self.renderer_a.timings();
        self.timings.1 = self
            .renderer_b
            .as_ref()
            .map(|r| r.timings())
            .unwrap_or_default();
    }

    /// Saves the display image (the 3D view without the interface) as PNG.
    pub fn screenshot(&self, path: &Path) -> Result<()> {
        crate::output::check_parent_dir(path)?;
        let encoder = self.ctx.device.create_command_encoder(&Default::default());
        if let Some(why) = self.ctx.lost() {
            return Err(nearfield_render::RenderError::Lost(why).into());
        }
        let bytes = nearfield_render::util::read_texture(
            &self.ctx.device,
            &self.ctx.queue,
            encoder,
            &self.display.output,
            4,
        );
        let (w, h) = self.display.size();
        let img = image::RgbaImage::from_raw(w, h, bytes)
            .ok_or_else(|| anyhow::anyhow!("display image has a wrong size"))?;
        crate::output::save_atomically(path, |tmp| {
            img.save_with_format(tmp, image::ImageFormat::Png)
                .map_err(anyhow::Error::from)
        })
    }

    /// Live GPU objects, after letting the device free what was dropped.
    pub fn resource_counts(&self) -> ResourceCounts {
        let _ = self
            .ctx
            .device
            .poll(nearfield_render::wgpu::PollType::wait_indefinitely());
        let Some(report) = self.ctx.instance.generate_report() else {
            return ResourceCounts::default();
        };
        let hub = report.hub_report();
        ResourceCounts {
            buffers: hub.buffers.num_kept_from_user,
            textures: hub.textures.num_kept_from_user,
            texture_views: hub.texture_views.num_kept_from_user,
            bind_groups: hub.bind_groups.num_kept_from_user,
            pipelines: hub.compute_pipelines.num_kept_from_user
                + hub.render_pipelines.num_kept_from_user,
        }
    }
}

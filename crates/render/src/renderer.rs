//! The frame: owns the GPU scene, environment, targets and passes, and runs them in order
//! (docs/src/architecture.md, "The frame"): G-buffer → shadow maps → direct lighting →
//! technique → composite → tonemap. Reads AOVs back for output.

use crate::RenderError;
use crate::context::GpuContext;
use crate::far::{FarMode, GpuFarField};
use crate::frame::{
    CameraMatrices, FrameInputs, FrameUniforms, PostUniforms, Tonemap, ViewUniforms,
};
use crate::gpu_env::GpuEnvironment;
use crate::gpu_scene::GpuScene;
use crate::passes::{
    FrameGroup,
    gbuffer::GBufferPass,
    shadow::{ShadowPass, ShadowSettings},
};
use crate::profiler::GpuProfiler;
use crate::targets::{self, FrameTargets};
use crate::technique::{self, TechniqueParams};
use nearfield_scene::{Camera, Environment, Scene, probes::ProbeVolume};
use passes_of_frame::{ErrorScopes, Passes};

mod ablation;
pub use ablation::FramePass;
mod passes_of_frame;
mod readback;

/// Frame-level settings.
#[derive(Clone, Copy, Debug)]
pub struct RenderSettings {
    /// Image size (pixels), 1..=8192 each side.
    pub size: (u32, u32),
    /// Exposure (EV stops) applied before tonemapping, −20..=20. Default 0.
    pub exposure: f32,
    pub tonemap: Tonemap,
    pub shadows: ShadowSettings,
    /// Seed of the per-pixel noise sequences.
    pub seed: u32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            size: (1280, 720),
            exposure: 0.0,
            tonemap: Tonemap::Aces,
            shadows: ShadowSettings::default(),
            seed: 0,
        }
    }
}

pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pub scene: GpuScene,
    pub env: GpuEnvironment,
    /// The far field: the open sky, or a probe volume ([`Self::set_far_field`]).
    pub far: GpuFarField,
    pub targets: FrameTargets,
    frame_buffer: wgpu::Buffer,
    view_buffer: wgpu::Buffer,
    /// Group 0 of every pass: the frame's uniforms and the environment.
    frame_group: FrameGroup,
    gbuffer: GBufferPass,
    shadows: ShadowPass,
    passes: Passes,
    /// The technique, resolved once: what a resize or an environment change rebuilds.
    technique: technique::Spec,
    pack_half: bool,
    /// Lights switched off ([`Self::set_light_enabled`]), by index into the scene's lights.
    lights_off: Vec<bool>,
    pub profiler: GpuProfiler,
    /// Untimed recording of the AOV pass (extraction is not part of the frame's timings).
    quiet: GpuProfiler,
    camera: Camera,
    previous: Option<CameraMatrices>,
    previous_camera: Option<Camera>,
    /// The next frame starts without history (set by a cut).
    cut: bool,
    frames_since_cut: u32,
    frame_index: u32,
    /// What the last rendered frame was recorded with (its index and whether it had history):
    /// the one definition AOV readback uses too.
    last_frame: technique::FrameInfo,
    settings: RenderSettings,
    /// Rebuilds by [`Self::set_technique`].
    rebuilds: u32,
    /// The device's lost flag ([`GpuContext::lost`]).
    lost: crate::context::LostFlag,
    /// The adapter's kind (what [`targets::check_memory`] budgets against).
    device_type: wgpu::DeviceType,
    /// The pass a timing run leaves out ([`Self::leave_out`]).
    left_out: Option<FramePass>,
}

/// The technique's near-field radius R (m), what the far field's own visibility is computed
/// within; 1 m for a technique without one (its value is then not read).
fn technique_radius(technique: &technique::Spec) -> f32 {
    technique
        .radius()
        .filter(|r| r.is_finite() && *r > 0.0)
        .unwrap_or(1.0)
}

impl Renderer {
    /// Uploads the scene, the environment and the far field (a probe volume baked for this scene
    /// and environment by `nearfield bake`, or `None` for the open sky) and builds every pass for
    /// `technique`.
    pub fn new(
        ctx: &GpuContext,
        scene: &Scene,
        env: &Environment,
        far: Option<&ProbeVolume>,
        camera: Camera,
        technique: &technique::Spec,
        settings: RenderSettings,
    ) -> Result<Self, RenderError> {
        targets::check_size(settings.size, ctx.device.limits().max_texture_dimension_2d)?;
        targets::check_memory(settings.size, ctx.adapter_info().device_type)?;
        camera.validate().map_err(RenderError::Scene)?;
        let device = ctx.device.clone();
        let queue = ctx.queue.clone();
        let scopes = ErrorScopes::push(&device);
        // The environment's sun (split out by `--sun auto`) is one more light, after the scene's.
        let lights: Vec<nearfield_scene::Light> = scene
            .lights
            .iter()
            .copied()
            .chain(env.sun_light())
            .collect();
        let gpu_scene = GpuScene::new(&device, &queue, scene, &lights)?;
        let gpu_env = GpuEnvironment::new(&device, &queue, env);
        let targets = FrameTargets::new(&device, settings.size);
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view uniforms"),
            size: std::mem::size_of::<ViewUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shadows = ShadowPass::new(&device, &gpu_scene, settings.shadows);
        gpu_scene.write_lights(&queue, &shadows.light_layers);
        let far = GpuFarField::new(&device, &queue, far, technique_radius(technique));
        let frame_group =
            FrameGroup::new(&device, &view_buffer, Some(&frame_buffer), &gpu_env, &far);
        let gbuffer = GBufferPass::new(&device, &frame_group, &gpu_scene);
        let passes = Passes::new(
            &device,
            &queue,
            &frame_group,
            &targets,
            &gpu_scene,
            &gpu_env,
            &shadows,
            ctx.pack_half,
            technique,
        );
        let profiler = GpuProfiler::new(&device, &queue, ctx.timestamps);
        scopes.pop()?;
        let passes = passes?;
        let lights_off = vec![false; gpu_scene.scene_lights.len()];
        Ok(Renderer {
            device,
            queue,
            scene: gpu_scene,
            env: gpu_env,
            far,
            targets,
            frame_buffer,
            view_buffer,
            frame_group,
            gbuffer,
            shadows,
            passes,
            technique: technique.clone(),
            pack_half: ctx.pack_half,
            lights_off,
            profiler,
            quiet: GpuProfiler::new(&ctx.device, &ctx.queue, false),
            camera,
            previous: None,
            previous_camera: None,
            cut: false,
            frames_since_cut: 0,
            left_out: None,
            frame_index: 0,
            last_frame: technique::FrameInfo {
                index: 0,
                history: false,
            },
            settings,
            rebuilds: 0,
            lost: ctx.lost_flag(),
            device_type: ctx.adapter_info().device_type,
        })
    }

    /// Rebuilds the screen passes and the technique for the current targets and environment.
    fn rebuild_passes(&mut self, technique: &technique::Spec) -> Result<(), RenderError> {
        let scopes = ErrorScopes::push(&self.device);
        let passes = Passes::new(
            &self.device,
            &self.queue,
            &self.frame_group,
            &self.targets,
            &self.scene,
            &self.env,
            &self.shadows,
            self.pack_half,
            technique,
        );
        scopes.pop()?;
        self.passes = passes?;
        self.cut = true;
        Ok(())
    }

    /// Replaces the technique (a `name` or `name:key=value+…` spec) and its parameters; scene,
    /// environment and targets stay. On error the renderer keeps its current technique.
    pub fn set_technique(
        &mut self,
        spec: &str,
        params: &TechniqueParams,
    ) -> Result<(), RenderError> {
        self.check_device()?;
        let technique = technique::Spec::resolve(spec, params)?;
        let in_place = technique.desc.name == self.passes.technique.name()
            && self.passes.technique.update(
                &self.queue,
                &technique.params_for(self.frame_group.far_volume()),
            )?;
        if in_place {
            self.cut = true;
        } else {
            self.rebuild_passes(&technique)?;
            self.rebuilds += 1;
        }
        self.far
            .set_radius(&self.queue, technique_radius(&technique));
        self.technique = technique;
        Ok(())
    }

    /// Why the device was lost, if it was: what was rendered or read since is not valid.
    pub fn lost(&self) -> Option<String> {
        self.lost.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// An error when the device was lost: commands call it before they write an output.
    pub fn check_device(&self) -> Result<(), RenderError> {
        // Lets the device run its callbacks (the loss is reported through one).
        let _ = self.device.poll(wgpu::PollType::Poll);
        match self.lost() {
            Some(why) => Err(RenderError::Lost(why)),
            None => Ok(()),
        }
    }

    /// How often [`Self::set_technique`] rebuilt the technique (a change it could not apply in
    /// place: another technique, a count, a resource).
    pub fn rebuilds(&self) -> u32 {
        self.rebuilds
    }

    /// Changes the image size: new targets, passes rebuilt, history discarded. On error (a size
    /// the device cannot hold) the renderer keeps its current size.
    pub fn resize(&mut self, size: (u32, u32)) -> Result<(), RenderError> {
        if size == self.settings.size {
            return Ok(());
        }
        self.check_device()?;
        targets::check_size(size, self.device.limits().max_texture_dimension_2d)?;
        targets::check_memory(size, self.device_type)?;
        let old = std::mem::replace(&mut self.targets, FrameTargets::new(&self.device, size));
        let technique = self.technique.clone();
        if let Err(e) = self.rebuild_passes(&technique) {
            self.targets = old;
            return Err(e);
        }
        self.settings.size = size;
        self.previous = None;
        Ok(())
    }

    /// Replaces the environment (map, intensity and rotation, its sun); passes are rebuilt.
    pub fn set_environment(&mut self, env: &Environment) -> Result<(), RenderError> {
        self.check_device()?;
        let scene_count =
            self.scene.scene_lights.len() - usize::from(self.env.source().sun.is_some());
        let mut lights = self.scene.scene_lights[..scene_count].to_vec();
        lights.extend(env.sun_light());
        if lights.len() > self.scene.light_capacity {
            return Err(RenderError::Scene("the light table is full".into()));
        }
        let old_lights = std::mem::replace(&mut self.scene.scene_lights, lights);
        let old_count = std::mem::replace(
            &mut self.scene.light_count,
            self.scene.scene_lights.len() as u32,
        );
        let old_shadows = std::mem::replace(
            &mut self.shadows,
            ShadowPass::new(&self.device, &self.scene, self.settings.shadows),
        );
        self.lights_off.resize(self.scene.scene_lights.len(), false);
        self.write_lights();
        let old = std::mem::replace(
            &mut self.env,
            GpuEnvironment::new(&self.device, &self.queue, env),
        );
        let group = self.new_frame_group();
        let old_group = std::mem::replace(&mut self.frame_group, group);
        let technique = self.technique.clone();
        if let Err(e) = self.rebuild_passes(&technique) {
            self.env = old;
            self.frame_group = old_group;
            self.scene.scene_lights = old_lights;
            self.scene.light_count = old_count;
            self.shadows = old_shadows;
            self.lights_off.resize(self.scene.scene_lights.len(), false);
            self.write_lights();
            return Err(e);
        }
        self.gbuffer.set_frame(&self.frame_group);
        Ok(())
    }

    /// Sets the far field of the next frames: a probe volume (baked for this scene and
    /// environment by `nearfield bake`), or `None` for the open sky. Passes are rebuilt; the
    /// history is discarded.
    pub fn set_far_field(&mut self, volume: Option<&ProbeVolume>) -> Result<(), RenderError> {
        self.check_device()?;
        let scopes = ErrorScopes::push(&self.device);
        let radius = technique_radius(&self.technique);
        let far = GpuFarField::new(&self.device, &self.queue, volume, radius);
        scopes.pop()?;
        let old_far = std::mem::replace(&mut self.far, far);
        let group = self.new_frame_group();
        let old_group = std::mem::replace(&mut self.frame_group, group);
        let technique = self.technique.clone();
        if let Err(e) = self.rebuild_passes(&technique) {
            self.far = old_far;
            self.frame_group = old_group;
            return Err(e);
        }
        self.gbuffer.set_frame(&self.frame_group);
        Ok(())
    }

    /// The far field the frames use.
    pub fn far_mode(&self) -> FarMode {
        self.far.mode
    }

    /// Multiplies the environment's radiance by `intensity` (≥ 0) for the next frames.
    pub fn set_environment_intensity(&mut self, intensity: f32) {
        self.env.set_intensity(&self.queue, intensity.max(0.0));
        self.update_sun();
    }

    /// After the environment turned or changed intensity: its sun light follows.
    fn update_sun(&mut self) {
        let Some(sun) = self.env.source().sun_light() else {
            return;
        };
        let index = self.scene.scene_lights.len() - 1;
        self.scene.scene_lights[index] = sun;
        self.shadows.set_light_kind(index, sun.kind);
        self.write_lights();
    }

    /// Writes the light table (shadow layers, switches).
    fn write_lights(&self) {
        self.scene
            .write_lights_masked(&self.queue, &self.shadows.light_layers, &self.lights_off);
    }

    /// Exposure (EV stops, clamped to −20..=20) and tonemap operator of the next frames.
    pub fn set_post(&mut self, exposure: f32, tonemap: Tonemap) {
        self.settings.exposure = exposure.clamp(-20.0, 20.0);
        self.settings.tonemap = tonemap;
    }

    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The technique spec and parameters in use.
    pub fn technique(&self) -> (&str, &TechniqueParams) {
        (&self.technique.spec, &self.technique.given)
    }

    /// Switches light `index` of the scene on or off (an off light contributes nothing; its
    /// shadow map is still drawn). Unknown indices are ignored.
    pub fn set_light_enabled(&mut self, index: usize, on: bool) {
        if let Some(off) = self.lights_off.get_mut(index) {
            *off = !on;
            self.write_lights();
        }
    }

    /// The lights the frame is lit by: the scene's, then the environment's sun if split out
    /// (`--sun auto`). [`Self::set_light_enabled`] indexes this list.
    pub fn lights(&self) -> &[nearfield_scene::Light] {
        &self.scene.scene_lights
    }

    /// Whether light `index` is on.
    pub fn light_enabled(&self, index: usize) -> bool {
        !self.lights_off.get(index).copied().unwrap_or(true)
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn size(&self) -> (u32, u32) {
        self.settings.size
    }

    pub fn technique_name(&self) -> &'static str {
        self.passes.technique.name()
    }

    /// Moves the camera for the next frames. A move that [`Camera::is_cut_to`] calls a cut
    /// discards the history of temporal techniques; smaller moves reproject it.
    pub fn set_camera(&mut self, camera: Camera) {
        if self.camera.is_cut_to(&camera) {
            self.cut = true;
        }
        self.camera = camera;
    }

    /// Discards all history: the next frame is rendered as if it were the first.
    pub fn cut(&mut self) {
        self.cut = true;
    }

    /// Discards all history and restarts the frame count: the next frames draw the same noise
    /// as a new renderer's first frames, so that one setting measured twice gives one result
    /// (what a fit that reuses the renderer needs).
    pub fn restart(&mut self) {
        self.cut = true;
        self.frame_index = 0;
        self.previous = None;
        self.previous_camera = None;
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Turns the environment about +Y (radians) for the next frames; the technique and every
    /// other pass stay as they are.
    pub fn set_environment_rotation(&mut self, rotation: f32) {
        self.env.set_rotation(&self.queue, rotation);
        self.update_sun();
    }

    /// Sets the scene's time (s) the next frames show: its moving objects are posed there, and
    /// their motion since the last frame goes into the motion vectors. Nothing happens in a
    /// scene where nothing moves.
    pub fn set_time(&mut self, t: f32) {
        if let Some(m) = &mut self.scene.moving {
            m.set_time(t);
        }
    }

    /// Whether anything in the scene moves ([`Self::set_time`]).
    pub fn moves(&self) -> bool {
        self.scene.moving.is_some()
    }

    pub fn frame_index(&self) -> u32 {
        self.frame_index
    }

    fn uniforms(&self, current: CameraMatrices) -> (ViewUniforms, FrameUniforms) {
        let s = &self.settings;
        let previous_camera = self.previous_camera.as_ref().unwrap_or(&self.camera);
        let view = ViewUniforms::new(&FrameInputs {
            camera: &self.camera,
            current,
            previous: self.previous.unwrap_or(current),
            size: s.size,
            frame_index: self.frame_index,
            seed: s.seed,
            previous_tan_half_fov: (0.5 * previous_camera.yfov).tan(),
            history: (self.history_valid(), self.frames_since_cut),
        });
        let frame = FrameUniforms::new(
            PostUniforms {
                exposure: s.exposure,
                tonemap: s.tonemap,
                shadow_normal_offset: s.shadows.normal_offset_texels,
            },
            self.scene.light_count,
        );
        (view, frame)
    }

    /// Group 0 over the current environment and far field.
    fn new_frame_group(&self) -> FrameGroup {
        FrameGroup::new(
            &self.device,
            &self.view_buffer,
            Some(&self.frame_buffer),
            &self.env,
            &self.far,
        )
    }

    /// Writes group 0's two uniforms.
    fn write_uniforms(&self, (view, frame): (ViewUniforms, FrameUniforms)) {
        self.queue
            .write_buffer(&self.view_buffer, 0, bytemuck::bytes_of(&view));
        self.queue
            .write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
    }

    /// Whether the next frame may reuse this one's buffers.
    fn history_valid(&self) -> bool {
        self.previous.is_some() && !self.cut
    }

    /// Leaves `pass` out of every frame from now on (`None`: every pass runs). For timing by
    /// ablation only (`nearfield bench --ablate`): the images are wrong while a pass is left out.
    pub fn leave_out(&mut self, pass: Option<FramePass>) {
        self.left_out = pass;
    }

    /// Renders one frame and submits it. Per-pass timings of it are then available from
    /// [`Self::timings`].
    pub fn render_frame(&mut self) {
        if self.lost().is_some() {
            return;
        }
        if !self.history_valid() {
            self.frames_since_cut = 0;
        }
        let history = self.history_valid();
        let current = CameraMatrices::new(&self.camera, self.settings.size, self.scene.bounds);
        self.write_uniforms(self.uniforms(current));
        self.passes.technique.prepare(&self.queue, &self.camera);
        if self.scene.advance(&self.queue) {
            self.shadows.moved();
        }
        if self
            .shadows
            .fit_to_view(&self.queue, &self.camera, self.settings.size)
        {
            self.write_lights();
        }
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        let size = self.settings.size;
        let run = |pass| self.left_out != Some(pass);
        let p = &mut self.profiler;
        p.begin_frame();
        p.lead(&mut encoder);
        if run(FramePass::Gbuffer) {
            self.gbuffer
                .encode(&mut encoder, p, &self.targets, &self.scene);
        }
        if run(FramePass::Shadows) {
            self.shadows.encode(&mut encoder, p);
        }
        if run(FramePass::Direct) {
            self.passes
                .direct
                .encode(&mut encoder, p, size, self.frame_index);
        }
        let info = technique::FrameInfo {
            index: self.frame_index,
            history,
        };
        if run(FramePass::Technique) {
            self.passes.technique.encode(&mut encoder, p, info);
        }
        if run(FramePass::Composite) {
            self.passes.composite.encode(&mut encoder, p, size, 0);
        }
        if run(FramePass::Tonemap) {
            self.passes.tonemap.encode(&mut encoder, p, size, 0);
        }
        p.resolve(&mut encoder);
        self.queue.submit([encoder.finish()]);
        self.previous = Some(current);
        self.previous_camera = Some(self.camera);
        self.cut = false;
        self.frames_since_cut += 1;
        self.frame_index += 1;
        self.last_frame = info;
    }

    /// Per-pass GPU milliseconds of the last frame (waits for it), its empty
    /// [`profiler::LEAD`](crate::profiler::LEAD) first; [`crate::profiler::frame_total`] sums
    /// the frame.
    pub fn timings(&self) -> Vec<(&'static str, f64)> {
        self.profiler.read(&self.device)
    }

    /// Waits for all submitted work.
    pub fn wait(&self) {
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}

//! The window: winit event loop, wgpu surface, egui, and the frame loop that drives the
//! [`Session`]. Resizes, minimising (zero size) and lost or outdated surfaces are handled by
//! skipping or reconfiguring, never by panicking.

use super::panel::{Panel, Requests};
use super::script::Command;
use super::session::{Session, Start};
use anyhow::{Context, Result};
use nearfield_render::GpuContext;
use nearfield_render::wgpu;
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// What the window runs.
pub struct Plan {
    pub start: Start,
    pub adapter: Option<String>,
    pub vsync: bool,
    /// Render this many frames, then save `screenshot` (if any) and exit.
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    pub script: Vec<Command>,
    /// Arguments of `compare` that name the scene options (scene, env, …) are rebuilt from the
    /// session; these are the ones it cannot know (e.g. --adapter).
    pub extra_compare_args: Vec<String>,
}

pub fn run(plan: Plan) -> Result<()> {
    let event_loop = EventLoop::new().context("cannot open a window (is a display available?)")?;
    let instance = GpuContext::instance(Some(Box::new(event_loop.owned_display_handle())));
    let mut app = App {
        plan: Some(plan),
        instance: Some(instance),
        running: None,
        result: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .context("window event loop failed")?;
    app.result
}

struct App {
    plan: Option<Plan>,
    instance: Option<wgpu::Instance>,
    running: Option<Running>,
    result: Result<()>,
}

struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    session: Session,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    view_texture: egui::TextureId,
    view_size: (u32, u32),
    panel: Panel,
    script: VecDeque<Command>,
    wait: u32,
    frames_done: u32,
    frames: Option<u32>,
    screenshot: Option<PathBuf>,
    last_frame: Instant,
    compare: Option<mpsc::Receiver<Result<PathBuf, String>>>,
    extra_compare_args: Vec<String>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.result = Err(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        let (Some(plan), Some(instance)) = (self.plan.take(), self.instance.take()) else {
            return;
        };
        match Running::new(event_loop, instance, plan) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else {
            return;
        };
        let response = r.egui_state.on_window_event(&r.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => r.resize(size.width, size.height),
            WindowEvent::DroppedFile(path) => r.dropped(path),
            WindowEvent::RedrawRequested => match r.redraw() {
                Ok(true) => {}
                Ok(false) => event_loop.exit(),
                Err(e) => self.fail(event_loop, e),
            },
            _ => {
                if response.repaint {
                    r.window.request_redraw();
                }
            }
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        // Continuous rendering: temporal techniques converge and timings stay live.
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, instance: wgpu::Instance, plan: Plan) -> Result<Self> {
        let (w, h) = plan.start.settings.size;
        let attributes = Window::default_attributes()
            .with_title(format!("nearfield — {}", plan.start.scene_name))
            // Room for the control panel (its content makes it up to ~440 pixels wide) beside
            // the image at one texel per pixel.
            .with_inner_size(winit::dpi::PhysicalSize::new(
                (w + 480).clamp(640, 2400),
                h.clamp(480, 1400),
            ));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create a window")?,
        );
        let surface = instance
            .create_surface(window.clone())
            .context("cannot create a surface for the window")?;
        let ctx = GpuContext::with_instance(instance, plan.adapter.as_deref(), Some(&surface))?;
        let caps = surface.get_capabilities(&ctx.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .context("the window's surface offers no format")?;
        let size = window.inner_size();
        let mut config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        config.present_mode = present_mode(plan.vsync);
        if size.width > 0 && size.height > 0 {
            surface.configure(&ctx.device, &config);
        }
        let mut session = Session::new(ctx, plan.start)?;
        // `--frames N` renders what `render --frames N` renders: every frame with the far field
        // it will have (interactively the window opens at once with the sky and the volume
        // comes in when its background bake is ready, at a frame that depends on the load).
        if plan.frames.is_some() {
            session.wait_bake().map_err(anyhow::Error::msg)?;
        }
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            event_loop,
            Some(window.scale_factor() as f32),
            None,
            Some(session.ctx.device.limits().max_texture_dimension_2d as usize),
        );
        let mut egui_renderer =
            egui_wgpu::Renderer::new(&session.ctx.device, format, Default::default());
        let view_texture = egui_renderer.register_native_texture(
            &session.ctx.device,
            &session.display.encoded_view,
            wgpu::FilterMode::Linear,
        );
        let panel = Panel::new(&session, plan.vsync);
        Ok(Running {
            view_size: session.display.size(),
            window,
            surface,
            config,
            session,
            egui_ctx,
            egui_state,
            egui_renderer,
            view_texture,
            panel,
            script: plan.script.into(),
            wait: 0,
            frames_done: 0,
            frames: plan.frames,
            screenshot: plan.screenshot,
            last_frame: Instant::now(),
            compare: None,
            extra_compare_args: plan.extra_compare_args,
        })
    }

    fn resize(&mut self, width: u32, height: u32) {
        self.config.width = width;
        self.config.height = height;
        if width > 0 && height > 0 {
            self.surface
                .configure(&self.session.ctx.device, &self.config);
        }
        self.window.request_redraw();
    }

    fn dropped(&mut self, path: PathBuf) {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        let name = path.display().to_string();
        let change = match ext.as_str() {
            "gltf" | "glb" | "obj" | "ply" => super::session::Change::Scene(name.clone()),
            "hdr" | "exr" => super::session::Change::Env(name.clone()),
            _ => {
                self.panel.status = format!(
                    "{name}: drop a .gltf/.glb/.obj/.ply scene or an .hdr/.exr environment"
                );
                return;
            }
        };
        self.apply(change);
    }

    fn apply(&mut self, change: super::session::Change) {
        if let Err(e) = self.session.apply(change) {
            eprintln!("nearfield: view: {e}");
            self.panel.status = e;
        }
    }

    /// Runs the next script command; false when the script says quit.
    fn step_script(&mut self) -> Result<bool> {
        if self.wait > 0 {
            self.wait -= 1;
            return Ok(true);
        }
        let Some(cmd) = self.script.pop_front() else {
            return Ok(true);
        };
        match cmd {
            Command::Change(c) => self.apply(c),
            Command::Wait(n) => self.wait = n,
            Command::BakeWait => self.session.wait_bake().map_err(crate::BadInput)?,
            Command::Screenshot(path) => {
                self.session.screenshot(&path)?;
                eprintln!("nearfield: view: saved {}", path.display());
            }
            Command::Report => {
                println!(
                    "resources frame={} {}",
                    self.frames_done,
                    self.session.resource_counts()
                );
            }
            Command::Quit => return Ok(false),
        }
        Ok(true)
    }

    /// One frame: script, interface, 3D view, present. False when the viewer should close.
    fn redraw(&mut self) -> Result<bool> {
        let now = Instant::now();
        let elapsed = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        self.panel.record_frame_time(elapsed * 1000.0);
        // Camera motion per frame is capped, so a slow frame does not fling the fly camera.
        let dt = elapsed.min(0.25);
        if !self.step_script()? {
            return Ok(false);
        }
        self.poll_compare();

        let raw = self.egui_state.take_egui_input(&self.window);
        let session = &self.session;
        let panel = &mut self.panel;
        let view = self.view_texture;
        let mut requests = Requests::default();
        let output = self.egui_ctx.run_ui(raw, |ui| {
            requests = panel.ui(ui, session, view, dt);
        });
        for c in requests.changes {
            self.apply(c);
        }
        if let Some(v) = requests.vsync {
            self.config.present_mode = present_mode(v);
            if self.config.width > 0 && self.config.height > 0 {
                self.surface
                    .configure(&self.session.ctx.device, &self.config);
            }
        }

        self.session.frame();
        self.frames_done += 1;
        if self.session.display.size() != self.view_size {
            self.view_size = self.session.display.size();
            self.egui_renderer.update_egui_texture_from_wgpu_texture(
                &self.session.ctx.device,
                &self.session.display.encoded_view,
                wgpu::FilterMode::Linear,
                self.view_texture,
            );
        }
        if requests.screenshot {
            let path = PathBuf::from(format!("nearfield-{}.png", unix_seconds()));
            self.panel.status = match self.session.screenshot(&path) {
                Ok(()) => format!("saved {}", path.display()),
                Err(e) => format!("{e:#}"),
            };
        }
        if requests.compare {
            self.start_compare();
        }

        self.egui_state
            .handle_platform_output(&self.window, output.platform_output.clone());
        self.present(output);

        if let Some(n) = self.frames
            && self.frames_done >= n
        {
            if let Some(path) = &self.screenshot {
                self.session.screenshot(path)?;
                eprintln!("nearfield: view: wrote {}", path.display());
            }
            // Frame time (wall clock between frames, the first two — start-up — left out).
            let mut ms: Vec<f32> = self.panel.frame_ms.iter().skip(2).copied().collect();
            ms.sort_by(f32::total_cmp);
            let median = ms.get(ms.len() / 2).copied().unwrap_or(0.0);
            let (w, h) = self.session.settings.size;
            eprintln!(
                "nearfield: view: {} frames of {}{} at {w}×{h}, median frame time {median:.1} ms ({})",
                self.frames_done,
                self.session.a.spec(),
                if self.session.split.is_some() {
                    format!(" | {}", self.session.b.spec())
                } else {
                    String::new()
                },
                self.session.adapter()
            );
            return Ok(false);
        }
        Ok(true)
    }

    fn present(&mut self, mut output: egui::FullOutput) {
        let device = &self.session.ctx.device;
        let queue = &self.session.ctx.queue;
        // Texture updates are applied every frame, shown or not.
        for (id, deltas) in output.textures_delta.set.drain() {
            for delta in deltas {
                self.egui_renderer.update_texture(device, queue, id, &delta);
            }
        }
        let freed: Vec<egui::TextureId> = output.textures_delta.free.drain().collect();
        let frame = if self.config.width == 0 || self.config.height == 0 {
            None // minimised
        } else {
            match self.surface.get_current_texture() {
                wgpu::CurrentSurfaceTexture::Success(f) => Some(f),
                wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
                    // Present this one; the next frame gets a fresh configuration.
                    self.surface.configure(device, &self.config);
                    Some(f)
                }
                wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                    self.surface.configure(device, &self.config);
                    None
                }
                _ => None, // timeout, occluded, validation: try again next frame
            }
        };
        let Some(frame) = frame else {
            for id in &freed {
                self.egui_renderer.free_texture(id);
            }
            return;
        };
        let ppp = output.pixels_per_point;
        let jobs = self
            .egui_ctx
            .tessellate(std::mem::take(&mut output.shapes), ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("interface"),
        });
        let extra = self
            .egui_renderer
            .update_buffers(device, queue, &mut encoder, &jobs, &screen);
        let target = frame.texture.create_view(&Default::default());
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("interface"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.02,
                            g: 0.02,
                            b: 0.02,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            let mut pass = pass.forget_lifetime();
            self.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        self.window.pre_present_notify();
        queue.present(frame);
        for id in &freed {
            self.egui_renderer.free_texture(id);
        }
    }

    /// Starts `nearfield compare` on the current view in the background.
    fn start_compare(&mut self) {
        if self.compare.is_some() {
            self.panel.status = "a comparison is already running".into();
            return;
        }
        let stamp = unix_seconds();
        let out = PathBuf::from(format!("nearfield-compare-{stamp}"));
        if let Err(e) = std::fs::create_dir_all(&out) {
            self.panel.status = format!("{}: {e}", out.display());
            return;
        }
        let camera = out.join("camera.json");
        if let Err(e) = super::session::save_camera(&self.session.camera, &camera) {
            self.panel.status = e;
            return;
        }
        let s = &self.session;
        let mut methods = vec![s.a.spec()];
        if s.split.is_some() {
            methods.push(s.b.spec());
        }
        let (w, h) = s.settings.size;
        let mut args: Vec<String> = vec![
            "compare".into(),
            s.scene_name.clone(),
            "--camera".into(),
            camera.display().to_string(),
            "--size".into(),
            format!("{w}x{h}"),
            "--env".into(),
            s.env_name.clone(),
            "--env-intensity".into(),
            s.env_intensity.to_string(),
            "--env-rotation".into(),
            s.env_rotation_deg.to_string(),
            "--methods".into(),
            methods.join(","),
            "--out".into(),
            out.display().to_string(),
        ];
        if compare_aovs().contains(&s.aov.as_str()) {
            args.extend(["--aov".into(), s.aov.clone()]);
        }
        args.extend(self.extra_compare_args.iter().cloned());
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let result = std::env::current_exe()
                .map_err(|e| e.to_string())
                .and_then(|exe| {
                    std::process::Command::new(exe)
                        .args(&args)
                        .output()
                        .map_err(|e| e.to_string())
                })
                .and_then(|o| {
                    if o.status.success() {
                        Ok(out.join("report.html"))
                    } else {
                        let err = String::from_utf8_lossy(&o.stderr);
                        Err(err.lines().last().unwrap_or("compare failed").to_string())
                    }
                });
            let _ = tx.send(result);
        });
        self.compare = Some(rx);
        self.panel.status = "compare: running (reference + metrics)…".into();
    }

    fn poll_compare(&mut self) {
        let Some(rx) = &self.compare else {
            return;
        };
        match rx.try_recv() {
            Ok(Ok(report)) => {
                self.panel.status = format!("compare: {}", report.display());
                open_file(&report);
                self.compare = None;
            }
            Ok(Err(e)) => {
                self.panel.status = format!("compare: {e}");
                self.compare = None;
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => self.compare = None,
        }
    }
}

/// AOVs `compare` measures.
fn compare_aovs() -> [&'static str; 6] {
    [
        "ao",
        "env-irradiance",
        "light-irradiance",
        "indirect-irradiance",
        "diffuse",
        "lambertian",
    ]
}

fn present_mode(vsync: bool) -> wgpu::PresentMode {
    if vsync {
        wgpu::PresentMode::AutoVsync
    } else {
        wgpu::PresentMode::AutoNoVsync
    }
}

fn unix_seconds() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

/// Opens a file with the desktop's default application (best effort).
fn open_file(path: &std::path::Path) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else {
        "xdg-open"
    };
    let _ = std::process::Command::new(opener)
        .arg(path)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
}

//! The viewer's interface (egui): side panel with every control, the 3D view with camera input
//! and the A/B divider. It only *proposes* changes ([`Change`]); the session validates them.

use super::camera_control;
use super::session::{Change, Session, Side};
use nearfield_render::Tonemap;
use nearfield_render::technique;
use std::collections::VecDeque;

mod setting;

/// Render resolutions offered besides following the window.
const SIZES: &[(u32, u32)] = &[
    (320, 180),
    (640, 360),
    (960, 540),
    (1280, 720),
    (1600, 900),
    (1920, 1080),
];
const BUILTINS: &[&str] = &["cornell", "boxes", "city", "plane", "wall", "closed-box"];

/// What the window should do besides applying changes.
#[derive(Default)]
pub struct Requests {
    pub changes: Vec<Change>,
    pub screenshot: bool,
    pub compare: bool,
    pub vsync: Option<bool>,
}

/// Interface state that is not part of the session.
pub struct Panel {
    pub frame_ms: VecDeque<f32>,
    pub status: String,
    pub fly: bool,
    pub follow_window: bool,
    pub vsync: bool,
    /// Which side's settings the panel edits.
    editing: Side,
    scene_text: String,
    env_text: String,
    camera_path: String,
    dragging_divider: bool,
    /// Slider values being dragged, applied on release: (side, key, value).
    pending: Option<(Side, &'static str, f32)>,
}

impl Panel {
    pub fn new(session: &Session, vsync: bool) -> Self {
        Panel {
            frame_ms: VecDeque::new(),
            status: String::new(),
            fly: false,
            follow_window: false,
            vsync,
            editing: Side::A,
            scene_text: session.scene_name.clone(),
            env_text: session.env_name.clone(),
            camera_path: "camera.json".into(),
            dragging_divider: false,
            pending: None,
        }
    }

    pub fn record_frame_time(&mut self, ms: f32) {
        self.frame_ms.push_back(ms);
        while self.frame_ms.len() > 240 {
            self.frame_ms.pop_front();
        }
    }

    /// Builds the interface for one frame; `view` is the display image's texture.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        session: &Session,
        view: egui::TextureId,
        dt: f32,
    ) -> Requests {
        let mut req = Requests::default();
        egui::Panel::left("controls")
            .default_size(330.0)
            .resizable(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui, session, &mut req));
            });
        egui::CentralPanel::no_frame().show(ui, |ui| self.view(ui, session, view, dt, &mut req));
        req
    }

    fn controls(&mut self, ui: &mut egui::Ui, s: &Session, req: &mut Requests) {
        ui.heading("nearfield");
        ui.small(s.adapter());
        self.timings(ui, s);
        ui.separator();

        self.technique_controls(ui, s, req);
        ui.separator();
        self.display_controls(ui, s, req);
        ui.separator();
        self.scene_controls(ui, s, req);
        ui.separator();
        self.camera_controls(ui, s, req);
    }

    /// The technique of the side being edited (A, or B when the view is split): its name, its
    /// quality presets and its settings.
    fn technique_controls(&mut self, ui: &mut egui::Ui, s: &Session, req: &mut Requests) {
        // Techniques: A, and B when the view is split.
        let mut split = s.split.is_some();
        ui.horizontal(|ui| {
            if ui.checkbox(&mut split, "A/B split").changed() {
                req.changes.push(Change::Split(split.then_some(0.5)));
            }
            if split {
                ui.selectable_value(&mut self.editing, Side::A, "edit A");
                ui.selectable_value(&mut self.editing, Side::B, "edit B");
            } else {
                self.editing = Side::A;
            }
        });
        let side = self.editing;
        let state = s.technique(side);
        egui::ComboBox::from_id_salt("technique")
            .selected_text(format!("{}: {}", side_name(side), state.name()))
            .show_ui(ui, |ui| {
                for d in technique::REGISTRY {
                    if ui
                        .selectable_label(d.name == state.name(), d.name)
                        .on_hover_text(d.summary)
                        .clicked()
                        && d.name != state.name()
                    {
                        req.changes.push(Change::Method(side, d.name.into()));
                    }
                }
            });
        if !state.desc.presets.is_empty() {
            ui.horizontal(|ui| {
                ui.label("quality");
                let current = state.matching_preset();
                for p in state.desc.presets {
                    if ui
                        .selectable_label(current == Some(p.name), p.name)
                        .clicked()
                    {
                        req.changes.push(Change::Preset(side, p.name.into()));
                    }
                }
            });
        }
        egui::CollapsingHeader::new("settings")
            .default_open(true)
            .show(ui, |ui| {
                // A setting of the family that this technique ignores (hbil's `fresnel` on gtao)
                // is not shown.
                for (setting, (key, value)) in state.desc.settings.iter().zip(&state.values) {
                    if setting.applies(state.desc.name) {
                        self.setting(ui, side, setting, key, value, req);
                    }
                }
                if state.desc.settings.is_empty() {
                    ui.label("(no settings)");
                }
            });
    }

    /// What is shown, at which exposure, tone mapping and size.
    fn display_controls(&mut self, ui: &mut egui::Ui, s: &Session, req: &mut Requests) {
        // What is shown.
        egui::ComboBox::from_id_salt("aov")
            .selected_text(format!("image: {}", s.aov))
            .show_ui(ui, |ui| {
                for name in s.image_names() {
                    let current = name.strip_prefix("extra:").unwrap_or(&name) == s.aov;
                    if ui.selectable_label(current, &name).clicked() {
                        req.changes.push(Change::Aov(name));
                    }
                }
            });
        let mut exposure = s.settings.exposure;
        if ui
            .add(egui::Slider::new(&mut exposure, -20.0..=20.0).text("exposure (EV)"))
            .changed()
        {
            req.changes.push(Change::Exposure(exposure));
        }
        egui::ComboBox::from_id_salt("tonemap")
            .selected_text(format!("tonemap: {}", tonemap_name(s.settings.tonemap)))
            .show_ui(ui, |ui| {
                for name in Tonemap::NAMES {
                    if ui.selectable_label(false, *name).clicked() {
                        req.changes.push(Change::Tonemap(name.to_string()));
                    }
                }
            });
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.follow_window, "size follows window");
        });
        if !self.follow_window {
            let (w, h) = s.settings.size;
            egui::ComboBox::from_id_salt("size")
                .selected_text(format!("resolution: {w}×{h}"))
                .show_ui(ui, |ui| {
                    for &(sw, sh) in SIZES {
                        if ui
                            .selectable_label((sw, sh) == (w, h), format!("{sw}×{sh}"))
                            .clicked()
                        {
                            req.changes.push(Change::Size(sw, sh));
                        }
                    }
                });
        }
        if ui.checkbox(&mut self.vsync, "vsync").changed() {
            req.vsync = Some(self.vsync);
        }
    }

    /// The scene, the environment, the far field and the lights.
    fn scene_controls(&mut self, ui: &mut egui::Ui, s: &Session, req: &mut Requests) {
        // Scene and environment.
        ui.horizontal(|ui| {
            ui.label("scene");
            ui.text_edit_singleline(&mut self.scene_text);
            if ui.button("load").clicked() {
                req.changes
                    .push(Change::Scene(self.scene_text.trim().to_string()));
            }
        });
        ui.horizontal_wrapped(|ui| {
            for b in BUILTINS {
                if ui.small_button(*b).clicked() {
                    self.scene_text = format!("builtin:{b}");
                    req.changes.push(Change::Scene(self.scene_text.clone()));
                }
            }
        });
        ui.horizontal(|ui| {
            ui.label("environment");
            ui.text_edit_singleline(&mut self.env_text);
            if ui.button("load").clicked() {
                req.changes
                    .push(Change::Env(self.env_text.trim().to_string()));
            }
        });
        ui.horizontal(|ui| {
            for e in ["sky", "constant:1,1,1"] {
                if ui.small_button(e).clicked() {
                    self.env_text = e.into();
                    req.changes.push(Change::Env(e.into()));
                }
            }
        });
        let mut intensity = s.env_intensity;
        if ui
            .add(
                egui::Slider::new(&mut intensity, 0.0..=64.0)
                    .logarithmic(true)
                    .text("intensity"),
            )
            .changed()
        {
            req.changes.push(Change::EnvIntensity(intensity));
        }
        // The far field: the sky, or the probe volume (baked in the background after a change).
        ui.horizontal(|ui| {
            ui.label("far field");
            for (volume, name) in [(false, "sky"), (true, "volume")] {
                if ui.selectable_label(s.far_volume == volume, name).clicked()
                    && s.far_volume != volume
                {
                    req.changes.push(Change::Far(name.into()));
                }
            }
            match (s.bake_progress(), s.volume_probes()) {
                (Some(f), _) => {
                    ui.label(format!("baking {:.0} %", f * 100.0));
                }
                (None, Some((n, active))) if s.far_volume => {
                    ui.label(format!("{active} of {n} probes"));
                }
                _ => {}
            }
        });
        let mut rotation = s.env_rotation_deg;
        if ui
            .add(egui::Slider::new(&mut rotation, 0.0..=360.0).text("rotation (°)"))
            .changed()
        {
            req.changes.push(Change::EnvRotation(rotation));
        }
        let lights = s
            .renderer(Side::A)
            .map(|r| r.lights().to_vec())
            .unwrap_or_default();
        for (i, light) in lights.iter().enumerate() {
            let mut on = s.renderer(Side::A).is_some_and(|r| r.light_enabled(i));
            let label = format!("light {i} ({})", light_kind(light));
            if ui.checkbox(&mut on, label).changed() {
                req.changes.push(Change::Light(i, on));
            }
        }
    }

    /// The camera, the screenshot and `compare` of this view.
    fn camera_controls(&mut self, ui: &mut egui::Ui, s: &Session, req: &mut Requests) {
        // Camera.
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.fly, "fly (WASD, Q/E)");
            if ui.button("frame scene (F)").clicked() {
                req.changes.push(Change::FrameScene);
            }
        });
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut self.camera_path);
        });
        ui.horizontal(|ui| {
            let path = std::path::PathBuf::from(self.camera_path.trim());
            if ui.button("save camera").clicked() {
                req.changes.push(Change::SaveCamera(path.clone()));
            }
            if ui.button("load camera").clicked() {
                req.changes.push(Change::LoadCamera(path));
            }
        });
        // The camera path: recorded frame by frame into the file named above with .json.
        ui.horizontal(|ui| match &s.recording {
            Some(r) => {
                if ui.button("stop path").clicked() {
                    req.changes.push(Change::StopPath);
                }
                ui.label(format!("recording {} frames", r.frames()));
            }
            None => {
                let path =
                    std::path::PathBuf::from(self.camera_path.trim()).with_extension("path.json");
                if ui.button("record path").clicked() {
                    req.changes.push(Change::RecordPath(path.clone()));
                }
                ui.small(format!("into {}", path.display()));
            }
        });
        let c = s.camera;
        ui.small(format!(
            "eye {:.3},{:.3},{:.3}  target {:.3},{:.3},{:.3}  fov {:.1}°",
            c.eye.x,
            c.eye.y,
            c.eye.z,
            c.target.x,
            c.target.y,
            c.target.z,
            c.yfov.to_degrees()
        ));
        ui.separator();
        ui.horizontal(|ui| {
            if ui.button("screenshot (P)").clicked() {
                req.screenshot = true;
            }
            if ui
                .button("compare this view")
                .on_hover_text("runs `nearfield compare` on this camera and opens its report")
                .clicked()
            {
                req.compare = true;
            }
        });
        if !self.status.is_empty() {
            ui.label(&self.status);
        }
    }

    fn timings(&self, ui: &mut egui::Ui, s: &Session) {
        let last = self.frame_ms.back().copied().unwrap_or(0.0);
        let mean = if self.frame_ms.is_empty() {
            0.0
        } else {
            self.frame_ms.iter().sum::<f32>() / self.frame_ms.len() as f32
        };
        ui.label(format!(
            "frame {last:.1} ms (mean {mean:.1} ms, {:.0} fps)",
            1000.0 / mean.max(1e-3)
        ));
        // Rolling plot of the frame time.
        let (rect, _) =
            ui.allocate_exact_size(egui::vec2(ui.available_width(), 48.0), egui::Sense::hover());
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, egui::Color32::from_gray(24));
        let max = self.frame_ms.iter().copied().fold(1.0f32, f32::max);
        let n = self.frame_ms.len().max(2) as f32;
        let points: Vec<egui::Pos2> = self
            .frame_ms
            .iter()
            .enumerate()
            .map(|(i, &ms)| {
                egui::pos2(
                    rect.left() + rect.width() * i as f32 / (n - 1.0),
                    rect.bottom() - rect.height() * ms / max,
                )
            })
            .collect();
        painter.add(egui::Shape::line(
            points,
            egui::Stroke::new(1.0, egui::Color32::LIGHT_GREEN),
        ));
        painter.text(
            rect.left_top(),
            egui::Align2::LEFT_TOP,
            format!("{max:.0} ms"),
            egui::FontId::monospace(10.0),
            egui::Color32::GRAY,
        );
        for (side, t) in [(Side::A, &s.timings.0), (Side::B, &s.timings.1)] {
            if t.is_empty() {
                continue;
            }
            let total = nearfield_render::profiler::frame_total(t);
            egui::CollapsingHeader::new(format!(
                "GPU {}: {total:.2} ms ({})",
                side_name(side),
                s.technique(side).name()
            ))
            .id_salt(("gpu", side_name(side)))
            .show(ui, |ui| {
                for (name, ms) in t {
                    ui.monospace(format!("{name:<22} {ms:7.3} ms"));
                }
            });
        }
        if s.timings.0.is_empty() {
            ui.small("no timestamp queries on this adapter: GPU timings unavailable");
        }
    }

    fn view(
        &mut self,
        ui: &mut egui::Ui,
        s: &Session,
        view: egui::TextureId,
        dt: f32,
        req: &mut Requests,
    ) {
        let avail = ui.available_size();
        let ppp = ui.ctx().pixels_per_point();
        if self.follow_window {
            let w = ((avail.x * ppp) as u32).clamp(16, nearfield_render::targets::MAX_SIZE);
            let h = ((avail.y * ppp) as u32).clamp(16, nearfield_render::targets::MAX_SIZE);
            if (w, h) != s.settings.size {
                req.changes.push(Change::Size(w, h));
            }
        }
        // The image at one texel per physical pixel, scaled down to fit when larger.
        let (w, h) = s.display.size();
        let native = egui::vec2(w as f32, h as f32) / ppp;
        let scale = (avail.x / native.x).min(avail.y / native.y).min(1.0);
        let size = native * scale;
        // Its corner on the physical pixel grid, so that texels land on pixels unfiltered.
        let corner = ((ui.max_rect().center() - size / 2.0) * ppp).round() / ppp;
        let rect = egui::Rect::from_min_size(corner, size);
        let response = ui.put(
            rect,
            egui::Image::new((view, size)).sense(egui::Sense::click_and_drag()),
        );
        let image_height = h as f32;
        let px_per_point = w as f32 / size.x.max(1.0);

        // The A/B divider: grab it within 6 points.
        if let Some(f) = s.split {
            let x = rect.left() + f * rect.width();
            if response.drag_started()
                && let Some(p) = response.interact_pointer_pos()
            {
                self.dragging_divider = (p.x - x).abs() < 6.0;
            }
            if response.hovered()
                && let Some(p) = response.hover_pos()
                && (p.x - x).abs() < 6.0
            {
                ui.ctx().set_cursor_icon(egui::CursorIcon::ResizeHorizontal);
            }
            if self.dragging_divider && response.dragged() {
                if let Some(p) = response.interact_pointer_pos() {
                    let f = ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0);
                    req.changes.push(Change::Split(Some(f)));
                }
                return;
            }
        }
        if !response.dragged() {
            self.dragging_divider = false;
        }

        let mut camera = s.camera;
        let delta = response.drag_delta() * px_per_point;
        if self.fly {
            let look = if response.dragged_by(egui::PointerButton::Primary) {
                (delta.x, delta.y)
            } else {
                (0.0, 0.0)
            };
            let mut mv = glam::Vec3::ZERO;
            if !ui.ctx().egui_wants_keyboard_input() {
                ui.input(|i| {
                    for (key, d) in [
                        (egui::Key::W, glam::Vec3::Z),
                        (egui::Key::S, -glam::Vec3::Z),
                        (egui::Key::D, glam::Vec3::X),
                        (egui::Key::A, -glam::Vec3::X),
                        (egui::Key::E, glam::Vec3::Y),
                        (egui::Key::Q, -glam::Vec3::Y),
                    ] {
                        if i.key_down(key) {
                            mv += d;
                        }
                    }
                    if i.modifiers.shift {
                        mv *= 4.0;
                    }
                });
            }
            let speed = 0.5 * s.scene.bounds().radius().max(0.1);
            if look != (0.0, 0.0) || mv != glam::Vec3::ZERO {
                camera = camera_control::fly(&camera, look, mv, speed, dt);
            }
        } else if response.dragged_by(egui::PointerButton::Primary) {
            camera = camera_control::orbit(&camera, delta.x, delta.y);
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
        {
            camera = camera_control::pan(&camera, delta.x, delta.y, image_height);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                camera = camera_control::zoom(&camera, scroll / 50.0);
            }
        }
        if !ui.ctx().egui_wants_keyboard_input() {
            ui.input(|i| {
                if i.key_pressed(egui::Key::F) {
                    req.changes.push(Change::FrameScene);
                }
                if i.key_pressed(egui::Key::P) || i.key_pressed(egui::Key::F12) {
                    req.screenshot = true;
                }
            });
        }
        if camera != s.camera {
            req.changes.push(Change::Camera(camera));
        }
    }
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::A => "A",
        Side::B => "B",
    }
}

fn tonemap_name(t: Tonemap) -> &'static str {
    Tonemap::NAMES[t.index() as usize]
}

fn light_kind(l: &nearfield_scene::Light) -> &'static str {
    match l.kind {
        nearfield_scene::LightKind::Directional { angular_radius, .. } if angular_radius > 0.0 => {
            "the environment's sun"
        }
        nearfield_scene::LightKind::Directional { .. } => "directional",
        nearfield_scene::LightKind::Point { .. } => "point",
        nearfield_scene::LightKind::Spot { .. } => "spot",
    }
}

//! How each change of [`super::Change`] reaches the renderers.

use super::{Session, Side, TechniqueState, env_name};
use nearfield_render::far::FarMode;
use nearfield_render::technique::Spec;
use nearfield_render::{Aov, Renderer, Tonemap};
use nearfield_scene::{EnvSource, Environment, SceneSource};

impl Session {
    pub(super) fn set_aov(&mut self, name: String) -> Result<(), String> {
        let name = name.strip_prefix("extra:").unwrap_or(&name).to_string();
        let known =
            Aov::parse(&name).is_some() || self.renderer_a.extra_names().contains(&name.as_str());
        if !known {
            return Err(format!(
                "aov {name}: unknown (known: {})",
                self.image_names().join(", ")
            ));
        }
        self.aov = name;
        Ok(())
    }

    pub(super) fn resize(&mut self, w: u32, h: u32) -> Result<(), String> {
        crate::options::parse_size(&format!("{w}x{h}")).map_err(|e| e.to_string())?;
        let old = self.settings.size;
        self.renderer_a.resize((w, h)).map_err(|e| e.to_string())?;
        if let Some(b) = &mut self.renderer_b
            && let Err(e) = b.resize((w, h))
        {
            let _ = self.renderer_a.resize(old);
            return Err(e.to_string());
        }
        self.settings.size = (w, h);
        self.display.resize(&self.ctx.device, (w, h));
        Ok(())
    }

    pub(super) fn set_env(&mut self, name: String) -> Result<(), String> {
        let env = self.load_env(&name)?;
        self.renderer_a
            .set_environment(&env)
            .map_err(|e| e.to_string())?;
        if let Some(b) = &mut self.renderer_b {
            b.set_environment(&env).map_err(|e| e.to_string())?;
        }
        self.env_name = name;
        self.refresh_far()
    }

    pub(super) fn set_env_intensity(&mut self, k: f32) -> Result<(), String> {
        if !(k.is_finite() && (0.0..=1e6).contains(&k)) {
            return Err(format!("env-intensity {k}: must be in 0..=1e6"));
        }
        self.env_intensity = k;
        self.for_each_renderer(|r| r.set_environment_intensity(k));
        self.refresh_far()
    }

    pub(super) fn set_env_rotation(&mut self, deg: f32) -> Result<(), String> {
        if !deg.is_finite() {
            return Err("env-rotation: must be finite".into());
        }
        self.env_rotation_deg = deg.rem_euclid(360.0);
        let rad = self.env_rotation_deg.to_radians();
        self.for_each_renderer(|r| r.set_environment_rotation(rad));
        self.refresh_far()
    }

    pub(super) fn set_exposure(&mut self, ev: f32) -> Result<(), String> {
        if !(ev.is_finite() && (-20.0..=20.0).contains(&ev)) {
            return Err(format!("exposure {ev}: must be in −20..=20"));
        }
        self.settings.exposure = ev;
        let t = self.settings.tonemap;
        self.for_each_renderer(|r| r.set_post(ev, t));
        Ok(())
    }

    pub(super) fn set_tonemap(&mut self, name: String) -> Result<(), String> {
        let t = Tonemap::parse(&name).ok_or_else(|| {
            format!(
                "tonemap {name}: unknown (known: {})",
                Tonemap::NAMES.join(", ")
            )
        })?;
        self.settings.tonemap = t;
        let ev = self.settings.exposure;
        self.for_each_renderer(|r| r.set_post(ev, t));
        Ok(())
    }

    pub(super) fn set_light(&mut self, i: usize, on: bool) -> Result<(), String> {
        let count = self.renderer_a.lights().len();
        if i >= count {
            return Err(format!(
                "light {i}: the frame has {count} light(s) (the scene's, then the environment's sun)"
            ));
        }
        self.for_each_renderer(|r| r.set_light_enabled(i, on));
        self.refresh_far()
    }

    pub(super) fn split(&mut self, f: f32) -> Result<(), String> {
        if !(f.is_finite() && (0.0..=1.0).contains(&f)) {
            return Err(format!("split {f}: must be off or in 0..=1"));
        }
        if self.renderer_b.is_none() {
            self.renderer_b = Some(self.new_renderer(&self.b)?);
        }
        self.split = Some(f);
        Ok(())
    }

    pub(super) fn set_far_mode(&mut self, mode: String) -> Result<(), String> {
        self.far_volume = match mode.as_str() {
            "volume" => true,
            "sky" => false,
            _ => return Err(format!("far {mode}: expected sky or volume")),
        };
        self.refresh_far()
    }

    pub(super) fn for_each_renderer(&mut self, mut f: impl FnMut(&mut Renderer)) {
        f(&mut self.renderer_a);
        if let Some(b) = &mut self.renderer_b {
            f(b);
        }
    }

    pub(super) fn set_technique(
        &mut self,
        side: Side,
        mut state: TechniqueState,
    ) -> Result<(), String> {
        state.follow_far(self.renderer_a.far_mode() == FarMode::Volume);
        let renderer = match side {
            Side::A => Some(&mut self.renderer_a),
            Side::B => self.renderer_b.as_mut(),
        };
        if let Some(r) = renderer {
            r.set_technique(state.name(), &state.params())
                .map_err(|e| e.to_string())?;
        }
        match side {
            Side::A => {
                self.a = state;
                self.keep_image_valid();
            }
            Side::B => self.b = state,
        }
        Ok(())
    }

    pub(super) fn load_env(&self, name: &str) -> Result<Environment, String> {
        let source = EnvSource::parse(name).map_err(|e| e.to_string())?;
        let (mut env, _) = source.load_split(self.sun).map_err(|e| e.to_string())?;
        env.intensity = self.env_intensity;
        env.rotation = self.env_rotation_deg.to_radians();
        Ok(env)
    }

    /// A renderer of `state` over the session's scene, environment and far field, its lights
    /// switched as side A's.
    pub(super) fn new_renderer(&self, state: &TechniqueState) -> Result<Renderer, String> {
        let env = self.load_env(&self.env_name)?;
        let volume = self
            .volume
            .as_ref()
            .filter(|_| self.far_volume)
            .map(|(_, v)| v.as_ref());
        let technique = Spec::resolve(state.name(), &state.params()).map_err(|e| e.to_string())?;
        let mut r = Renderer::new(
            &self.ctx,
            &self.scene,
            &env,
            volume,
            self.camera,
            &technique,
            self.settings,
        )
        .map_err(|e| e.to_string())?;
        for i in 0..self.renderer_a.lights().len() {
            r.set_light_enabled(i, self.renderer_a.light_enabled(i));
        }
        Ok(r)
    }

    /// Loads a scene; the environment and the camera become the scene's own.
    pub(super) fn load_scene(&mut self, name: &str) -> Result<(), String> {
        let scene = SceneSource::parse(name).load().map_err(|e| e.to_string())?;
        let env_name = env_name(&scene.default_env);
        let env = self.load_env(&env_name)?;
        let camera = scene.default_camera();
        // The old renderers stay until the new ones exist, so a failure changes nothing.
        let a = self.a.clone();
        let make = |state: &TechniqueState| {
            let technique =
                Spec::resolve(state.name(), &state.params()).map_err(|e| e.to_string())?;
            Renderer::new(
                &self.ctx,
                &scene,
                &env,
                None,
                camera,
                &technique,
                self.settings,
            )
            .map_err(|e| e.to_string())
        };
        let new_a = make(&a)?;
        let new_b = match self.renderer_b {
            Some(_) => Some(make(&self.b)?),
            None => None,
        };
        self.renderer_a = new_a;
        self.renderer_b = new_b;
        self.scene = scene;
        self.scene_name = name.to_string();
        self.env_name = env_name;
        self.camera = camera;
        self.keep_image_valid();
        Ok(())
    }
}

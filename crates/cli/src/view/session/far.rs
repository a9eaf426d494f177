//! The viewer's far field: the probe volume of the scene as it is now (environment, lights),
//! baked in a background thread or taken from the cache, handed to every renderer when ready.

use super::Session;
use anyhow::Result;
use nearfield_reference::bake::Monitor;
use nearfield_scene::probes::ProbeVolume;
use std::sync::Arc;

/// A bake under way in the background: what it is for ([`Session::far_key`]), how far it is,
/// and the thread.
pub(super) struct Bake {
    pub(super) key: String,
    pub(super) monitor: Arc<Monitor>,
    pub(super) thread: std::thread::JoinHandle<Result<ProbeVolume, String>>,
}

impl Session {
    /// What the volume must be baked for now: the scene, the environment (intensity and rotation
    /// too) and which lights are on.
    pub(super) fn far_key(&self) -> String {
        let lights: String = (0..self.renderer_a.lights().len())
            .map(|i| {
                if self.renderer_a.light_enabled(i) {
                    '1'
                } else {
                    '0'
                }
            })
            .collect();
        format!(
            "{}|{}|{}|{}|{lights}",
            self.scene_name, self.env_name, self.env_intensity, self.env_rotation_deg
        )
    }

    /// After a change the far field may depend on: with the sky, every renderer drops its volume;
    /// with the volume, one that matches the session is used, or baked in the background (the
    /// renderers keep the old one until the new one is ready).
    pub(super) fn refresh_far(&mut self) -> Result<(), String> {
        if !self.far_volume {
            if let Some(b) = self.bake.take() {
                b.monitor
                    .cancel
                    .store(true, std::sync::atomic::Ordering::Relaxed);
            }
            self.volume = None;
            return self.set_far_field(None);
        }
        let key = self.far_key();
        if let Some((k, v)) = &self.volume
            && *k == key
        {
            let v = v.clone();
            return self.set_far_field(Some(&v));
        }
        if self.bake.as_ref().is_some_and(|b| b.key == key) {
            return Ok(());
        }
        if let Some(b) = self.bake.take() {
            b.monitor
                .cancel
                .store(true, std::sync::atomic::Ordering::Relaxed);
        }
        // What the bake sees: the scene's lights that are on, the sun if it is on.
        let lights = self.renderer_a.lights().len();
        let scene_lights = self.scene.lights.len();
        // The bake leaves dynamic meshes out (`--dynamic`, `--add`).
        let mut scene = self.scene.baked_part();
        scene.lights = (0..scene_lights)
            .filter(|&i| self.renderer_a.light_enabled(i))
            .map(|i| self.scene.lights[i])
            .collect();
        let mut env = self.load_env(&self.env_name)?;
        if lights > scene_lights && !self.renderer_a.light_enabled(lights - 1) {
            env.sun = None;
        }
        let settings = self.grid.settings_for(&scene).map_err(|e| e.to_string())?;
        let monitor = Arc::new(Monitor::default());
        let (scene_name, env_name) = (self.scene_name.clone(), self.env_name.clone());
        let m = monitor.clone();
        let thread = std::thread::spawn(move || {
            let input = crate::far::BakeInput {
                scene_name: &scene_name,
                scene: &scene,
                env_name: &env_name,
                env: &env,
            };
            crate::far::baked_from(&input, &settings, false, false, Some(&m))
                .map(|(v, _)| v)
                .map_err(|e| e.to_string())
        });
        self.bake = Some(Bake {
            key,
            monitor,
            thread,
        });
        Ok(())
    }

    /// Every renderer's far field.
    pub(super) fn set_far_field(&mut self, volume: Option<&ProbeVolume>) -> Result<(), String> {
        self.renderer_a
            .set_far_field(volume)
            .map_err(|e| e.to_string())?;
        if let Some(b) = &mut self.renderer_b {
            b.set_far_field(volume).map_err(|e| e.to_string())?;
        }
        self.a.follow_far(volume.is_some());
        self.b.follow_far(volume.is_some());
        Ok(())
    }

    /// Takes a finished background bake into the renderers; `wait` blocks until it finishes.
    pub(super) fn poll_bake(&mut self, wait: bool) -> Result<(), String> {
        let finished = self.bake.as_ref().is_some_and(|b| b.thread.is_finished());
        if !(finished || (wait && self.bake.is_some())) {
            return Ok(());
        }
        let b = self.bake.take().expect("a bake");
        let v = b
            .thread
            .join()
            .map_err(|_| "the background bake failed".to_string())??;
        eprintln!(
            "nearfield: baked the probe volume in the background ({} probes, {} active)",
            v.probes.len(),
            v.active_count()
        );
        let v = Arc::new(v);
        self.set_far_field(Some(&v))?;
        self.volume = Some((b.key, v));
        Ok(())
    }

    /// Waits for a background bake (the script's `bake-wait`).
    pub fn wait_bake(&mut self) -> Result<(), String> {
        self.poll_bake(true)
    }

    /// How far the background bake is (0..=1), when one is under way.
    pub fn bake_progress(&self) -> Option<f32> {
        self.bake.as_ref().map(|b| b.monitor.fraction())
    }

    /// Probes of the volume in use, active ones.
    pub fn volume_probes(&self) -> Option<(usize, usize)> {
        self.volume
            .as_ref()
            .map(|(_, v)| (v.probes.len(), v.active_count()))
    }
}

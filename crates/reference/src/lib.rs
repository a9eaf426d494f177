//! nearfield's CPU ground truth: a BVH ray tracer (obvhs) that computes, for the pixels the GPU
//! shades, exactly the integrals that docs/src/aovs.md defines for each AOV, with a per-pixel
//! standard error. No wgpu: it shares only the scene model (`nearfield_scene`) with the renderer.
//!
//! Same camera model and pixel centres as the rasterizer (`Camera::primary_ray`), the same
//! environment lookup (`Environment::radiance`, bilinear, the lat-long convention of
//! docs/src/conventions.md), the same albedo (`Scene::base_color`: factor × bilinear
//! sRGB-decoded texture) and the same shading normals (see [`tracer`]). Hemisphere integrals use
//! cosine-weighted samples around the shading normal; directions below the geometric tangent
//! plane count as blocked (the surface itself is there).

pub mod bake;
pub mod cache;
pub mod env_sampling;
pub mod exr_io;
pub mod integrate;
pub mod irradiance;
pub mod lights;
pub mod sampling;
pub mod tracer;

use glam::Vec3;
use nearfield_scene::{Camera, Environment, Scene};
use rayon::prelude::*;

/// What the reference computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ReferenceAov {
    /// (1/π) ∫ V_R cos θ dω.
    Ao,
    /// (1/π) ∫ L_env V_R cos θ dω.
    EnvIrradiance,
    /// (1/π) Σ E_l with exact shadow rays.
    LightIrradiance,
    /// (1/π) ∫ (1 − V_R) L_o(x′) cos θ dω, one bounce.
    IndirectIrradiance,
    /// ρ × (env + light + indirect irradiance).
    Diffuse,
    /// Path-traced image (Lambertian, environment + lights + emission).
    Radiance,
    /// (1/π) ∫ V_R L_far cos θ dω: what arrives from beyond R, path-traced to full depth.
    FarIrradiance,
    /// Base colour ρ.
    Albedo,
    /// Shading normal.
    Normal,
    /// View depth (m).
    Depth,
}

impl ReferenceAov {
    pub const ALL: [ReferenceAov; 10] = [
        ReferenceAov::Ao,
        ReferenceAov::EnvIrradiance,
        ReferenceAov::LightIrradiance,
        ReferenceAov::IndirectIrradiance,
        ReferenceAov::Diffuse,
        ReferenceAov::Radiance,
        ReferenceAov::FarIrradiance,
        ReferenceAov::Albedo,
        ReferenceAov::Normal,
        ReferenceAov::Depth,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ReferenceAov::Ao => "ao",
            ReferenceAov::EnvIrradiance => "env-irradiance",
            ReferenceAov::LightIrradiance => "light-irradiance",
            ReferenceAov::IndirectIrradiance => "indirect-irradiance",
            ReferenceAov::Diffuse => "diffuse",
            ReferenceAov::Radiance => "radiance",
            ReferenceAov::FarIrradiance => "far-irradiance",
            ReferenceAov::Albedo => "albedo",
            ReferenceAov::Normal => "normal",
            ReferenceAov::Depth => "depth",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|a| a.name() == s)
    }

    /// Whether its value depends on the near-field radius R (the path tracer's radiance, the
    /// lights' irradiance and the G-buffer images do not).
    pub fn depends_on_radius(self) -> bool {
        matches!(
            self,
            ReferenceAov::Ao
                | ReferenceAov::EnvIrradiance
                | ReferenceAov::IndirectIrradiance
                | ReferenceAov::Diffuse
                | ReferenceAov::FarIrradiance
        )
    }

    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|a| a.name()).collect()
    }
}

/// What the senders x′ of `indirect-irradiance` emit (L_o of docs/src/aovs.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Senders {
    /// Their physical direct light: environment with the full shadow test, lights with shadows.
    #[default]
    Physical,
    /// For analysis: environment and lights without shadows at x′ (V ≡ 1).
    Unshadowed,
}

impl Senders {
    pub const NAMES: [&'static str; 2] = ["physical", "unshadowed"];

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "physical" => Some(Senders::Physical),
            "unshadowed" => Some(Senders::Unshadowed),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Settings of one reference render.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceSettings {
    pub aov: ReferenceAov,
    pub size: (u32, u32),
    /// Near-field radius R (m), > 0 or infinite; 0 means nothing is near (V_R = 1).
    pub radius: f32,
    /// Samples per pixel, ≥ 1.
    pub spp: u32,
    pub seed: u32,
    /// Path length limit for `radiance` (segments, camera segment included), ≥ 1.
    pub max_depth: u32,
    /// What the senders of `indirect-irradiance` (and `diffuse`) emit.
    pub senders: Senders,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        ReferenceSettings {
            aov: ReferenceAov::Ao,
            size: (512, 512),
            radius: f32::INFINITY,
            spp: 64,
            seed: 0,
            max_depth: 5,
            senders: Senders::Physical,
        }
    }
}

/// A reference image: value (rgb + coverage alpha), the standard error of the mean per channel,
/// and view depth (0 on background). Row 0 at the top.
#[derive(Clone, Debug)]
pub struct ReferenceImage {
    pub width: u32,
    pub height: u32,
    pub value: Vec<[f32; 4]>,
    pub stderr: Vec<[f32; 3]>,
    pub depth: Vec<f32>,
    /// Rays traced (primary + secondary), for throughput figures.
    pub rays: u64,
}

impl ReferenceImage {
    pub fn get(&self, x: u32, y: u32) -> [f32; 4] {
        self.value[(y * self.width + x) as usize]
    }
}

/// Result of one pixel.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelResult {
    pub value: Vec3,
    pub alpha: f32,
    pub stderr: Vec3,
    pub depth: f32,
    pub rays: u64,
}

/// Renders the reference for one AOV. `progress` shows a bar with ETA on stderr when it is a
/// terminal, else a plain line every few seconds. Results depend only on the inputs and settings, not on the thread count.
pub fn render(
    scene: &Scene,
    env: &Environment,
    camera: &Camera,
    settings: &ReferenceSettings,
    progress: bool,
) -> ReferenceImage {
    let ctx = integrate::Context::new(scene, env, camera, settings);
    render_rows(settings, progress, |x, y| ctx.pixel(x, y))
}

/// `far-irradiance` lit by a probe volume with the exact visibility V_R
/// ([`integrate::Context::volume_pixel`]): the volume measured alone.
pub fn render_volume_far(
    scene: &Scene,
    env: &Environment,
    camera: &Camera,
    settings: &ReferenceSettings,
    volume: &nearfield_scene::probes::ProbeVolume,
    progress: bool,
) -> ReferenceImage {
    let settings = ReferenceSettings {
        aov: ReferenceAov::FarIrradiance,
        ..*settings
    };
    let ctx = integrate::Context::new(scene, env, camera, &settings);
    render_rows(&settings, progress, |x, y| ctx.volume_pixel(x, y, volume))
}

fn render_rows(
    settings: &ReferenceSettings,
    progress: bool,
    pixel: impl Fn(u32, u32) -> PixelResult + Sync,
) -> ReferenceImage {
    let (w, h) = settings.size;
    let bar = nearfield_scene::progress::Progress::new(
        &format!("reference {}", settings.aov.name()),
        h as u64,
        "rows",
        progress,
    );
    let rows: Vec<Vec<PixelResult>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let row = (0..w).map(|x| pixel(x, y)).collect();
            bar.inc(1);
            row
        })
        .collect();
    bar.finish();
    let mut img = ReferenceImage {
        width: w,
        height: h,
        value: Vec::with_capacity((w * h) as usize),
        stderr: Vec::with_capacity((w * h) as usize),
        depth: Vec::with_capacity((w * h) as usize),
        rays: 0,
    };
    for p in rows.into_iter().flatten() {
        img.value.push([p.value.x, p.value.y, p.value.z, p.alpha]);
        img.stderr.push(p.stderr.into());
        img.depth.push(p.depth);
        img.rays += p.rays;
    }
    img
}

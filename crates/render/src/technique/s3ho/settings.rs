//! Settings of `s3ho` and `ssbn` (technique/s3ho).

use crate::declare_settings;
use crate::settings::TechniqueParams;
use crate::settings::denoise::{Denoise, SvgfSettings};
use crate::settings::layers::LayerSettings;
use crate::settings::sampling::Pattern;

declare_settings! {
    /// Settings of `s3ho` and `ssbn`.
    pub struct Settings {
        samples: u32 = "16", integer(1, 256), count, "", "directions per pixel";
        radius: f32 = "0.5", log(1e-6, 1e6), uniform, "m", "hemisphere radius d_max (`--radius`; finite)";
        steps: u32 = "2", integer(1, 16), count, "", "ray-marching points per direction (at λ·k/steps; 2 = the paper's); 16 by default with `layers` 2 or 4 (`layers::LAYERED_STEPS`)";
        lambda: f32 = "0", number(0, 1000), uniform, "", "smooth visibility 1 − 1/(1 + λd) for occluded directions (d: blocker distance); 0 = off";
        indirect: bool = "on", toggle, uniform("s3ho"), "", "the indirect extension, Eq. 5 (s3ho)";
        pattern: Pattern = "interleaved", choice, uniform, "", "sample sets: the chapter's, or the paper's 4×4 interleaved sets (as ssdo)";
        fade: f32 = "0.75", number(0, 1), uniform, "", "the blocker fade starts at `fade`·d_max";
        strength: f32 = "1", number(0, 16), uniform, "", "indirect strength";
        distance_clamp: f32 = "0.1", log(0, 1e6), uniform, "m", "smallest sender distance in 1/d²";
        denoise: Denoise = "bilateral", choice, denoiser, "", "`bilateral` s3ho: the paper's 8×8 geometry-aware bilateral filter on the coefficients, ssbn: bilateral blur of bent normal, cone and ao; `svgf` the shared spatio-temporal denoiser on the AOVs; `off` none";
    }
    flatten { layers: LayerSettings, svgf: SvgfSettings }
}

/// `quality` presets (shared with ssdo): directions per pixel.
pub use crate::settings::sampling::PRESETS;

impl Settings {
    /// Applies `--samples`, `--radius` and `--set` on top of the defaults.
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        crate::settings::apply(&mut s, params, &[])?;
        s.steps = crate::settings::layers::resolve_steps(params, s.layers.layers, s.steps);
        Ok(s)
    }
}

//! Settings of `s3ho` and `ssbn` (technique/s3ho).

use super::denoise::{Denoise, SvgfSettings};
use super::layers::LayerSettings;
use super::ssdo::Pattern;
use super::{Preset, TechniqueParams};
use crate::declare_settings;

declare_settings! {
    /// Settings of `s3ho` and `ssbn`.
    pub struct Settings {
        samples: u32 = "16", integer(1, 256), "", "directions per pixel";
        radius: f32 = "0.5", log(1e-6, 1e6), "m", "hemisphere radius d_max (`--radius`; finite)";
        steps: u32 = "2", integer(1, 16), "", "ray-marching points per direction (at λ·k/steps; 2 = the paper's); 16 by default with `layers` 2 or 4 (`layers::LAYERED_STEPS`)";
        lambda: f32 = "0", number(0, 1000), "", "smooth visibility 1 − 1/(1 + λd) for occluded directions (d: blocker distance); 0 = off";
        indirect: bool = "on", toggle, "", "the indirect extension, Eq. 5 (s3ho)";
        pattern: Pattern = "interleaved", choice, "", "sample sets: the chapter's, or the paper's 4×4 interleaved sets (as ssdo)";
        fade: f32 = "0.75", number(0, 1), "", "the blocker fade starts at `fade`·d_max";
        strength: f32 = "1", number(0, 16), "", "indirect strength";
        distance_clamp: f32 = "0.1", log(0, 1e6), "m", "smallest sender distance in 1/d²";
        denoise: Denoise = "bilateral", choice, "", "`bilateral` s3ho: the paper's 8×8 geometry-aware bilateral filter on the coefficients, ssbn: bilateral blur of bent normal, cone and ao; `svgf` the shared spatio-temporal denoiser on the AOVs; `off` none";
    }
    flatten { layers: LayerSettings, svgf: SvgfSettings }
}

/// `quality` presets (shared with ssdo): directions per pixel.
pub const PRESETS: &[Preset] = super::ssdo::PRESETS;

impl Settings {
    /// Applies `--samples`, `--radius` and `--set` on top of the defaults.
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        if let Some(n) = params.samples {
            s.samples = n;
        }
        if let Some(r) = params.radius {
            s.radius = r;
        }
        super::apply(&mut s, params, &[])?;
        s.steps = super::layers::resolve_steps(params, s.layers.layers, s.steps);
        super::check_sampling(s.samples, s.radius)?;
        Ok(s)
    }
}

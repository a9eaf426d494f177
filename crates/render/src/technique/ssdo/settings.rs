//! Settings of `ssao`, `ssdo`, `ssdo-vpl` and `instant-radiosity` (technique/ssdo).

use crate::settings::TechniqueParams;
use crate::settings::denoise::{Denoise, SvgfSettings};
use crate::settings::layers::LayerSettings;
pub use crate::settings::sampling::{PRESETS, Pattern};
use crate::vpl::MAX_VPLS;
use crate::{choice, declare_settings};

choice! {
    /// How the environment term is formed.
    pub enum Mode {
        /// Luminance-weighted visible fraction × SH irradiance (the chapter's visibility mode).
        Visibility = "visibility",
        /// Σ (1/π) L_in V cos θ Δω from the environment at `lod` (radiance mode).
        Radiance = "radiance",
    }
}

choice! {
    /// Where radiance mode's per-sample light L_in comes from (with `--far sky`; a probe volume
    /// gives its own radiance).
    pub enum SampleLight {
        /// The environment's order-3 SH radiance, the sum scaled per channel so that an
        /// unoccluded point gets the pre-convolved irradiance exactly (unbiased where nothing
        /// occludes; see technique/ssdo/mod.rs).
        Sh = "sh",
        /// The box-filtered map at mip `lod` (the chapter's blurred lookup).
        Mip = "mip",
    }
}

choice! {
    /// What part of the ray towards a light is tested in screen space.
    pub enum LightSegment {
        /// Length R, on top of the shadow map (paper Sec. 4, Fig. 6).
        Radius = "radius",
        /// The length the shadow map's bias hides (paper Sec. 5, Fig. 8–9).
        Bias = "bias",
    }
}

declare_settings! {
    /// Settings of `ssao` and `ssdo` (`--samples`, `--radius`, `--set key=value`).
    pub struct Settings {
        samples: u32 = "16", integer(1, 256), count, "", "directions per pixel N";
        steps: u32 = "1", integer(1, 16), count, "", "points tested per direction at λ·k/steps, the first occluded one decides (ray marching); 1 = the paper's single point at λ; 16 by default with `layers` 2 or 4 (one point frees what the ray cannot reach: `layers::LAYERED_STEPS`)";
        radius: f32 = "0.5", log(1e-6, 1e6), uniform, "m", "hemisphere radius R (`--radius`; finite)";
        mode: Mode = "visibility", choice, uniform("ssdo"), "", "`visibility`: luminance-weighted visible fraction × SH irradiance; `radiance`: Σ (1/π) L_in V cos θ Δω with Δω = 2π/N, L_in from the environment at `lod` (ssdo)";
        bounce: bool = "on", toggle, uniform("ssdo", "ssdo-vpl"), "", "one indirect bounce (ssdo)";
        pattern: Pattern = "interleaved", choice, uniform, "", "`chapter`: stratified elevation cos θ = 1 − α, golden-ratio azimuth 2π·α·(7N/9) + φ, φ from interleaved gradient noise, random λ; `interleaved`: the paper's M×N texture, 4×4 sets of N low-discrepancy samples, one set per pixel";
        sample_light: SampleLight = "sh", choice, uniform, "", "radiance mode's L_in: `sh` the environment's SH radiance; `mip` the box-filtered map at `lod` (the chapter's); a probe volume gives its own radiance";
        normalise: bool = "on", toggle, uniform, "", "radiance mode: each channel's sum divided by the same sum with V ≡ 1 and multiplied by the exact unoccluded irradiance (the pre-convolved map's, or the probe volume's), so an open point gets it exactly (the plane under the built-in sky with its sun in the map: 1.0016 of the reference; the plain sum: `sh` 0.95, `mip` 0.82–0.87); `off`: the paper's plain sum Σ (1/π) L_in V cos θ Δω";
        lod: f32 = "5", number(0, 16), uniform, "", "mip of the box-filtered environment read per sample (5: 32×16 for a 1k map): visibility mode's weights, and radiance mode's L_in with `sample_light=mip`";
        contrast: f32 = "1", number(0.1, 8), uniform("ssao", "ssdo"), "", "exponent on the visibility (ssdo) or on 1 − scale·S (ssao)";
        scale: f32 = "1", number(0, 4), uniform, "", "SSAO's scale on the occluded fraction S";
        strength: f32 = "1", number(0, 16), uniform, "", "bounce strength (the patch-area correction the paper leaves to the user)";
        distance_clamp: f32 = "0.1", log(0, 1e6), uniform, "m", "smallest sender distance used in 1/d²";
        fade: f32 = "0.75", number(0, 1), uniform, "", "the smooth-step fade of blockers starts at `fade`·R and ends at R";
        light_samples: u32 = "8", integer(0, 64), count("ssdo", "ssdo-vpl", "instant-radiosity"), "", "points on each light's segment (ssdo; ssdo-vpl, instant-radiosity: also per virtual point light); 0 turns screen-space light occlusion off";
        light_segment: LightSegment = "radius", choice, uniform, "", "`radius`: the segment P → P + R·l (paper Sec. 4); `bias`: P → P + b·l with b the length the light's shadow map cannot resolve (screen-space shadow correction, Sec. 5)";
        vpls: u32 = "64", integer(1, MAX_VPLS), count("ssdo-vpl", "instant-radiosity"), "", "virtual point lights (ssdo-vpl, instant-radiosity; draws of one texel merge)";
        vpl_map: u32 = "512", integer(128, 2048), structural("ssdo-vpl", "instant-radiosity"), "", "shadow-map side per virtual point light (ssdo-vpl, instant-radiosity)";
        rsm: u32 = "256", integer(16, 1024), structural("instant-radiosity"), "", "reflective-shadow-map side per light view (instant-radiosity)";
        vpl_clamp: f32 = "0.5", log(0, 1e6), uniform("instant-radiosity"), "m", "smallest distance in a virtual point light's 1/d² (instant-radiosity); with `bounce=on` it must be ≤ R, since the screen-space bounce adds back what it removes (the default becomes R where R is smaller)";
        denoise: Denoise = "bilateral", choice, denoiser, "", "`bilateral` geometry-aware blur of visibility, direct and indirect radiance; `svgf` the shared spatio-temporal denoiser on the AOVs; `off` none";
        blur_radius: u32 = "4", integer(0, 16), filter, "pixels", "blur half width (≥ 4 hides the 4×4 interleaving)";
        blur_depth: f32 = "0.01", log(1e-4, 10), filter, "", "tangent-plane distance, relative to view depth, at which a tap's weight falls by e";
        blur_normal: f32 = "8", number(0, 128), filter, "", "exponent on the normals' cosine in the blur";
    }
    flatten { layers: LayerSettings, svgf: SvgfSettings }
}

impl Settings {
    /// Applies `--samples`, `--radius` and `--set` on top of the defaults.
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        crate::settings::apply(&mut s, params, &[])?;
        s.steps = crate::settings::layers::resolve_steps(params, s.layers.layers, s.steps);
        Ok(s)
    }
}

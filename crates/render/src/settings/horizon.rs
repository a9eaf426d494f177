//! Settings of `gtao` and `hbil` (technique/horizon).

use super::denoise::{Denoise, SvgfSettings};
use super::{Preset, TechniqueParams};
use crate::{choice, declare_settings};

choice! {
    /// How last frame's pixels reach this frame.
    pub enum ReprojectMode {
        /// Forward: last frame's pixels move to their new place (depth-tested, atomics).
        Scatter = "scatter",
        /// Backward: this frame's pixels fetch through their motion vectors.
        Gather = "gather",
    }
}

choice! {
    /// Far-field estimate through the bent cone (hbil).
    pub enum Far {
        /// SH irradiance with the cone's reduced aperture (HBIL Sec. 2.2.4).
        Sh = "sh",
        /// Pre-convolved diffuse map at the bent normal × F0(ao) (HBIL Sec. 2.2.3).
        Envmap = "envmap",
        /// The environment integrated over every slice's visible arcs (directional; beyond the
        /// paper, see technique/horizon/mod.rs).
        Slices = "slices",
    }
}

choice! {
    /// How the bent cone's aperture follows from the (cosine-weighted) ao (hbil, `far=sh`).
    pub enum Aperture {
        /// cos α = 1 − ao (HBIL Eq. 12).
        Eq12 = "eq12",
        /// cos α = √(1 − ao): the cone whose cosine-weighted visibility is ao (see technique/horizon/mod.rs).
        Matched = "matched",
    }
}

choice! {
    /// Where the near-field radiance comes from (hbil).
    pub enum Source {
        /// Last frame's diffuse radiance, reprojected (bounces accumulate, HBIL Eq. 17); this
        /// frame's direct radiance on the first frame and after a cut.
        Previous = "previous",
        /// This frame's direct radiance every frame (exactly one bounce, L_o of docs/src/aovs.md).
        Direct = "direct",
    }
}

declare_settings! {
    /// Settings of `gtao` and `hbil` (`--samples` = steps, `--radius`, `--set key=value`).
    pub struct Settings {
        slices: u32 = "2", integer(1, 32), "", "slices per pixel S (with interleaving a 4×4 block covers 16·S directions)";
        steps: u32 = "16", integer(1, 128), "", "samples per side of a slice (`samples`, `--samples`)";
        radius: f32 = "0.5", log(1e-6, 1e6), "m", "near-field radius R (`--radius`; finite); only occluders within R count";
        interleaved: bool = "on", toggle, "", "4×4 deinterleaved quarter-resolution layers (HBIL Sec. 3.3)";
        reprojection: ReprojectMode = "scatter", choice, "", "hbil: `scatter` (forward, atomic depth test) then push/pull, or `gather` through motion vectors then push/pull";
        far: Far = "slices", choice, "", "hbil's far field: `sh` SH irradiance through the bent cone (Sec. 2.2.4); `envmap` pre-convolved diffuse map at the bent normal × F0(ao) (Sec. 2.2.3); `slices` the environment integrated over each slice's visible arcs";
        aperture: Aperture = "matched", choice, "", "hbil, `far=sh`: cone aperture `eq12` cos α = 1 − ao, or `matched` cos α = √(1 − ao)";
        source: Source = "previous", choice, "", "hbil's near-field radiance: `previous` last frame's diffuse radiance, reprojected (bounces add up, Eq. 17); `direct` this frame's direct radiance (exactly one bounce)";
        temporal: bool = "on", toggle, "", "running mean over frames, disocclusion-rejected";
        history: u32 = "32", integer(1, 1024), "", "frames in the running mean at most";
        fresnel: bool = "on", toggle, "", "hbil: (1 − F0) of the receiver on near-field light (Eq. 19)";
        falloff: f32 = "0.1", number(0, 1), "", "an occluder's rise fades out over the last `falloff`·R";
        step_power: f32 = "2", number(1, 4), "", "step distribution t_j ∝ ((j + ξ)/steps)^p (denser near the pixel)";
        max_pixels: f32 = "256", log(1, 8192), "pixels", "longest march (full resolution)";
        reject_a: f32 = "-0.1", number(-1, 1), "", "radiance rejection (HBIL Sec. 3.4): lower smoothstep edge on −n′·ω (< `reject_b`)";
        reject_b: f32 = "0.1", number(-1, 1), "", "radiance rejection: upper smoothstep edge";
        denoise: Denoise = "bilateral", choice, "", "`bilateral` geometry-aware blur of the raw results (merges a 4×4 block's directions) then the running mean; `svgf` the shared spatio-temporal denoiser on the AOVs; `off` raw results (with the running mean)";
        blur_radius: u32 = "4", integer(0, 16), "pixels", "blur half width (Gaussian σ = radius/2; 4 weighs a 4×4 block nearly evenly)";
        reject_depth: f32 = "0.02", log(1e-4, 1), "", "history/reprojection: largest distance from the current tangent plane, relative to view depth";
        reject_normal: f32 = "0.9", number(-1, 1), "", "history/reprojection: smallest cosine between the normals";
    }
    flatten { svgf: SvgfSettings }
}

/// `quality` presets: slices and steps.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "low",
        set: &[("slices", "1"), ("steps", "8")],
    },
    Preset {
        name: "medium",
        set: &[("slices", "2"), ("steps", "16")],
    },
    Preset {
        name: "high",
        set: &[("slices", "4"), ("steps", "16")],
    },
    Preset {
        name: "ultra",
        set: &[("slices", "8"), ("steps", "32")],
    },
];

impl Settings {
    /// Applies `--samples` (steps), `--radius` and `--set` on top of the defaults (`quality`
    /// was expanded by `technique::expand_presets` before).
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        if let Some(n) = params.samples {
            s.steps = n;
        }
        if let Some(r) = params.radius {
            s.radius = r;
        }
        super::apply(&mut s, params, &[("samples", "steps")])?;
        check_march(s.radius, s.steps, s.reject_a, s.reject_b)?;
        Ok(s)
    }
}

/// The checks the slice marches (gtao, hbil, vbgi) share: a finite radius, steps in range, and
/// the sender rejection's edges in order.
pub fn check_march(radius: f32, steps: u32, reject_a: f32, reject_b: f32) -> Result<(), String> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(format!(
            "radius {radius}: the slice march needs a finite radius > 0"
        ));
    }
    if !(1..=128).contains(&steps) {
        return Err(format!("steps {steps}: must be in 1..=128"));
    }
    if reject_a >= reject_b {
        return Err(format!(
            "reject_a {reject_a} must be below reject_b {reject_b}"
        ));
    }
    Ok(())
}

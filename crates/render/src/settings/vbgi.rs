//! Settings of `vbgi` (technique/vbgi): visibility-bitmask indirect lighting.

use super::denoise::{Denoise, SvgfSettings};
use super::horizon::{ReprojectMode, Source};
use super::{Preset, TechniqueParams};
use crate::{choice, declare_settings};

choice! {
    /// How thick the surface behind a sample is (the occluder covers the sectors between its
    /// front and its back).
    pub enum Thickness {
        /// The second depth layer (depth peeling): back depth − front depth per pixel; a pixel
        /// with nothing behind it is a solid to the far plane (a horizon, as gtao/hbil assume).
        Layer = "layer",
        /// `thickness_m` everywhere (what the peer implementations do).
        Constant = "constant",
        /// `thickness_ratio` × the sample's view depth, for engines without a second layer.
        Adaptive = "adaptive",
    }
}

choice! {
    /// vbgi's far field.
    pub enum VbgiFar {
        /// The environment through each unoccupied sector, cosine-weighted (directional).
        Sectors = "sectors",
        /// SH irradiance through the bent cone (aperture cos α = √(1 − ao)).
        Sh = "sh",
        /// The pre-convolved diffuse map at the bent normal × F0(ao).
        Envmap = "envmap",
    }
}

declare_settings! {
    /// Settings of `vbgi` (`--samples` = steps, `--radius`, `--set key=value`).
    pub struct Settings {
        slices: u32 = "2", integer(1, 32), "", "slices per pixel S (with interleaving a 4×4 block covers 16·S directions)";
        steps: u32 = "16", integer(1, 128), "", "samples per side of a slice (`samples`, `--samples`)";
        radius: f32 = "0.5", log(1e-6, 1e6), "m", "near-field radius R (`--radius`; finite); a sample counts when its front is within R";
        sectors: u32 = "32", values("8", "16", "32"), "", "sectors of a slice's half circle in its bitmask (a u32)";
        thickness: Thickness = "layer", choice, "", "an occluder's depth extent: `layer` from the second depth layer (depth peeling), `constant` `thickness_m`, `adaptive` `thickness_ratio` × view depth";
        thickness_m: f32 = "0.1", log(1e-4, 1e4), "m", "thickness with `thickness=constant`";
        thickness_ratio: f32 = "0.05", log(1e-4, 10), "", "thickness with `thickness=adaptive`, relative to the sample's view depth";
        interleaved: bool = "on", toggle, "", "4×4 deinterleaved quarter-resolution layers (HBIL Sec. 3.3)";
        reprojection: ReprojectMode = "scatter", choice, "", "`scatter` (forward, atomic depth test) then push/pull, or `gather` through motion vectors then push/pull";
        far: VbgiFar = "sectors", choice, "", "far field: `sectors` the environment through each unoccupied sector; `sh` SH irradiance through the bent cone; `envmap` pre-convolved map at the bent normal × F0(ao)";
        source: Source = "previous", choice, "", "near-field radiance: `previous` last frame's diffuse radiance, reprojected (bounces add up, HBIL Eq. 17); `direct` this frame's direct radiance (exactly one bounce)";
        temporal: bool = "on", toggle, "", "running mean over frames, disocclusion-rejected (in svgf with `denoise=svgf`)";
        history: u32 = "32", integer(1, 1024), "", "frames in the running mean at most";
        denoise: Denoise = "svgf", choice, "", "`svgf` the shared spatio-temporal denoiser; `bilateral` the horizon techniques' blur then their running mean; `off` raw results (with the running mean)";
        blur_radius: u32 = "4", integer(0, 16), "pixels", "blur half width with `denoise=bilateral`";
        fresnel: bool = "on", toggle, "", "(1 − F0) of the receiver on near-field light (HBIL Eq. 19)";
        step_power: f32 = "2", number(1, 4), "", "step distribution t_j ∝ ((j + ξ)/steps)^p (denser near the pixel)";
        max_pixels: f32 = "256", log(1, 8192), "pixels", "longest march (full resolution)";
        reject_a: f32 = "-0.1", number(-1, 1), "", "sender rejection (HBIL Sec. 3.4): lower smoothstep edge on −n′·ω (< `reject_b`)";
        reject_b: f32 = "0.1", number(-1, 1), "", "sender rejection: upper smoothstep edge";
        reject_depth: f32 = "0.02", log(1e-4, 1), "", "history/reprojection: largest distance from the current tangent plane, relative to view depth";
        reject_normal: f32 = "0.9", number(-1, 1), "", "history/reprojection: smallest cosine between the normals";
    }
    flatten { svgf: SvgfSettings }
}

/// `quality` presets: slices, steps and sectors.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "low",
        set: &[("slices", "1"), ("steps", "8"), ("sectors", "16")],
    },
    Preset {
        name: "medium",
        set: &[("slices", "2"), ("steps", "16"), ("sectors", "32")],
    },
    Preset {
        name: "high",
        set: &[("slices", "4"), ("steps", "16"), ("sectors", "32")],
    },
    Preset {
        name: "ultra",
        set: &[("slices", "8"), ("steps", "32"), ("sectors", "32")],
    },
];

impl Settings {
    /// Applies `--samples` (steps), `--radius` and `--set` on top of the defaults.
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        if let Some(n) = params.samples {
            s.steps = n;
        }
        if let Some(r) = params.radius {
            s.radius = r;
        }
        super::apply(&mut s, params, &[("samples", "steps")])?;
        super::horizon::check_march(s.radius, s.steps, s.reject_a, s.reject_b)?;
        Ok(s)
    }
}

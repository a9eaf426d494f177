//! Settings of `vbgi` (technique/vbgi): visibility-bitmask indirect lighting.

use crate::settings::denoise::{Denoise, SvgfSettings};
use crate::settings::march::MarchSettings;
use crate::settings::{Preset, TechniqueParams};
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
        @first { march: MarchSettings }
        sectors: u32 = "32", values("8", "16", "32"), count, "", "sectors of a slice's half circle in its bitmask (a u32)";
        thickness: Thickness = "layer", choice, structural, "", "an occluder's depth extent: `layer` from the second depth layer (depth peeling), `constant` `thickness_m`, `adaptive` `thickness_ratio` × view depth";
        thickness_m: f32 = "0.1", log(1e-4, 1e4), uniform, "m", "thickness with `thickness=constant`";
        thickness_ratio: f32 = "0.05", log(1e-4, 10), uniform, "", "thickness with `thickness=adaptive`, relative to the sample's view depth";
        far: VbgiFar = "sectors", choice, structural, "", "far field: `sectors` the environment through each unoccupied sector; `sh` SH irradiance through the bent cone; `envmap` pre-convolved map at the bent normal × F0(ao)";
        denoise: Denoise = "svgf", choice, denoiser, "", "`svgf` the shared spatio-temporal denoiser; `bilateral` the horizon techniques' blur then their running mean; `off` raw results (with the running mean)";
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
        crate::settings::apply(&mut s, params, &[("samples", "steps")])?;
        crate::settings::march::settle_march(&mut s.march)?;
        Ok(s)
    }
}

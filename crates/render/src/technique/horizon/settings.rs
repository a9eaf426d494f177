//! Settings of `gtao` and `hbil` (technique/horizon).

use crate::settings::denoise::{Denoise, SvgfSettings};
use crate::settings::march::MarchSettings;
pub use crate::settings::march::{ReprojectMode, Resolution, Source, settle_march};
use crate::settings::{Preset, TechniqueParams};
use crate::{choice, declare_settings};

choice! {
    /// Far-field estimate through the bent cone (hbil).
    pub enum Far {
        /// SH irradiance with the cone's reduced aperture (HBIL Sec. 2.2.4).
        Sh = "sh",
        /// Pre-convolved diffuse map at the bent normal × F0(ao) (HBIL Sec. 2.2.3).
        Envmap = "envmap",
        /// The environment integrated over every slice's visible arcs (directional; beyond the
        /// paper, see technique/horizon/march.wgsl).
        Slices = "slices",
    }
}

choice! {
    /// How the bent cone's aperture follows from the (cosine-weighted) ao (hbil, `far=sh`).
    pub enum Aperture {
        /// cos α = 1 − ao (HBIL Eq. 12).
        Eq12 = "eq12",
        /// cos α = √(1 − ao): the cone whose cosine-weighted visibility is ao (see technique/horizon/accumulate.wgsl).
        Matched = "matched",
    }
}

choice! {
    /// The light of a sender whose seen face turns away from the receiver (hbil with a probe
    /// volume; under the sky always `last`).
    pub enum Hidden {
        /// The last accepted sender's light (HBIL Sec. 3.4).
        Last = "last",
        /// The sender's albedo times the volume's irradiance at it about the direction back to
        /// the receiver: the light of its hidden face (see technique/horizon/march.wgsl).
        Volume = "volume",
        /// `volume` for the senders the bake never saw (dynamic meshes), `last` for the rest.
        Unbaked = "unbaked",
    }
}

declare_settings! {
    /// Settings of `gtao` and `hbil` (`--samples` = steps, `--radius`, `--set key=value`).
    pub struct Settings {
        @first { march: MarchSettings }
        far: Far = "slices", choice, structural("hbil"), "", "hbil's far field: `sh` SH irradiance through the bent cone (Sec. 2.2.4); `envmap` pre-convolved diffuse map at the bent normal × F0(ao) (Sec. 2.2.3); `slices` the environment integrated over each slice's visible arcs";
        aperture: Aperture = "matched", choice, uniform("hbil"), "", "hbil, `far=sh`: cone aperture `eq12` cos α = 1 − ao, or `matched` cos α = √(1 − ao)";
        hidden: Hidden = "unbaked", choice, structural("hbil"), "", "hbil with a probe volume: a sender whose seen face turns away sends `last` the last accepted sender's light (Sec. 3.4), `volume` its hidden face's, its albedo times the volume's irradiance there, or `unbaked` its hidden face's where the bake never saw it (a dynamic mesh) and the last accepted sender's elsewhere";
        falloff: f32 = "0.1", number(0, 1), uniform, "", "an occluder's rise fades out over the last `falloff`·R";
        #[cfg(feature = "scratch")]
        scratch: f32 = "0", number(0, 1), uniform("gtao"), "", "the test build's scratch setting (tests/scratch.rs)";
        denoise: Denoise = "bilateral", choice, denoiser, "", "`bilateral` geometry-aware blur of the raw results (merges a 4×4 block's directions) then the running mean; `svgf` the shared spatio-temporal denoiser on the AOVs; `off` raw results (with the running mean)";
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
        crate::settings::apply(&mut s, params, &[("samples", "steps")])?;
        settle_march(&mut s.march)?;
        Ok(s)
    }
}

//! `vbgi`: visibility-bitmask indirect lighting (after Therrien et al. 2023, "Screen Space
//! Indirect Lighting with Visibility Bitmask", arXiv 2301.11376) with per-pixel thickness from
//! the second depth layer and projected-cosine sector weights. It runs on the horizon
//! techniques' machinery (technique/horizon: local camera frame, slice directions, step
//! distribution, 4×4 interleaving, reprojection and push/pull, outputs); only the march
//! differs ([`bitmask`]; [`back`] deinterleaves the second layer's depth). Its default
//! denoiser is svgf (passes/denoise).
//!
//! Frame: [depth peeling (layer 2)] → [reproject → push/pull] → split (+ back) → bitmask →
//! merge → [bilateral blur | temporal mean, by `denoise`] → outputs → [svgf].
//! With `resolution=half` the bitmask march runs at one pixel of each 2×2 block, reading the
//! full-resolution G-buffer and second layer (no split), and its results are upsampled as gtao's
//! and hbil's are (technique/horizon, half.wgsl).
//!
//! The derivations stand at the WGSL lines that compute them (bitmask.wgsl): the sectors and
//! their stochastic rounding at `range_bits`, the thickness τ at the sample's back, the
//! cosine-weighted sector weights at `slice_s` and `mask_weight`, the near-field light and its
//! rejection at the sender's radiance, the ratio estimators at the outputs.

pub mod back;
pub mod bitmask;
pub mod march;
pub mod settings;

use crate::contract::technique::FarRule;
use crate::contract::technique::{Output, TechniqueDesc, TechniqueParams};
use crate::passes::denoise::{Denoise, SvgfConfig};
use crate::settings::Declared;
use crate::technique::horizon;

pub use settings::{PRESETS, Settings, Thickness, VbgiFar};

const VBGI_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::VBGI);

pub const VBGI: TechniqueDesc = TechniqueDesc {
    family: "vbgi",
    name: "vbgi",
    summary: "visibility-bitmask GI: sectors occupied between each sample's front and back (thickness from the second depth layer), cosine-weighted; light passes behind thin objects",
    create: |ctx, tp| horizon::build(ctx, FLAVOR, tp),
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &VBGI_PRESETS,
    denoise: Some(config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::BentNormal,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
    ],
    far_rule: FarRule::Replace,
    with_volume: &[],
};

crate::gpu_struct! {
    /// `VbgiParams` in bitmask.wgsl.
    #[derive(PartialEq)]
    pub struct VbgiParams {
        pub thickness: u32,
        pub thickness_m: f32,
        pub thickness_ratio: f32,
        pub _pad0: u32,
    }
}

/// What the bitmask march adds to the horizon machinery.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bitmask {
    pub params: VbgiParams,
    pub sectors: u32,
    /// `thickness=layer`: the second depth layer is peeled.
    pub layer: bool,
}

impl Settings {
    /// The horizon machinery's settings and the bitmask part (pure).
    pub fn split(&self) -> (horizon::Settings, Bitmask) {
        // vbgi's own over the horizon family's defaults: a setting the family adds reaches vbgi
        // at its default (today every field is named, which the lint reports).
        #[allow(clippy::needless_update)]
        let h = horizon::Settings {
            march: self.march,
            far: match self.far {
                VbgiFar::Sectors => horizon::Far::Slices,
                VbgiFar::Sh => horizon::Far::Sh,
                VbgiFar::Envmap => horizon::Far::Envmap,
            },
            aperture: horizon::Aperture::Matched,
            falloff: 0.0,
            denoise: self.denoise,
            svgf: self.svgf,
            ..horizon::Settings::default()
        };
        let b = Bitmask {
            params: VbgiParams {
                thickness: match self.thickness {
                    Thickness::Layer => 0,
                    Thickness::Constant => 1,
                    Thickness::Adaptive => 2,
                },
                thickness_m: self.thickness_m,
                thickness_ratio: self.thickness_ratio,
                _pad0: 0,
            },
            sectors: self.sectors,
            layer: self.thickness == Thickness::Layer,
        };
        (h, b)
    }
}

/// vbgi on the horizon machinery: the machinery's part of its settings and the bitmask march.
pub const FLAVOR: horizon::Flavor = horizon::Flavor {
    name: "vbgi",
    near: true,
    settings: |tp| Ok(Settings::from_params(tp)?.split().0),
    march: march::create,
};

/// The settings parsed without a device (`TechniqueDesc::check`).
fn check(tp: &TechniqueParams) -> Result<(), String> {
    config(tp).map(|_| ())
}

fn config(tp: &TechniqueParams) -> Result<(Denoise, SvgfConfig), String> {
    Ok(horizon::svgf_config(&Settings::from_params(tp)?.split().0))
}

/// The machinery's passes with the bitmask march (`TechniqueDesc::pass_layouts`).
fn pass_layouts() -> Vec<crate::bindings::PassLayout> {
    vec![
        horizon::split::pass_layout(),
        bitmask::pass_layout(),
        back::pass_layout(),
        horizon::accumulate::pass_layout(),
    ]
}

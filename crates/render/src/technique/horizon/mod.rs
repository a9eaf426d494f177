//! `gtao` and `hbil`: horizon-based ambient occlusion (Jimenez et al. 2016) and horizon-based
//! indirect lighting (Mayaux 2018, "Horizon-Based Indirect Lighting"); each pass is one `.rs`
//! and one `.wgsl` here: [`split`], [`search`], [`accumulate`] (`params.wgsl` is shared).
//!
//! Frame (hbil; gtao skips the radiance steps):
//!   reproject (scatter or gather last frame's diffuse radiance) → push/pull (fill holes) →
//!   split (4×4 deinterleave, with interleaving) → horizon search (straight to full resolution) →
//!   bilateral blur → accumulate (temporal, disocclusion-rejected) and, in the same kernel, the
//!   outputs (ao, env-irradiance through the bent
//!   cone, indirect-irradiance, and the diffuse radiance the next frame gathers).
//! On the first frame and after a camera cut the source radiance is this frame's direct
//! radiance (L_o of docs/src/aovs.md: one bounce); afterwards it is last frame's diffuse
//! radiance, so bounces add up over frames (HBIL Eq. 17).
//!
//! Entry points, in frame order:
//!   split     deinterleave depth, normal and source radiance into 4×4 quarter-resolution layers
//!             (HBIL Sec. 3.3; only with interleaving)
//!   horizon   the horizon search: AO, bent normal and near-field irradiance per pixel
//!   accumulate  temporal accumulation with disocclusion rejection (history ping-pong)
//!             and from it the AOVs: ao, env-irradiance (far field through the bent cone), indirect-irradiance and the
//!             diffuse radiance kept for the next frame (HBIL Eq. 17)
//!
//! The derivations sit beside the code that computes them:
//! - the local camera frame, the slice's straight screen line and its horizon angles at
//!   `local_frame`, the initial horizons and a normal facing away from the eye at
//!   `projected_normal`, the slice integrals (and where they depart from the paper's Eq. 6 and
//!   11) at `slice_g` (slice.wgsl);
//! - R, the falloff, the steps and the near field's rejection of back-facing senders at
//!   `march_side`, the ratio estimators of ao and near light at `search_pixel` (march.wgsl);
//! - the slice angles at `slice_phi` (params.wgsl);
//! - half resolution in half.wgsl's header.

pub mod accumulate;
mod machine;
pub mod march;
pub mod params;
pub mod search;
pub mod settings;
pub mod split;
mod stages;
pub mod upsample;

use crate::contract::technique::FarRule;
use crate::contract::technique::{Output, TechniqueDesc, TechniqueParams};
use crate::passes::denoise::{Denoise, SvgfConfig};
use crate::settings::Declared;

pub use machine::build;
pub use march::{Flavor, HorizonMarch, March, MarchContext, MarchIo};
pub use params::HorizonParams;
pub use settings::{Aperture, Far, Hidden, PRESETS, ReprojectMode, Resolution, Settings, Source};

/// The history geometry and split geometry: world normal xyz, view depth w.
pub const GEOMETRY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

const GTAO_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::GTAO);
const HBIL_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::HBIL);

/// gtao on the machinery: the horizon march, occlusion only.
pub const GTAO_FLAVOR: Flavor = Flavor {
    name: "gtao",
    near: false,
    settings: Settings::from_params,
    march: |m| Ok(HorizonMarch::create(m, false)),
};

/// hbil on the machinery: the horizon march with near-field light.
pub const HBIL_FLAVOR: Flavor = Flavor {
    name: "hbil",
    near: true,
    settings: Settings::from_params,
    march: |m| Ok(HorizonMarch::create(m, true)),
};

pub const GTAO: TechniqueDesc = TechniqueDesc {
    family: "horizon",
    name: "gtao",
    summary: "ground-truth AO: horizon search in slices, cosine-weighted AO, bent normal; ao × SH irradiance",
    create: |ctx, tp| build(ctx, GTAO_FLAVOR, tp),
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &GTAO_PRESETS,
    denoise: Some(config),
    pass_layouts,
    writes: &[Output::Ao, Output::BentNormal],
    far_rule: FarRule::Occlusion,
    with_volume: &[],
};

pub const HBIL: TechniqueDesc = TechniqueDesc {
    family: "horizon",
    name: "hbil",
    summary: "horizon-based indirect lighting: bent cones, far field through the cone, near-field bounces from reprojected radiance",
    create: |ctx, tp| build(ctx, HBIL_FLAVOR, tp),
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &HBIL_PRESETS,
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

/// The settings parsed without a device (`TechniqueDesc::check`).
fn check(tp: &TechniqueParams) -> Result<(), String> {
    config(tp).map(|_| ())
}

/// gtao's and hbil's denoiser choice and svgf configuration.
fn config(tp: &TechniqueParams) -> Result<(Denoise, SvgfConfig), String> {
    Ok(svgf_config(&Settings::from_params(tp)?))
}

/// The denoiser choice and svgf's configuration of the machinery's settings: svgf keeps the
/// running mean under the technique's own `temporal`, `history` and history tests.
pub fn svgf_config(s: &Settings) -> (Denoise, SvgfConfig) {
    (
        s.denoise,
        SvgfConfig {
            temporal: s.march.temporal,
            history: s.march.history,
            reject_depth: s.march.reject_depth,
            reject_normal: s.march.reject_normal,
            radius: s.march.radius,
            svgf: s.svgf,
        },
    )
}

/// The machinery's passes with the horizon march (`TechniqueDesc::pass_layouts`).
pub fn pass_layouts() -> Vec<crate::bindings::PassLayout> {
    vec![
        split::pass_layout(),
        upsample::pass_layout(),
        search::pass_layout(),
        accumulate::pass_layout(),
    ]
}

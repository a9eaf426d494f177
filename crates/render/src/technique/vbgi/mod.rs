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
//! Sectors. In slice φ (plane of ω_o and D(φ), angles θ from ω_o, positive towards D, as in
//! technique/horizon) the hemisphere above the tangent plane is θ ∈ [γ − π/2, γ + π/2], γ the
//! projected normal's angle. It is cut into N = `sectors` sectors of equal angle, sector b
//! covering [θ_b, θ_b+1], θ_b = γ − π/2 + π b/N; a u32 per slice holds which are occupied.
//! A march sample x′ (within R) with front direction v = x′ − x and back v_b = v + τ r̂
//! (r̂ the camera ray through x′, τ its thickness along the ray) occupies the sectors between
//! its angles θ_f = ±acos(v̂_s·ω_o) and θ_b (v_s: v projected into the slice plane). The ends
//! are rounded stochastically (floor(u + ξ), ξ per pixel and frame, the same for all samples of
//! a pixel so that adjacent ranges tile without gaps): a sector's expected coverage is the
//! exact fraction of it in the range.
//!
//! Thickness τ (`thickness`):
//!   layer     τ = (z₂ − z₁)/(r̂·forward), z₁ the sample's view depth and z₂ the second depth
//!             layer's (depth peeling: the nearest surface behind the first); a texel with no
//!             second layer (z₂ = 0) or none behind it is a solid to infinity, its back
//!             direction r̂ (what gtao/hbil assume everywhere). So a closed object is exactly as
//!             thick as it is, and light passes behind it; a lone wall never leaks.
//!   constant  τ = `thickness_m` (the peers' single constant)
//!   adaptive  τ = `thickness_ratio` × z₁ (for engines without a second layer: a thickness that
//!             grows with distance, as the depth buffer's own resolution does)
//!
//! Cosine weighting (`ao` is (1/π) ∫ V cos θ dω, docs/src/aovs.md). In the slice the measure of
//! the hemisphere integral is |sin θ| dθ dφ/… and the integrand n·ω = n′·ω(θ) with the
//! projected normal n′ = (n·D, n·ω_o) (unnormalised: slices weigh by its length, as in GTAO). With
//!     G(θ) = ½ n′x (θ − sin θ cos θ) + ½ n′y sin² θ      (technique/horizon)
//! the weight of the angles [a, b] is
//!     W(a, b) = S(b) − S(a),   S(θ) = ∫_0^θ (n′·ω(t)) |sin t| dt = sign(θ) G(θ),
//! exact on either side of ω_o and across it (G's first term is odd, its second even). Each
//! slice keeps the prefix weights cum[b] = S(θ_b) − S(θ_0); a mask's weight is the sum over its
//! runs of bits [s, e) of cum[e] − cum[s]. With U = cum[N] (the open hemisphere's weight):
//!   ao      = Σ_slices W(unoccupied) / Σ_slices U           (ratio estimator, as hbil)
//!   E_near  = Σ_slices Σ_samples a(x′) L(x′) W(newly occupied by x′) / Σ U
//!   far     = Σ_slices Σ_groups L_env(ω_g) W(unoccupied in group g) / Σ U   (`far=sectors`;
//!             16 groups of sectors, ω_g at the group's middle)
//!   bent    = normalize(Σ ω_g W(unoccupied in g))
//! Uniformly counted sectors (popcount / N, the peers' estimator) give the uniformly weighted
//! visibility instead: a wall meeting the floor at 90° reads 0.5 at its base either way, but
//! along the floor the uniform count is off the cosine-weighted curve.
//! Near-field light: L(x′) from the radiance source (last frame's diffuse radiance,
//! reprojected, or this frame's direct radiance: `source`), which holds emission, so emissive
//! surfaces light their surroundings as area lights. The sender's cosine is in the sectors
//! themselves (a sender seen edge-on covers few of them); a(x′) = smoothstep(a, b, −n_x′·v̂)
//! rejects back-facing senders (HBIL Sec. 3.4), which still occupy their sectors. Multi-bounce
//! over frames as HBIL Eq. 17 (the outputs' diffuse radiance is the next frame's source).

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

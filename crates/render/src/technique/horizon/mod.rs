//! `gtao` and `hbil`: horizon-based ambient occlusion (Jimenez et al. 2016) and horizon-based
//! indirect lighting (Mayaux 2018). The formulas, sources and deviations follow below;
//! each pass is one `.rs` + one `.wgsl` here: [`split`], [`search`], [`accumulate`]
//! (`params.wgsl` is shared).
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
//! The derivations. Horizon-based techniques: `gtao` (Jimenez et al. 2016) and `hbil` (Mayaux
//! 2018, "Horizon-Based Indirect Lighting"). Entry points, in frame order:
//!   split     deinterleave depth, normal and source radiance into 4×4 quarter-resolution layers
//!             (HBIL Sec. 3.3; only with interleaving)
//!   horizon   the horizon search: AO, bent normal and near-field irradiance per pixel
//!   accumulate  temporal accumulation with disocclusion rejection (history ping-pong)
//!             and from it the AOVs: ao, env-irradiance (far field through the bent cone), indirect-irradiance and the
//!             diffuse radiance kept for the next frame (HBIL Eq. 17)
//!
//! Horizon search (HBIL Sec. 1.1–1.3, 2.1). At the surface point x (normal n) the local camera
//! frame is ω_o = normalize(eye − x), ω_x = normalize(Y × ω_o) with Y the camera's up vector,
//! ω_y = ω_o × ω_x. Slice φ has the tangent direction D(φ) = cos φ ω_x + sin φ ω_y; the plane
//! spanned by ω_o and D contains the eye, so it projects to a straight screen line through x,
//! which is marched both ways. A sample s on it lies in the slice (up to the snap to a texel
//! centre, removed by projecting s − x onto the slice plane), and its angle from ω_o is
//! exactly cos θ = (s − x)·ω_o / |s − x| — the local-camera horizon angle that Sec. 1.3 obtains
//! from the camera-space angle β by cos θ = (cos α z + sin α r)/√(r² + z²); computing it from the
//! vector in the local frame is the same correction without the intermediate angles.
//! Horizons are initialised from the normal (Sec. 2.1): with the projected normal
//! n′ = (n·D, n·ω_o) at slice angle γ = atan2(n′x, n′y), θ_front = γ + π/2 and θ_back = γ − π/2,
//! so they never fall below the tangent plane. A shading normal may face away from the eye (a
//! normal map's, or one interpolated across a silhouette: n·ω_o < 0). Its hemisphere then
//! reaches past the slice's half circle θ ∈ [−π, π]: the initial horizons cross (θ_back > 0),
//! the open hemisphere's weight U (below) can vanish or turn negative while the visible arcs'
//! weights do not, and the ratio estimators blow up (hbil with one slice wrote irradiance of
//! 8000 on Crytek Sponza's normal-mapped arcade). Such a normal is taken at the eye's horizon,
//! n′y = max(n·ω_o, 0) in every slice, which is the normal with its ω_o part removed (the
//! common length cancels in every ratio below): γ ∈ [−π/2, π/2], both horizons stay on their
//! sides, and every weight is ≥ 0. XeGTAO clamps the projected normal's angle the same way.
//! Only samples within the near-field radius R count
//! (V_R of docs/src/aovs.md); over the last `falloff`·R their rise fades out (GTAO's falloff).
//! Steps: t_j = r_px ((j + ξ)/steps)^power along the screen line, r_px the screen length of R at
//! the point (capped by `max_pixels`), ξ a per-pixel, per-frame jitter; with 4×4 interleaving the
//! march reads the pixel's own quarter-resolution layer, so offsets are multiples of 4 pixels.
//!
//! Slice integrals. For one slice with horizons θ0 ≤ 0 ≤ θ1 and n′ = (nx, ny) (unnormalised, so
//! that slices weigh by the projected normal's length as in GTAO), every quantity is an integral
//! ∫ f(θ) |sin θ| dθ over [θ0, θ1], and with
//!     G(θ) = ½ nx (θ − sin θ cos θ) + ½ ny sin² θ
//! (one antiderivative serves both sides because θ − sin θ cos θ is odd and sin² θ even):
//!   AO_i   = G(θ1) + G(θ0)                                            (HBIL Eq. 10–11)
//!   ñ′     = (Gx(θ1) + Gx(θ0), Gy(θ1) + Gy(θ0)),  Gx: n′ = (1, 0), Gy: n′ = (0, 1)   (Eq. 4–6)
//!   ΔE     = L_d(x′) (G(θ_old) − G(θ_new)) when a sample raises a horizon from θ_old to θ_new
//!                                                                       (Eq. 18, both sides)
//! Deviation: the paper prints Eq. 6 and Eq. 11 as ½ nx [θ1 − θ0 + sin θ0 cos θ0 − sin θ1 cos θ1];
//! with θ0 ≤ 0 that is not the integral of sin θ |sin θ| (it gives ñx = π/2 for the symmetric
//! horizons ±π/2, where the true value is 0); the G form above is the exact integral and agrees
//! with Jimenez et al.'s per-side â(h). AO = Σ_i AO_i / Σ_i U_i and E_near = Σ_i Σ ΔE / Σ_i U_i
//! (both carry the 1/π of docs/src/aovs.md), bent normal = normalize(Σ_i D ñx + ω_o ñy), where
//! U_i = G(θ_front,init) + G(θ_back,init) is slice i's value for an open hemisphere. The paper's
//! mean (1/S) Σ AO_i is unbiased only over uniformly spread φ — a single tilted slice of an open
//! plane gives |n′| (cos γ + γ sin γ) ≠ 1 — so with 2 slices per pixel a plane would read as
//! noise around 1; the ratio (same expectation, since E[U_i] = 1) is exactly 1 there.
//! Near field (Sec. 2.3, 3.4): L_d(x′) is read from the source radiance (this frame's direct
//! radiance on the first frame, else last frame's diffuse radiance reprojected); a sample whose
//! normal faces away from x is replaced by the last accepted one:
//! L ← mix(L, L(x′), smoothstep(a, b, −n′·ω)), ω = normalize(x′ − x). Eq. 19's (1 − F0) is the
//! receiver's, so it is applied once per pixel in `outputs`.
//! Slice angles: pixel cell c (its position in a 4×4 block, Bayer order) and slice k of S take
//! φ = π (k + frac(c/16 + ξ_frame)) / S: the 16 cells × S slices of a block cover [0, π) evenly
//! (32 directions for S = 2, the paper's setting), and ξ_frame (golden-ratio sequence) turns
//! them from frame to frame through the whole of [0, 1), so that every pixel's running mean
//! sees every direction. (Turning them by ξ_frame/16 only, within each cell's sixteenth, left
//! each pixel's mean converged to its own sixteenth of the integral: a fixed 4×4 pattern that
//! neither the running mean nor an edge-stopping filter removes.)
//! Half resolution (`resolution=half`, gtao, hbil and vbgi, half.wgsl): the search runs at one pixel
//! of each 2×2 block, the block's four in turn over frames ((0,0), (1,1), (1,0), (0,1)), reading
//! the full-resolution G-buffer; slice angles and step jitter follow the block grid, so that the
//! blocks around a pixel bring different directions. Every pixel then takes the four searched
//! pixels around it with the bilinear weights of its position, each times
//! (n·n_s)⁸ / (1 + (d/(0.01 depth))²), d the searched point's distance from the pixel's tangent
//! plane: a tap on another surface (across a silhouette or a crease) hardly counts, and a pixel
//! whose nearest taps all lie on other surfaces takes the likeliest of them. The bilinear weights
//! carry a floor of 10⁻³ for that case, the normals' term one of 10⁻¹² for a pixel whose every
//! tap faces 90° or more away (a roof's edge over a wall, one pixel wide). A pixel none of whose
//! taps sees a surface (a ledge one pixel wide against the sky, on the three frames of four whose
//! searched rows or columns miss it) is taken as open: ao 1, its own normal as the bent normal,
//! no near field, and the far field of an open hemisphere (the probe volume's irradiance, or the
//! sky's). Left dark, such pixels read a quarter of their light in the running mean. The far field (the environment through the visible arcs
//! or sectors) is a cosine-weighted integral at the searched pixel's normal n_s; each tap's is
//! carried to the pixel's normal n by E_sky(n)/E_sky(n_s), the open sky's SH irradiance at the two
//! (per channel; not where E_sky(n_s) is below 5 % of E_sky(n)): the visibility is shared by
//! neighbours, the normal is not where a normal map varies it. Accumulate upsamples on its way in;
//! with the bilateral blur the `upsample` pass writes full-resolution images first, which the blur
//! reads.

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
pub use settings::{Aperture, Far, PRESETS, ReprojectMode, Resolution, Settings, Source};

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

// params.wgsl — `SsdoParams`, the constants of every ssdo pass (technique/ssdo/mod.rs
// `SsdoParams`; the formulas and sources are in mod.rs), a library: each pass binds the struct as
// `params` in its group 1 and passes it to the functions that take it (segment.wgsl).

struct SsdoParams {
    // Hemisphere radius R (m).
    radius: f32,
    // Radiance mode's L_in: 0 the environment's SH radiance (scaled, see direct.wgsl), 1 the mip
    // at `lod`. (Directions per pixel: the override SAMPLES.)
    sample_light: u32,
    // 0 visibility mode, 1 radiance mode.
    mode: u32,
    // 0 ssao, 1 ssdo.
    technique: u32,
    // Mip of the box-filtered environment read per sample.
    lod: f32,
    // Exponent applied to the visibility (SSDO) or to 1 − scale·S (SSAO).
    contrast: f32,
    // SSAO's scale on the occlusion sum S.
    scale: f32,
    // Fraction of R where the occluder fade starts.
    fade: f32,
    // Bounce strength.
    strength: f32,
    // Smallest sender distance used in 1/d² (m).
    distance_clamp: f32,
    // 0 chapter pattern, 1 interleaved M×N sets (M = 4×4).
    pattern: u32,
    // Points on each light's segment (0: no screen-space light occlusion).
    light_samples: u32,
    // Depth layers of the main view (1..=4) and additional cameras (0..=4), passes/layers/.
    layers: u32,
    cameras: u32,
    // Light segment: 0 length R (Sec. 4 screen-space shadows), 1 the shadow map's bias
    // (Sec. 5 screen-space shadow correction).
    light_segment: u32,
    // Virtual point lights: 0 none; 1 ssdo-vpl, the environment is `vpl_count` directional
    // lights in the direct pass's light table (bindings 13..=16 then hold them, not the scene's
    // lights); 2 instant-radiosity, the bounce pass's light table holds `vpl_count` cosine
    // emitters (spot lights about their normals with colour Φ/π).
    vpl_mode: u32,
    vpl_count: u32,
    // instant-radiosity: smallest distance in a VPL's 1/d² (m).
    vpl_clamp: f32,
    // 1: the bounce pass gathers sender pixels (ssdo with bounce=on).
    near: u32,
    // Radiance mode: 1 divides each channel's sum by the same sum with V ≡ 1 and multiplies by
    // the exact unoccluded irradiance (direct.wgsl); 0 the paper's plain sum. (Points per
    // direction: the override STEPS.)
    normalise: u32,
}

// Counts, fixed per pipeline (WGSL override constants; technique/ssdo/mod.rs sets them): a
// change of one of them rebuilds the technique, every other setting is a uniform.
// Directions per pixel N.
override SAMPLES: u32 = 16u;
// Points tested per direction (ray marching, the first occluded decides); 1: the paper's single
// point at λ.
override STEPS: u32 = 1u;


// params.wgsl — `HorizonParams` and the per-pixel noise shared by the horizon passes
// (the derivations: slice.wgsl, march.wgsl). A library: it declares no bindings (each
// pass binds its `HorizonParams` in group 1 and passes it to the functions that read it).

struct HorizonParams {
    radius: f32,
    // (Slices per pixel and samples per side: the overrides SLICES and STEPS.)
    // 1: the host handed in a bent-normal output (accumulate writes it).
    bent_normal: u32,
    falloff: f32,
    max_pixels: f32,
    // 4 with interleaving (layers of 1/4 × 1/4 resolution), else 1.
    scale: u32,
    // 1: gather near-field radiance (hbil).
    indirect: u32,
    step_power: f32,
    reject_a: f32,
    reject_b: f32,
    // Layer size in texels (the image size without interleaving).
    layer_width: u32,
    layer_height: u32,
    // 1: temporal accumulation.
    temporal: u32,
    max_history: f32,
    // Far field: FAR_AO, FAR_SH, FAR_ENVMAP or FAR_SLICES (below).
    far: u32,
    // 1: (1 − F0) on the near-field irradiance (HBIL Eq. 19).
    fresnel: u32,
    // History rejection: tangent-plane distance relative to view depth, normal cosine.
    reject_depth: f32,
    reject_normal: f32,
    // Cone aperture from ao: 0 cos α = 1 − ao (Eq. 12), 1 cos α = √(1 − ao) (matched).
    aperture: u32,
    // Sub-arcs per side of the environment integration (far = FAR_SLICES).
    far_steps: u32,
}

// `far` (technique/horizon/params.rs has the same names): ao only, the far field from the direct
// pass's irradiance (gtao); SH irradiance through the bent cone (HBIL Sec. 2.2.4); the
// pre-convolved diffuse map at the bent normal × F0(ao) (Sec. 2.2.3); the environment or the
// probe volume over the slices' visible arcs.
const FAR_AO: u32 = 0u;
const FAR_SH: u32 = 1u;
const FAR_ENVMAP: u32 = 2u;
const FAR_SLICES: u32 = 3u;

// Counts, fixed per pipeline (WGSL override constants; technique/horizon/stages.rs sets them).
// Slices per pixel S.
override SLICES: u32 = 2u;
// Samples per side of a slice.
override STEPS: u32 = 16u;
// What a pipeline computes besides the bent cone (fixed per pipeline, so gtao's kernels carry
// none of hbil's work): near-field light (hbil, vbgi), the far field through the slices' arcs
// (`far=slices`: FAR is set exactly when `far` is FAR_SLICES, and the kernels test FAR alone,
// so that the other far fields' code is left out of the pipeline).
override NEAR: bool = true;
override FAR: bool = true;
// `resolution=half` (half.wgsl): the search runs at one pixel of each 2×2 block and accumulate
// brings its results to every pixel.
override HALF: bool = false;
// `hidden` (hbil; march.wgsl's march_side), with a probe volume: which senders that face away
// send their hidden face's light rather than the last accepted sender's (Sec. 3.4): 0 none
// (`last`), 1 every one (`volume`), 2 those the bake never saw (`unbaked`: the G-buffer's
// material b = 1).
override HIDDEN: u32 = 0u;


const BAYER4: array<u32, 16> = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);

fn cell_index(pixel: vec2<u32>) -> u32 {
    return BAYER4[(pixel.x % 4u) + 4u * (pixel.y % 4u)];
}

// Angle of slice k of S at a pixel of cell `cell` on a frame with rotation `rotation` ∈ [0, 1):
// φ = π (k + frac(cell/16 + rotation)) / S. In one frame the 16 cells of a 4×4 block sit 1/16
// apart (with S slices they cover [0, π) evenly); over frames the rotation moves every cell
// through all of [0, 1), so each pixel's running mean sees every direction (a cell kept to its
// 1/16 would converge to its own sixteenth of the integral: a 4×4 pattern no mean removes).
fn slice_phi(k: u32, slices: u32, cell: u32, rotation: f32) -> f32 {
    return PI * (f32(k) + fract(f32(cell) / 16.0 + rotation)) / f32(slices);
}

fn golden(i: u32) -> f32 {
    return fract(f32(i % 4096u) * 0.618034);
}

fn noise(pixel: vec2<u32>) -> f32 {
    let c = vec2<f32>(pixel) + 0.5;
    return fract(52.9829189 * fract(0.06711056 * c.x + 0.00583715 * c.y));
}

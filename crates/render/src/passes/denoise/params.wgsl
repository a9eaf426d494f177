// params.wgsl — `SvgfParams` and the helpers the svgf passes share (passes/denoise/mod.rs holds
// the model and its deviations), a library (after common.wgsl). It declares no bindings: the
// helpers take the `SvgfParams` and the `View` they read as parameters (each kernel binds its own
// `params` in group 1 and passes it, with group 0's `view`, on).

struct SvgfParams {
    // 1: temporal accumulation.
    temporal: u32,
    // Frames in the running mean at most.
    max_history: f32,
    // History rejection: tangent-plane distance relative to view depth, normal cosine.
    reject_depth: f32,
    reject_normal: f32,
    // Edge stopping: σ_l (value, in standard deviations; 0 = off), σ_z (tangent-plane distance
    // relative to view depth), σ_n (exponent on the normals' cosine).
    sigma_l: f32,
    sigma_z: f32,
    sigma_n: f32,
    // This à-trous iteration's tap spacing (pixels).
    step: i32,
    // The history's clamp: this frame's 5×5 neighbourhood mean ± clamp standard deviations
    // (0: off).
    clamp: f32,
    // A surface that moves in the world keeps the history of its last `motion` metres of travel.
    motion: f32,
    // The filter's reach (m): a tap this far from the centre has its weight fall by e.
    reach: f32,
    _pad2: f32,
}

fn svgf_luma(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The geometric part of a tap's weight: the tap's surface point's distance from the centre's
// tangent plane relative to the centre's view depth, and the normals' cosine. Positions in view
// space (`view_position`), `n_view` the centre's normal in view space, `n` and `nq` in world space;
// σ_z and σ_n from `p`.
fn svgf_geometry_weight(p: SvgfParams, x_view: vec3<f32>, n_view: vec3<f32>, n: vec3<f32>, depth: f32, xq_view: vec3<f32>, nq: vec3<f32>) -> f32 {
    let plane = abs(dot(n_view, xq_view - x_view)) / (p.sigma_z * depth);
    return exp(-plane) * pow(max(dot(n, nq), 0.0), p.sigma_n);
}

// The weight of a tap for the filter's reach: a tap `reach` metres from the centre in the world
// (x_view, xq_view) has its weight fall by e; a tap within REACH_FLOOR pixels (`taps`) keeps its
// weight, so that a pixel's noise is always averaged with its nearest neighbours'.
const REACH_FLOOR: f32 = 3.0;
fn svgf_reach_weight(p: SvgfParams, x_view: vec3<f32>, xq_view: vec3<f32>, taps: f32) -> f32 {
    if taps <= REACH_FLOOR {
        return 1.0;
    }
    let apart = xq_view - x_view;
    return exp(-dot(apart, apart) / (p.reach * p.reach));
}

// A world-space direction in the view space of `cam`.
fn to_view(cam: View, n: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(cam.world_from_view[0].xyz, n), dot(cam.world_from_view[1].xyz, n), dot(cam.world_from_view[2].xyz, n));
}

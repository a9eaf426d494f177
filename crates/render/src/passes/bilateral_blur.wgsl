// bilateral_blur.wgsl — one direction of a separable geometry-aware blur (compute, 8×8).
//
// out(p) = Σ_k w_k in(p + k·dir) / Σ_k w_k over k ∈ [−radius, radius], with
//   w_k = exp(−k² / (2σ²))                      spatial, σ = radius / 2
//       · exp(−|n_p · (X_k − X_p)| / (depth_sigma · z_p))  distance of the tap's surface point
//                                                      from the centre's tangent plane, relative
//                                                      to the centre's view depth (so grazing
//                                                      planes still blur along themselves)
//       · max(0, n_k · n_p)^normal_power          normals
// Background taps (and background centres) are skipped. The SSDO paper (Sec. 3, after Segovia et
// al. 2006) and the chapter blur both visibility and radiance this way; with radius ≥ 4 the M×N
// interleaving of 4×4 sample sets disappears. Horizontal and vertical passes use this shader with
// `direction` (1, 0) and (0, 1).

struct BlurParams {
    direction: vec2<i32>,
    radius: i32,
    // 1 = blur, 0 = copy (settings with blur off still route through here).
    enabled: u32,
    depth_sigma: f32,
    normal_power: f32,
    _pad0: f32,
    _pad1: f32,
}

@group(1) @binding(0) var<uniform> blur: BlurParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var source: texture_2d<f32>;
@group(1) @binding(4) var destination: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let centre = textureLoad(source, pixel, 0);
    let nw = textureLoad(gb_normal, pixel, 0);
    if blur.enabled == 0u || nw.w == 0.0 {
        textureStore(destination, pixel, centre);
        return;
    }
    let n = normalize(nw.xyz);
    // Positions in view space (no matrix per tap); the centre's normal there for the plane test.
    let n_view = (view.view_from_world * vec4<f32>(n, 0.0)).xyz;
    let z = textureLoad(gb_view_depth, pixel, 0).r;
    let x = view_position(view, pixel, z);
    let size = vec2<i32>(view.size);
    let sigma = max(f32(blur.radius) * 0.5, 0.5);
    let spatial = -1.0 / (2.0 * sigma * sigma);
    let plane = -1.0 / (blur.depth_sigma * z);
    var sum = vec4<f32>(0.0);
    var weight = 0.0;
    for (var k = -blur.radius; k <= blur.radius; k++) {
        let q = vec2<i32>(pixel) + blur.direction * k;
        if any(q < vec2<i32>(0)) || any(q >= size) {
            continue;
        }
        let qn = textureLoad(gb_normal, q, 0);
        if qn.w == 0.0 {
            continue;
        }
        let qx = view_position(view, vec2<u32>(q), textureLoad(gb_view_depth, q, 0).r);
        let w = exp(f32(k * k) * spatial + abs(dot(qx - x, n_view)) * plane)
            * pow(max(0.0, dot(normalize(qn.xyz), n)), blur.normal_power);
        sum += textureLoad(source, q, 0) * w;
        weight += w;
    }
    textureStore(destination, pixel, select(centre, sum / weight, weight > 0.0));
}

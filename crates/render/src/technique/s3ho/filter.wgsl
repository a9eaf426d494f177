// filter.wgsl — s3ho `filter_pass`: the paper's geometry-aware 8×8 bilateral filter on the
// packed coefficients. technique/s3ho/mod.rs has the overview.
//
// `filter_pass`: the paper's geometry-aware 8×8 bilateral filter (offsets −3..4) on the coefficients,
//   weights from the distance to the centre's tangent plane and the normals' agreement.

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(2) var in_coeffs0: texture_2d<u32>;
@group(1) @binding(3) var in_coeffs1: texture_2d<u32>;
@group(1) @binding(4) var out_coeffs0: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(5) var out_coeffs1: texture_storage_2d<rgba32uint, write>;

@compute @workgroup_size(8, 8, 1)
fn filter_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let centre = surface_at(view, gb_normal, gb_view_depth, pixel);
    if !centre.valid {
        textureStore(out_coeffs0, pixel, vec4<u32>(0u));
        textureStore(out_coeffs1, pixel, vec4<u32>(0u));
        return;
    }
    let z = textureLoad(gb_view_depth, pixel, 0).r;
    let size = vec2<i32>(view.size);
    var sum = array<f32, 16>();
    var weight = 0.0;
    for (var dy = -3; dy <= 4; dy++) {
        for (var dx = -3; dx <= 4; dx++) {
            let q = vec2<i32>(pixel) + vec2<i32>(dx, dy);
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let s = surface_at(view, gb_normal, gb_view_depth, vec2<u32>(q));
            if !s.valid {
                continue;
            }
            let w = exp(-abs(dot(s.p - centre.p, centre.n)) / (0.01 * z)) * pow(max(0.0, dot(s.n, centre.n)), 8.0);
            let c = unpack16(textureLoad(in_coeffs0, q, 0), textureLoad(in_coeffs1, q, 0));
            for (var i = 0u; i < 16u; i++) {
                sum[i] += c[i] * w;
            }
            weight += w;
        }
    }
    for (var i = 0u; i < 16u; i++) {
        sum[i] /= weight;
    }
    let packed = pack16(sum);
    textureStore(out_coeffs0, pixel, packed[0]);
    textureStore(out_coeffs1, pixel, packed[1]);
}

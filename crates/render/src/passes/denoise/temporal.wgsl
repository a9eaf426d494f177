// temporal.wgsl — svgf's temporal accumulation (passes/denoise/mod.rs).

// temporal: this frame's ao, env-irradiance and indirect-irradiance join last frame's running
// means, fetched where the surface point was through the motion vectors (previous = pixel +
// motion), bilinearly from the taps that pass the disocclusion test `history_taps` (common.wgsl:
// tangent plane, normal, footprint). The first and second moments of ao and of the indirect
// light's luminance are accumulated the same way (the per-pixel variance of the spatial filter).
// No passing tap, no history (first frame, camera cut) or temporal off: the mean restarts at
// this frame's value, count 1. Weight of the new frame 1 / min(count, max_history).

@group(1) @binding(0) var<uniform> params: SvgfParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var gb_motion: texture_2d<f32>;
@group(1) @binding(4) var raw_ao: texture_2d<f32>;
@group(1) @binding(5) var raw_env: texture_2d<f32>;
@group(1) @binding(6) var raw_indirect: texture_2d<f32>;
@group(1) @binding(7) var prev_moments: texture_2d<f32>;
@group(1) @binding(8) var prev_env: texture_2d<f32>;
@group(1) @binding(9) var prev_indirect: texture_2d<f32>;
@group(1) @binding(10) var prev_geometry: texture_2d<f32>;
@group(1) @binding(11) var acc_moments: texture_storage_2d<rgba32float, write>;
@group(1) @binding(12) var acc_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(13) var acc_indirect: texture_storage_2d<rgba16float, write>;
@group(1) @binding(14) var acc_geometry: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn temporal(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(acc_moments, pixel, vec4<f32>(1.0, 1.0, 0.0, 0.0));
        textureStore(acc_env, pixel, vec4<f32>(0.0));
        textureStore(acc_indirect, pixel, vec4<f32>(0.0));
        textureStore(acc_geometry, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let x = world_position(view, pixel, depth);
    let ao = textureLoad(raw_ao, pixel, 0).r;
    var env = textureLoad(raw_env, pixel, 0).rgb;
    var indirect = textureLoad(raw_indirect, pixel, 0).rgb;
    let l = svgf_luma(indirect);
    var moments = vec4<f32>(ao, ao * ao, l, l * l);
    var count = 1.0;
    if params.temporal == 1u && view.history_valid == 1u {
        let prev = vec2<f32>(pixel) + 0.5 + textureLoad(gb_motion, pixel, 0).xy;
        let taps = history_taps(view, prev_geometry, prev, x, n, depth, params.reject_depth, params.reject_normal);
        if taps.total > 1e-3 {
            var m = vec4<f32>(0.0);
            var e = vec4<f32>(0.0);
            var ind = vec3<f32>(0.0);
            for (var k = 0u; k < 4u; k++) {
                let w = taps.weights[k];
                if w > 0.0 {
                    let q = taps.base + tap_offset(k);
                    m += w * textureLoad(prev_moments, q, 0);
                    e += w * textureLoad(prev_env, q, 0);
                    ind += w * textureLoad(prev_indirect, q, 0).rgb;
                }
            }
            let inv = 1.0 / taps.total;
            count = min(e.w * inv + 1.0, params.max_history);
            let a = 1.0 / count;
            moments = mix(m * inv, moments, a);
            env = mix(e.rgb * inv, env, a);
            indirect = mix(ind * inv, indirect, a);
        }
    }
    textureStore(acc_moments, pixel, moments);
    textureStore(acc_env, pixel, vec4<f32>(env, count));
    textureStore(acc_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(acc_geometry, pixel, vec4<f32>(n, depth));
}

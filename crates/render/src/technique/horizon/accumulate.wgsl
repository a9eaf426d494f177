// accumulate.wgsl — the temporal running mean with disocclusion rejection.
// Derivations and sources: technique/horizon/mod.rs.

// accumulate: running mean over up to `max_history` frames of the bent cone (xyz bent normal,
// w ao), the near-field irradiance (w = frames in the mean) and the far field. Last frame's
// accumulation is fetched where this surface point was (previous camera), bilinearly from the
// taps that pass the disocclusion test `same_surface` (common.wgsl) with the tap's surface point
// rebuilt from last frame's depth and camera: near this point's tangent plane (reject_depth ×
// depth), with a normal within acos(reject_normal), and within a few pixel footprints of it.
// No passing tap (or no history: first frame, camera cut, temporal off) restarts the mean at
// this frame's value.

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var raw_cone: texture_2d<f32>;
@group(1) @binding(4) var raw_near: texture_2d<f32>;
@group(1) @binding(5) var raw_far: texture_2d<f32>;
@group(1) @binding(6) var prev_cone: texture_2d<f32>;
@group(1) @binding(7) var prev_near: texture_2d<f32>;
@group(1) @binding(8) var prev_far: texture_2d<f32>;
@group(1) @binding(9) var prev_geometry: texture_2d<f32>;
@group(1) @binding(10) var acc_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(11) var acc_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(12) var acc_far: texture_storage_2d<rgba16float, write>;
@group(1) @binding(13) var acc_geometry: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn accumulate(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(acc_cone, pixel, vec4<f32>(0.0));
        textureStore(acc_near, pixel, vec4<f32>(0.0));
        textureStore(acc_geometry, pixel, vec4<f32>(0.0));
        textureStore(acc_far, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let x = world_position(pixel, depth);
    var cone = textureLoad(raw_cone, pixel, 0);
    var far = textureLoad(raw_far, pixel, 0);
    var near = vec4<f32>(textureLoad(raw_near, pixel, 0).rgb, 1.0);
    if params.temporal == 1u && frame.history_valid == 1u {
        let taps = history_taps(prev_geometry, to_screen(frame.prev_clip_from_world, x), x, n, depth, params.reject_depth, params.reject_normal);
        var sum_cone = vec4<f32>(0.0);
        var sum_near = vec4<f32>(0.0);
        var sum_far = vec4<f32>(0.0);
        for (var k = 0u; k < 4u; k++) {
            let w = taps.weights[k];
            if w > 0.0 {
                let q = taps.base + tap_offset(k);
                sum_cone += w * textureLoad(prev_cone, q, 0);
                sum_near += w * textureLoad(prev_near, q, 0);
                sum_far += w * textureLoad(prev_far, q, 0);
            }
        }
        let weight = taps.total;
        if weight > 1e-3 {
            let hist_cone = sum_cone / weight;
            let hist_near = sum_near / weight;
            let count = min(hist_near.w + 1.0, params.max_history);
            let a = 1.0 / count;
            cone = mix(hist_cone, cone, a);
            far = mix(sum_far / weight, far, a);
            near = vec4<f32>(mix(hist_near.rgb, near.rgb, a), count);
        }
    }
    textureStore(acc_cone, pixel, cone);
    textureStore(acc_near, pixel, near);
    textureStore(acc_geometry, pixel, vec4<f32>(n, depth));
    textureStore(acc_far, pixel, far);
}

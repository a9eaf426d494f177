// temporal.wgsl — svgf's temporal accumulation (passes/denoise/mod.rs).

// temporal: this frame's ao, env-irradiance and indirect-irradiance join last frame's running
// means, fetched where the surface point was through the motion vectors (previous = pixel +
// motion), bilinearly from the taps that pass the disocclusion test `history_taps` (common.wgsl:
// tangent plane, normal, footprint). The first and second moments of ao and of the indirect
// light's luminance are accumulated the same way (the per-pixel variance of the spatial filter).
// No passing tap, no history (first frame, camera cut) or temporal off: the mean restarts at
// this frame's value, count 1. Weight of the new frame 1 / min(count, max_history, the frames in
// which a moving surface travelled `motion` metres): a rolling ball turns its surface points
// through the light, and a long history would drag the light of its last half-turn along.
// With `clamp` > 0 the history's ao, env and indirect means are first clamped to this frame's
// raw values' mean ± clamp standard deviations over the 5×5 surface pixels around (variance
// clipping): where a moving object changed the light, the history follows within frames, while
// a still scene's history, whose mean lies inside its own noise, is left alone.

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

// The mean and standard deviation of this frame's raw ao and env and indirect channels over the
// 5×5 pixels around `pixel` on its surface (the history tests: normal cosine and tangent-plane
// distance; `x`, `n` and `depth` the centre's), so that another object's light beside it does
// not widen the range.
struct Neighbourhood {
    env_mean: vec3<f32>,
    env_sd: vec3<f32>,
    ind_mean: vec3<f32>,
    ind_sd: vec3<f32>,
    ao_mean: f32,
    ao_sd: f32,
}

fn neighbourhood(pixel: vec2<u32>, x: vec3<f32>, n: vec3<f32>, depth: f32) -> Neighbourhood {
    var count = 0.0;
    var e1 = vec3<f32>(0.0);
    var e2 = vec3<f32>(0.0);
    var i1 = vec3<f32>(0.0);
    var i2 = vec3<f32>(0.0);
    var a1 = 0.0;
    var a2 = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        for (var dx = -2; dx <= 2; dx++) {
            let q = vec2<i32>(pixel) + vec2<i32>(dx, dy);
            if q.x < 0 || q.y < 0 || !in_bounds(view, vec2<u32>(q)) {
                continue;
            }
            let nq = textureLoad(gb_normal, q, 0);
            let dq = textureLoad(gb_view_depth, q, 0).r;
            if nq.w == 0.0 || dq <= 0.0 || dot(nq.xyz, n) < params.reject_normal {
                continue;
            }
            let xq = world_position(view, vec2<u32>(q), dq);
            if abs(dot(n, xq - x)) > params.reject_depth * depth {
                continue;
            }
            let e = textureLoad(raw_env, q, 0).rgb;
            let i = textureLoad(raw_indirect, q, 0).rgb;
            let a = textureLoad(raw_ao, q, 0).r;
            count += 1.0;
            e1 += e;
            e2 += e * e;
            i1 += i;
            i2 += i * i;
            a1 += a;
            a2 += a * a;
        }
    }
    var o: Neighbourhood;
    let inv = 1.0 / max(count, 1.0);
    o.env_mean = e1 * inv;
    o.env_sd = sqrt(max(e2 * inv - o.env_mean * o.env_mean, vec3<f32>(0.0)));
    o.ind_mean = i1 * inv;
    o.ind_sd = sqrt(max(i2 * inv - o.ind_mean * o.ind_mean, vec3<f32>(0.0)));
    o.ao_mean = a1 * inv;
    o.ao_sd = sqrt(max(a2 * inv - o.ao_mean * o.ao_mean, 0.0));
    return o;
}

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
            // A surface that moved in the world since the last frame (its motion vector beyond the
            // camera's own reprojection of x, in pixels times the pixel's footprint in metres)
            // keeps the history of its last `motion` metres of travel.
            let still_at = to_screen(view, view.prev_clip_from_world, x);
            let moved = length(prev - still_at) * pixel_footprint(view, depth);
            let cap = max(1.0, params.motion / max(moved, 1e-6));
            count = min(min(e.w * inv + 1.0, params.max_history), cap);
            var hm = m * inv;
            var he = e.rgb * inv;
            var hi = ind * inv;
            if params.clamp > 0.0 {
                let g = params.clamp;
                let nb = neighbourhood(pixel, x, n, depth);
                let cm = clamp(hm.x, nb.ao_mean - g * nb.ao_sd, nb.ao_mean + g * nb.ao_sd);
                let ce = clamp(he, nb.env_mean - g * nb.env_sd, nb.env_mean + g * nb.env_sd);
                let ci = clamp(hi, nb.ind_mean - g * nb.ind_sd, nb.ind_mean + g * nb.ind_sd);
                hm.x = cm;
                he = ce;
                hi = ci;
            }
            let a = 1.0 / count;
            moments = mix(hm, moments, a);
            env = mix(he, env, a);
            indirect = mix(hi, indirect, a);
        }
    }
    textureStore(acc_moments, pixel, moments);
    textureStore(acc_env, pixel, vec4<f32>(env, count));
    textureStore(acc_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(acc_geometry, pixel, vec4<f32>(n, depth));
}

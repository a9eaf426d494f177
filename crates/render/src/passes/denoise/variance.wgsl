// variance.wgsl — svgf's per-pixel variance estimate (passes/denoise/mod.rs).

// variance: Var = E[v²] − E[v]² from the accumulated moments of ao and of the indirect light's
// luminance. Where the history is younger than 4 frames the moments are averaged over the 5×5
// neighbourhood first (taps weighted by geometry, as in the à-trous filter) and the variance is
// scaled by 4 / count, so that new pixels blur more until their history builds up (SVGF Sec.
// 4.2 does the same over 7×7).
// Output `out_signal`: x ao (the accumulated mean), y Var(ao), z Var(luminance), w count.

@group(1) @binding(0) var<uniform> params: SvgfParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var acc_moments: texture_2d<f32>;
@group(1) @binding(4) var acc_env: texture_2d<f32>;
@group(1) @binding(5) var out_signal: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn variance(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(out_signal, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let m = textureLoad(acc_moments, pixel, 0);
    let count = max(textureLoad(acc_env, pixel, 0).w, 1.0);
    var mm = m;
    var boost = 1.0;
    if count < 4.0 {
        let n = normalize(nw.xyz);
        let n_view = to_view(view, n);
        let x = view_position(view, pixel, depth);
        var sum = vec4<f32>(0.0);
        var wsum = 0.0;
        let size = vec2<i32>(view.size);
        for (var dy = -2; dy <= 2; dy++) {
            for (var dx = -2; dx <= 2; dx++) {
                let q = vec2<i32>(pixel) + vec2<i32>(dx, dy);
                if any(q < vec2<i32>(0)) || any(q >= size) {
                    continue;
                }
                let qn = textureLoad(gb_normal, q, 0);
                let qd = textureLoad(gb_view_depth, q, 0).r;
                if qn.w == 0.0 || qd <= 0.0 {
                    continue;
                }
                let xq = view_position(view, vec2<u32>(q), qd);
                let w = svgf_geometry_weight(params, x, n_view, n, depth, xq, normalize(qn.xyz));
                sum += w * textureLoad(acc_moments, q, 0);
                wsum += w;
            }
        }
        mm = sum / max(wsum, 1e-6);
        boost = 4.0 / count;
    }
    let var_ao = max(mm.y - mm.x * mm.x, 0.0) * boost;
    let var_l = max(mm.w - mm.z * mm.z, 0.0) * boost;
    textureStore(out_signal, pixel, vec4<f32>(m.x, var_ao, var_l, count));
}

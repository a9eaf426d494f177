// atrous.wgsl — one iteration of svgf's edge-aware à-trous filter (passes/denoise/mod.rs).

// atrous: out(p) = Σ_q w(p, q) in(q) / Σ_q w(p, q) over the 3×3 taps q = p + step·(i, j),
// i, j ∈ {−1, 0, 1}, with
//   w = h(i) h(j)                                   kernel (¼, ½, ¼)
//     · exp(−|n_p·(X_q − X_p)| / (σ_z z_p))         tangent-plane distance, relative to view depth
//     · max(0, n_p·n_q)^σ_n                          normals
//     · exp(−|v_q − v_p| / (σ_l √Var_p + ε))        value, Var_p the centre's variance filtered
//                                                   over the same taps with the kernel h
// ao and env-irradiance share ao's value term; indirect-irradiance has its own (luminance).
// ao and env-irradiance also fall with the tap's distance from the centre in the world, by e at
// the filter's reach (`svgf_reach_weight`): the visibility within R is made by the geometry
// within R and changes at that scale, and averaging it over several metres (four iterations
// span ±15 pixels, metres where the view is deep) mixes the occlusion of separate
// neighbourhoods. The near light keeps the kernel's whole span (the book, "vbgi").
// The variance is filtered with the squared weights (it is the variance of the weighted mean).
// in_signal / out_signal: x ao, y Var(ao), z Var(luminance of the indirect light), w count.

@group(1) @binding(0) var<uniform> params: SvgfParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var in_signal: texture_2d<f32>;
@group(1) @binding(4) var in_env: texture_2d<f32>;
@group(1) @binding(5) var in_indirect: texture_2d<f32>;
@group(1) @binding(6) var out_signal: texture_storage_2d<rgba16float, write>;
@group(1) @binding(7) var out_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(8) var out_indirect: texture_storage_2d<rgba16float, write>;

const KERNEL: array<f32, 3> = array<f32, 3>(0.25, 0.5, 0.25);

@compute @workgroup_size(8, 8, 1)
fn atrous(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let centre = textureLoad(in_signal, pixel, 0);
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(out_signal, pixel, centre);
        textureStore(out_env, pixel, textureLoad(in_env, pixel, 0));
        textureStore(out_indirect, pixel, textureLoad(in_indirect, pixel, 0));
        return;
    }
    let n = normalize(nw.xyz);
    let n_view = to_view(view, n);
    let x = view_position(view, pixel, depth);
    let size = vec2<i32>(view.size);
    var sig: array<vec4<f32>, 9>;
    var env: array<vec3<f32>, 9>;
    var ind: array<vec3<f32>, 9>;
    var geo: array<f32, 9>;
    var reach: array<f32, 9>;
    // The centre's variance, filtered over the taps with the kernel alone.
    var var_sum = vec2<f32>(0.0);
    var var_w = 0.0;
    for (var k = 0; k < 9; k++) {
        let o = vec2<i32>(k % 3 - 1, k / 3 - 1);
        let q = vec2<i32>(pixel) + o * params.step;
        geo[k] = 0.0;
        if any(q < vec2<i32>(0)) || any(q >= size) {
            continue;
        }
        let qn = textureLoad(gb_normal, q, 0);
        let qd = textureLoad(gb_view_depth, q, 0).r;
        if qn.w == 0.0 || qd <= 0.0 {
            continue;
        }
        sig[k] = textureLoad(in_signal, q, 0);
        env[k] = textureLoad(in_env, q, 0).rgb;
        ind[k] = textureLoad(in_indirect, q, 0).rgb;
        let h = KERNEL[o.x + 1] * KERNEL[o.y + 1];
        var_sum += h * sig[k].yz;
        var_w += h;
        let xq = view_position(view, vec2<u32>(q), qd);
        geo[k] = h * svgf_geometry_weight(params, x, n_view, n, depth, xq, normalize(qn.xyz));
        reach[k] = svgf_reach_weight(params, x, xq, f32(params.step) * length(vec2<f32>(o)));
    }
    let var_p = var_sum / max(var_w, 1e-6);
    let l_p = svgf_luma(ind[4]);
    let scale_ao = 1.0 / (params.sigma_l * sqrt(var_p.x) + 1e-4);
    let scale_l = 1.0 / (params.sigma_l * sqrt(var_p.y) + 1e-4 * (1.0 + l_p));
    var sum_ao = vec2<f32>(0.0);
    var sum_env = vec3<f32>(0.0);
    var w_ao = 0.0;
    var sum_ind = vec3<f32>(0.0);
    var var_l = 0.0;
    var w_l = 0.0;
    for (var k = 0; k < 9; k++) {
        let g = geo[k];
        if g <= 0.0 {
            continue;
        }
        var wa = g * reach[k];
        var wl = g;
        if params.sigma_l > 0.0 {
            wa *= exp(-abs(sig[k].x - centre.x) * scale_ao);
            wl *= exp(-abs(svgf_luma(ind[k]) - l_p) * scale_l);
        }
        sum_ao += vec2<f32>(wa * sig[k].x, wa * wa * sig[k].y);
        sum_env += wa * env[k];
        w_ao += wa;
        sum_ind += wl * ind[k];
        var_l += wl * wl * sig[k].z;
        w_l += wl;
    }
    // The centre's own tap has weight h(0)² > 0, so both sums are positive.
    let ia = 1.0 / max(w_ao, 1e-12);
    let il = 1.0 / max(w_l, 1e-12);
    textureStore(out_signal, pixel, vec4<f32>(sum_ao.x * ia, sum_ao.y * ia * ia, var_l * il * il, centre.w));
    textureStore(out_env, pixel, vec4<f32>(sum_env * ia, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(sum_ind * il, 1.0));
}

// search.wgsl — the horizon search in slices (the `horizon` kernel): ao, bent cone, near-field light and the far field through each slice's visible arcs.
// Derivations and sources: technique/horizon/mod.rs.

// horizon: one invocation per pixel of one layer. The 16 layers are stacked vertically in one
// 2D dispatch (rows of workgroups [l·G, (l+1)·G) with G = ⌈layer height / 8⌉ serve layer l);
// without interleaving there is one full-size layer.
// Inputs: with interleaving `in_normal` is the split geometry (xyz normal, w depth) and
// `in_depth` is not read; without, they are the G-buffer's normal and view depth.

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var in_depth: texture_2d_array<f32>;
@group(1) @binding(2) var in_normal: texture_2d_array<f32>;
@group(1) @binding(3) var in_radiance: texture_2d_array<f32>;
@group(1) @binding(4) var out_cone: texture_storage_2d_array<rgba16float, write>;
@group(1) @binding(5) var out_near: texture_storage_2d_array<rgba16float, write>;
@group(1) @binding(6) var out_far: texture_storage_2d_array<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn horizon(@builtin(global_invocation_id) id: vec3<u32>) {
    let rows = ((params.layer_height + 7u) / 8u) * 8u;
    let texel = vec2<u32>(id.x, id.y % rows);
    let layer = id.y / rows;
    if texel.x >= params.layer_width || texel.y >= params.layer_height {
        return;
    }
    let pixel = layer_pixel(texel, layer);
    let centre = geometry(vec2<i32>(texel), layer);
    let depth = centre.w;
    if !in_bounds(pixel) || depth <= 0.0 {
        textureStore(out_cone, texel, layer, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        textureStore(out_near, texel, layer, vec4<f32>(0.0));
        textureStore(out_far, texel, layer, vec4<f32>(0.0));
        return;
    }
    // Environment mip of about 32×16 texels (11°) for the arc integration.
    let far_lod = max(frame.env_radiance_mips - 5.0, 0.0);
    let n = normalize(centre.xyz);
    let x = world_position(pixel, depth);
    let lf = local_frame(x);
    let omega_o = lf.o;
    let omega_x = lf.x;
    let omega_y = lf.y;

    let r_layer = march_reach(depth);
    let cell = cell_index(pixel);
    let frame_jitter = golden(frame.frame_index);
    let step_jitter = fract(noise(pixel) + golden(frame.frame_index + 7u));
    let x_screen = to_screen(frame.clip_from_world, x);
    let layer_size = vec2<i32>(i32(params.layer_width), i32(params.layer_height));
    let fade_width = max(params.falloff * params.radius, 1e-6);

    var ao = 0.0;
    var unoccluded = 0.0;
    var bent = vec3<f32>(0.0);
    var near = vec3<f32>(0.0);
    var far = vec3<f32>(0.0);
    let slices = SLICES;
    for (var k = 0u; k < slices; k++) {
        let phi = slice_phi(k, slices, cell, frame_jitter);
        let d = cos(phi) * omega_x + sin(phi) * omega_y;
        let np = vec2<f32>(dot(n, d), dot(n, omega_o));
        // Normal of the slice plane: samples snapped to texel centres are projected back into it.
        let slice_normal = cross(d, omega_o);
        let gamma = atan2(np.x, np.y);
        // Screen direction of the slice (unit, in pixels).
        let dir = slice_screen_dir(x, x_screen, d, depth);
        // side 0: front (+dir, θ ≥ 0), side 1: back (−dir, θ ≤ 0).
        var theta_side = array<f32, 2>(min(gamma + 0.5 * PI, PI), max(gamma - 0.5 * PI, -PI));
        unoccluded += slice_g(theta_side[0], np) + slice_g(theta_side[1], np);
        for (var side = 0u; side < 2u; side++) {
            let side_sign = select(1.0, -1.0, side == 1u);
            let theta_init = theta_side[side];
            var cos_max = cos(theta_init);
            var theta = theta_init;
            var radiance = vec3<f32>(0.0);
            for (var j = 0u; j < STEPS; j++) {
                let t = r_layer * pow((f32(j) + step_jitter) / f32(STEPS), params.step_power);
                let offset = side_sign * dir * max(t, 1.0);
                let pos = vec2<f32>(texel) + 0.5 + offset;
                let q = vec2<i32>(floor(pos));
                if any(q < vec2<i32>(0)) || any(q >= layer_size) {
                    break;
                }
                let qg = geometry(q, layer);
                let qd = qg.w;
                if qd <= 0.0 {
                    continue;
                }
                let qn = normalize(qg.xyz);
                let q_centre = world_position(layer_pixel(vec2<u32>(q), layer), qd);
                // The texel centre is off the slice line by up to half a texel: slide along the
                // sample's tangent plane to the point seen exactly on the line (exact on planes).
                let on_line = on_slice_line(pos, layer, q_centre, qn);
                if on_line.w == 0.0 {
                    continue;
                }
                let v = on_line.xyz - x;
                let dist = length(v);
                if dist >= params.radius || dist < 1e-6 {
                    continue;
                }
                let vs = v - dot(v, slice_normal) * slice_normal;
                let cos_s = dot(vs, omega_o) / max(length(vs), 1e-9);
                let fade = clamp((params.radius - dist) / fade_width, 0.0, 1.0);
                let cos_h = mix(cos(theta_init), cos_s, fade);
                if params.indirect == 1u {
                    let accept = smoothstep(params.reject_a, params.reject_b, -dot(qn, v / dist));
                    radiance = mix(radiance, textureLoad(in_radiance, q, layer, 0).rgb, accept);
                }
                if cos_h > cos_max {
                    let theta_new = side_sign * acos(clamp(cos_h, -1.0, 1.0));
                    if params.indirect == 1u {
                        near += radiance * max(slice_g(theta, np) - slice_g(theta_new, np), 0.0);
                    }
                    cos_max = cos_h;
                    theta = theta_new;
                }
            }
            theta_side[side] = theta;
        }
        let t1 = theta_side[0];
        let t0 = theta_side[1];
        if params.far == 3u {
            // The visible arcs [θ0, 0] and [0, θ1], each in far_steps pieces of equal angle:
            // L_env at the piece's middle × ∫ (n′·ω) |sin θ| dθ over the piece.
            for (var side = 0u; side < 2u; side++) {
                let end = theta_side[side];
                for (var k = 0u; k < params.far_steps; k++) {
                    let a = end * f32(k) / f32(params.far_steps);
                    let b = end * f32(k + 1u) / f32(params.far_steps);
                    let m = 0.5 * (a + b);
                    let w = abs(slice_g(b, np) - slice_g(a, np));
                    far += env_radiance_at(sin(m) * d + cos(m) * omega_o, far_lod) * w;
                }
            }
        }
        ao += slice_g(t1, np) + slice_g(t0, np);
        let bx = slice_g(t1, vec2<f32>(1.0, 0.0)) + slice_g(t0, vec2<f32>(1.0, 0.0));
        let by = slice_g(t1, vec2<f32>(0.0, 1.0)) + slice_g(t0, vec2<f32>(0.0, 1.0));
        bent += d * bx + omega_o * by;
    }
    // Ratio estimator: divide by the same slices' value for an open hemisphere (their mean is 1
    // over all φ), so that a plane gives exactly 1 with any slice count.
    let norm = max(unoccluded, 1e-6);
    ao = clamp(ao / norm, 0.0, 1.0);
    near /= norm;
    let b = select(n, normalize(bent), dot(bent, bent) > 1e-12);
    textureStore(out_cone, texel, layer, vec4<f32>(b, ao));
    textureStore(out_near, texel, layer, vec4<f32>(near, 1.0));
    textureStore(out_far, texel, layer, vec4<f32>(far / norm, 1.0));
}

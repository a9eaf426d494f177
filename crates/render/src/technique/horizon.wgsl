// horizon.wgsl — horizon-based techniques: `gtao` (Jimenez et al. 2016) and `hbil` (Mayaux 2018,
// "Horizon-Based Indirect Lighting"). Entry points, in frame order:
//   split     deinterleave depth, normal and source radiance into 4×4 quarter-resolution layers
//             (HBIL Sec. 3.3; only with interleaving)
//   horizon   the horizon search: AO, bent normal and near-field irradiance per pixel
//   merge     re-interleave the layers' results to full resolution (only with interleaving)
//   accumulate  temporal accumulation with disocclusion rejection (history ping-pong)
//   outputs   ao, env-irradiance (far field through the bent cone), indirect-irradiance and the
//             diffuse radiance kept for the next frame (HBIL Eq. 17)
//
// Horizon search (HBIL Sec. 1.1–1.3, 2.1). At the surface point x (normal n) the local camera
// frame is ω_o = normalize(eye − x), ω_x = normalize(Y × ω_o) with Y the camera's up vector,
// ω_y = ω_o × ω_x. Slice φ has the tangent direction D(φ) = cos φ ω_x + sin φ ω_y; the plane
// spanned by ω_o and D contains the eye, so it projects to a straight screen line through x,
// which is marched both ways. A sample s on it lies in the slice (up to the snap to a texel
// centre, removed by projecting s − x onto the slice plane), and its angle from ω_o is
// exactly cos θ = (s − x)·ω_o / |s − x| — the local-camera horizon angle that Sec. 1.3 obtains
// from the camera-space angle β by cos θ = (cos α z + sin α r)/√(r² + z²); computing it from the
// vector in the local frame is the same correction without the intermediate angles.
// Horizons are initialised from the normal (Sec. 2.1): with the projected normal
// n′ = (n·D, n·ω_o) at slice angle γ = atan2(n′x, n′y), θ_front = γ + π/2 and θ_back = γ − π/2,
// so they never fall below the tangent plane. Only samples within the near-field radius R count
// (DESIGN.md's V_R); over the last `falloff`·R their rise fades out (GTAO's falloff).
// Steps: t_j = r_px ((j + ξ)/steps)^power along the screen line, r_px the screen length of R at
// the point (capped by `max_pixels`), ξ a per-pixel, per-frame jitter; with 4×4 interleaving the
// march reads the pixel's own quarter-resolution layer, so offsets are multiples of 4 pixels.
//
// Slice integrals. For one slice with horizons θ0 ≤ 0 ≤ θ1 and n′ = (nx, ny) (unnormalised, so
// that slices weigh by the projected normal's length as in GTAO), every quantity is an integral
// ∫ f(θ) |sin θ| dθ over [θ0, θ1], and with
//     G(θ) = ½ nx (θ − sin θ cos θ) + ½ ny sin² θ
// (one antiderivative serves both sides because θ − sin θ cos θ is odd and sin² θ even):
//   AO_i   = G(θ1) + G(θ0)                                            (HBIL Eq. 10–11)
//   ñ′     = (Gx(θ1) + Gx(θ0), Gy(θ1) + Gy(θ0)),  Gx: n′ = (1, 0), Gy: n′ = (0, 1)   (Eq. 4–6)
//   ΔE     = L_d(x′) (G(θ_old) − G(θ_new)) when a sample raises a horizon from θ_old to θ_new
//                                                                       (Eq. 18, both sides)
// Deviation: the paper prints Eq. 6 and Eq. 11 as ½ nx [θ1 − θ0 + sin θ0 cos θ0 − sin θ1 cos θ1];
// with θ0 ≤ 0 that is not the integral of sin θ |sin θ| (it gives ñx = π/2 for the symmetric
// horizons ±π/2, where the true value is 0); the G form above is the exact integral and agrees
// with Jimenez et al.'s per-side â(h). AO = Σ_i AO_i / Σ_i U_i and E_near = Σ_i Σ ΔE / Σ_i U_i
// (both carry the 1/π of DESIGN.md's AOVs), bent normal = normalize(Σ_i D ñx + ω_o ñy), where
// U_i = G(θ_front,init) + G(θ_back,init) is slice i's value for an open hemisphere. The paper's
// mean (1/S) Σ AO_i is unbiased only over uniformly spread φ — a single tilted slice of an open
// plane gives |n′| (cos γ + γ sin γ) ≠ 1 — so with 2 slices per pixel a plane would read as
// noise around 1; the ratio (same expectation, since E[U_i] = 1) is exactly 1 there.
// Near field (Sec. 2.3, 3.4): L_d(x′) is read from the source radiance (this frame's direct
// radiance on the first frame, else last frame's diffuse radiance reprojected); a sample whose
// normal faces away from x is replaced by the last accepted one:
// L ← mix(L, L(x′), smoothstep(a, b, −n′·ω)), ω = normalize(x′ − x). Eq. 19's (1 − F0) is the
// receiver's, so it is applied once per pixel in `outputs`.
// Slice angles: pixel cell c (its position in a 4×4 block, Bayer order) and slice k of S take
// φ = π (k + (c + ξ_frame)/16) / S: the 16 cells × S slices of a block cover [0, π) evenly
// (32 directions for S = 2, the paper's setting), and ξ_frame (golden-ratio sequence) turns
// them from frame to frame for the temporal accumulation.

struct HorizonParams {
    radius: f32,
    slices: u32,
    steps: u32,
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
    // Far field: 0 ao × SH irradiance (gtao), 1 SH through the bent cone, 2 pre-convolved map
    // × F0(ao).
    far: u32,
    // 1: (1 − F0) on the near-field irradiance (HBIL Eq. 19).
    fresnel: u32,
    // History rejection: tangent-plane distance relative to view depth, normal cosine.
    reject_depth: f32,
    reject_normal: f32,
    // Cone aperture from ao: 0 cos α = 1 − ao (Eq. 12), 1 cos α = √(1 − ao) (matched).
    aperture: u32,
    // Sub-arcs per side of the environment integration (far = 3).
    far_steps: u32,
}

@group(0) @binding(5) var<uniform> params: HorizonParams;

const BAYER4: array<u32, 16> = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);

fn cell_index(pixel: vec2<u32>) -> u32 {
    return BAYER4[(pixel.x % 4u) + 4u * (pixel.y % 4u)];
}

fn golden(i: u32) -> f32 {
    return fract(f32(i % 4096u) * 0.618034);
}

fn noise(pixel: vec2<u32>) -> f32 {
    let c = vec2<f32>(pixel) + 0.5;
    return fract(52.9829189 * fract(0.06711056 * c.x + 0.00583715 * c.y));
}

// ---------------------------------------------------------------------------------------------
// split: full resolution → 16 layers (layer = (x % 4) + 4 (y % 4), texel = (x / 4, y / 4)).

@group(0) @binding(11) var full_depth: texture_2d<f32>;
@group(0) @binding(12) var full_normal: texture_2d<f32>;
@group(0) @binding(13) var full_radiance: texture_2d<f32>;
// xyz: normal, w: view depth (0 on background) — one fetch per horizon sample.
@group(0) @binding(23) var split_geometry: texture_storage_2d_array<rgba32float, write>;
@group(0) @binding(24) var split_radiance: texture_storage_2d_array<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn split(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = id.xy;
    if texel.x >= params.layer_width || texel.y >= params.layer_height {
        return;
    }
    for (var layer = 0u; layer < 16u; layer++) {
        let pixel = texel * 4u + vec2<u32>(layer % 4u, layer / 4u);
        var depth = 0.0;
        var normal = vec4<f32>(0.0);
        var radiance = vec4<f32>(0.0);
        if in_bounds(pixel) {
            normal = textureLoad(full_normal, pixel, 0);
            depth = select(0.0, textureLoad(full_depth, pixel, 0).r, normal.w != 0.0);
            if params.indirect == 1u {
                radiance = textureLoad(full_radiance, pixel, 0);
            }
        }
        textureStore(split_geometry, texel, layer, vec4<f32>(normal.xyz, depth));
        if params.indirect == 1u {
            textureStore(split_radiance, texel, layer, radiance);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// horizon: one invocation per pixel of one layer. The 16 layers are stacked vertically in one
// 2D dispatch (rows of workgroups [l·G, (l+1)·G) with G = ⌈layer height / 8⌉ serve layer l);
// without interleaving there is one full-size layer.
// Inputs: with interleaving `in_normal` is the split geometry (xyz normal, w depth) and
// `in_depth` is not read; without, they are the G-buffer's normal and view depth.

@group(0) @binding(8) var in_depth: texture_2d_array<f32>;
@group(0) @binding(9) var in_normal: texture_2d_array<f32>;

// Normal (xyz) and view depth (w) of a layer texel.
fn geometry(q: vec2<i32>, layer: u32) -> vec4<f32> {
    let g = textureLoad(in_normal, q, layer, 0);
    if params.scale == 1u {
        return vec4<f32>(g.xyz, select(0.0, textureLoad(in_depth, q, layer, 0).r, g.w != 0.0));
    }
    return g;
}
@group(0) @binding(10) var in_radiance: texture_2d_array<f32>;
@group(0) @binding(20) var out_cone: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(21) var out_near: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(43) var out_far: texture_storage_2d_array<rgba16float, write>;

fn layer_pixel(texel: vec2<u32>, layer: u32) -> vec2<u32> {
    return texel * params.scale + vec2<u32>(layer % params.scale, layer / params.scale);
}

// The surface point seen through layer position `pos` (continuous texel coordinates), taken on
// the tangent plane (point `centre`, normal `n`) of the texel it falls in;
// w = 0 when the ray through `pos` misses that plane (it passes above a horizon line: the texel
// centre is not what the slice sees there, and the sample is skipped).
fn on_slice_line(pos: vec2<f32>, layer: u32, centre: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let scale = f32(params.scale);
    let full = (pos - 0.5) * scale + vec2<f32>(f32(layer % params.scale), f32(layer / params.scale)) + 0.5;
    let uv = full * frame.size.zw;
    let ndc = vec2<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
    let t = frame.projection.w;
    let dir_view = vec3<f32>(ndc.x * t * frame.projection.z, ndc.y * t, -1.0);
    let r = (frame.world_from_view * vec4<f32>(dir_view, 0.0)).xyz;
    let eye = frame.camera_position.xyz;
    let denom = dot(n, r);
    let along = dot(n, centre - eye) / denom;
    if abs(denom) < 1e-4 * length(r) || along <= 0.0 {
        return vec4<f32>(centre, 0.0);
    }
    return vec4<f32>(eye + r * along, 1.0);
}

// ½ nx (θ − sin θ cos θ) + ½ ny sin² θ.
fn slice_g(theta: f32, n: vec2<f32>) -> f32 {
    let s = sin(theta);
    let c = cos(theta);
    return 0.5 * n.x * (theta - s * c) + 0.5 * n.y * s * s;
}

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
    let far_lod = max(frame.env_params.w - 5.0, 0.0);
    let n = normalize(centre.xyz);
    let x = world_position(pixel, depth);
    let omega_o = normalize(frame.camera_position.xyz - x);
    let up = normalize(frame.world_from_view[1].xyz);
    var omega_x = cross(up, omega_o);
    if dot(omega_x, omega_x) < 1e-8 {
        omega_x = normalize(frame.world_from_view[0].xyz);
    }
    omega_x = normalize(omega_x);
    let omega_y = cross(omega_o, omega_x);

    // Screen length of R at x, as if the occluder were up to R nearer the camera.
    let focal = 0.5 * frame.size.y / frame.projection.w;
    let r_px = min(params.max_pixels, params.radius * focal / max(depth - params.radius, 0.2 * depth));
    let r_layer = r_px / f32(params.scale);
    let cell = cell_index(pixel);
    let frame_jitter = golden(frame.counts.x);
    let step_jitter = fract(noise(pixel) + golden(frame.counts.x + 7u));
    let x_screen = to_screen(frame.clip_from_world, x);
    let layer_size = vec2<i32>(i32(params.layer_width), i32(params.layer_height));
    let fade_width = max(params.falloff * params.radius, 1e-6);

    var ao = 0.0;
    var unoccluded = 0.0;
    var bent = vec3<f32>(0.0);
    var near = vec3<f32>(0.0);
    var far = vec3<f32>(0.0);
    let slices = params.slices;
    for (var k = 0u; k < slices; k++) {
        let phi = PI * (f32(k) + (f32(cell) + frame_jitter) / 16.0) / f32(slices);
        let d = cos(phi) * omega_x + sin(phi) * omega_y;
        let np = vec2<f32>(dot(n, d), dot(n, omega_o));
        // Normal of the slice plane: samples snapped to texel centres are projected back into it.
        let slice_normal = cross(d, omega_o);
        let gamma = atan2(np.x, np.y);
        // Screen direction of the slice (unit, in pixels).
        var dir = to_screen(frame.clip_from_world, x + d * (0.01 * depth)) - x_screen;
        if dot(dir, dir) < 1e-12 {
            dir = vec2<f32>(1.0, 0.0);
        }
        dir = normalize(dir);
        // side 0: front (+dir, θ ≥ 0), side 1: back (−dir, θ ≤ 0).
        var theta_side = array<f32, 2>(min(gamma + 0.5 * PI, PI), max(gamma - 0.5 * PI, -PI));
        unoccluded += slice_g(theta_side[0], np) + slice_g(theta_side[1], np);
        for (var side = 0u; side < 2u; side++) {
            let side_sign = select(1.0, -1.0, side == 1u);
            let theta_init = theta_side[side];
            var cos_max = cos(theta_init);
            var theta = theta_init;
            var radiance = vec3<f32>(0.0);
            for (var j = 0u; j < params.steps; j++) {
                let t = r_layer * pow((f32(j) + step_jitter) / f32(params.steps), params.step_power);
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

// ---------------------------------------------------------------------------------------------
// merge: layers → full resolution.

@group(0) @binding(14) var layered_cone: texture_2d_array<f32>;
@group(0) @binding(15) var layered_near: texture_2d_array<f32>;
@group(0) @binding(25) var merged_cone: texture_storage_2d<rgba16float, write>;
@group(0) @binding(26) var merged_near: texture_storage_2d<rgba16float, write>;
@group(0) @binding(44) var layered_far: texture_2d_array<f32>;
@group(0) @binding(45) var merged_far: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn merge(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let texel = pixel / 4u;
    let layer = (pixel.x % 4u) + 4u * (pixel.y % 4u);
    textureStore(merged_cone, pixel, textureLoad(layered_cone, texel, layer, 0));
    textureStore(merged_near, pixel, textureLoad(layered_near, texel, layer, 0));
    textureStore(merged_far, pixel, textureLoad(layered_far, texel, layer, 0));
}

// ---------------------------------------------------------------------------------------------
// accumulate: running mean over up to `max_history` frames of the bent cone (xyz bent normal,
// w ao), the near-field irradiance (w = frames in the mean) and the far field. Last frame's
// accumulation is fetched where this surface point was (previous camera), bilinearly from the
// taps that pass the disocclusion test `same_surface` (common.wgsl) with the tap's surface point
// rebuilt from last frame's depth and camera: near this point's tangent plane (reject_depth ×
// depth), with a normal within acos(reject_normal), and within a few pixel footprints of it.
// No passing tap (or no history: first frame, camera cut, temporal off) restarts the mean at
// this frame's value.

@group(0) @binding(16) var gb_normal: texture_2d<f32>;
@group(0) @binding(17) var gb_view_depth: texture_2d<f32>;
@group(0) @binding(18) var raw_cone: texture_2d<f32>;
@group(0) @binding(19) var raw_near: texture_2d<f32>;
@group(0) @binding(27) var prev_cone: texture_2d<f32>;
@group(0) @binding(28) var prev_near: texture_2d<f32>;
@group(0) @binding(29) var prev_geometry: texture_2d<f32>;
@group(0) @binding(30) var acc_cone: texture_storage_2d<rgba16float, write>;
@group(0) @binding(31) var acc_near: texture_storage_2d<rgba16float, write>;
@group(0) @binding(32) var acc_geometry: texture_storage_2d<rgba32float, write>;
@group(0) @binding(46) var raw_far: texture_2d<f32>;
@group(0) @binding(47) var prev_far: texture_2d<f32>;
@group(0) @binding(48) var acc_far: texture_storage_2d<rgba16float, write>;

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
    if params.temporal == 1u && frame.history.x == 1u {
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

// ---------------------------------------------------------------------------------------------
// outputs: the AOVs and the diffuse radiance for the next frame.
//   ao                   accumulated cone .w
//   env-irradiance       far = 0 (gtao):   ao × E_SH(n)/π
//                        far = 1 (sh):     SH irradiance through the bent cone (Sec. 2.2.4),
//                                          aperture cos α = 1 − ao (Eq. 12) or, `matched`,
//                                          cos α = √(1 − ao). Deviation: Eq. 12 equates the
//                                          cone's solid angle with 2π ao, which holds for the
//                                          uniformly weighted AO of Eq. 1, but the AO here is
//                                          the cosine-weighted one of Eq. 9; a cone about the
//                                          normal has cosine-weighted visibility sin² α, so
//                                          Eq. 12 makes the cone too wide (ao = ½: 60° where
//                                          45° holds ½) and a uniform sky too bright (0.75
//                                          for ao = ½). `matched` takes the cone whose
//                                          cosine-weighted visibility is ao: exact for a
//                                          uniform environment.
//                        far = 2 (envmap): pre-convolved map at the bent normal × F0(ao),
//                                          F0(a) = a (1 + (1 − a)^0.75 / 2) (Sec. 2.2.3)
//                        far = 3 (slices): the environment integrated over each slice's
//                                          visible arcs (horizon pass), accumulated like ao —
//                                          directional, so light from one side (a sun) is
//                                          shadowed by the horizons that hide it
//   indirect-irradiance  accumulated E_near × (1 − F0) with F0 = mix(0.04, ρ, metallic) when
//                        `fresnel` is on (Eq. 19)
//   feedback             L_d = emission + (1 − metallic) ρ (light + env + indirect) irradiance
//                        (Eq. 17), gathered by the next frame

@group(0) @binding(6) var env_irradiance_map: texture_2d<f32>;
@group(0) @binding(33) var gb_albedo: texture_2d<f32>;
@group(0) @binding(34) var gb_material: texture_2d<f32>;
@group(0) @binding(35) var gb_emissive: texture_2d<f32>;
@group(0) @binding(36) var light_irradiance: texture_2d<f32>;
@group(0) @binding(37) var final_cone: texture_2d<f32>;
@group(0) @binding(38) var final_near: texture_2d<f32>;
@group(0) @binding(39) var out_ao: texture_storage_2d<r32float, write>;
@group(0) @binding(40) var out_env: texture_storage_2d<rgba16float, write>;
@group(0) @binding(41) var out_indirect: texture_storage_2d<rgba16float, write>;
@group(0) @binding(42) var out_feedback: texture_storage_2d<rgba16float, write>;
@group(0) @binding(49) var final_far: texture_2d<f32>;

fn energy_compensation(a: f32) -> f32 {
    return a * (1.0 + pow(max(1.0 - a, 0.0), 0.75) * 0.5);
}

@compute @workgroup_size(8, 8, 1)
fn outputs(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_ao, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        textureStore(out_env, pixel, vec4<f32>(0.0));
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        textureStore(out_feedback, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let cone = textureLoad(final_cone, pixel, 0);
    let ao = clamp(cone.w, 0.0, 1.0);
    let bent = select(n, normalize(cone.xyz), dot(cone.xyz, cone.xyz) > 1e-12);
    var env = vec3<f32>(0.0);
    switch params.far {
        case 1u: {
            let cos_alpha = select(1.0 - ao, sqrt(1.0 - ao), params.aperture == 1u);
            env = env_irradiance_cone(bent, cos_alpha);
        }
        case 2u: {
            let e = textureSampleLevel(env_irradiance_map, env_sampler, env_uv(bent), 0.0).rgb;
            env = e * frame.env_params.y * energy_compensation(ao);
        }
        case 3u: {
            env = textureLoad(final_far, pixel, 0).rgb;
        }
        default: {
            env = ao * env_irradiance_sh(n);
        }
    }
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let metallic = textureLoad(gb_material, pixel, 0).r;
    var indirect = textureLoad(final_near, pixel, 0).rgb;
    if params.fresnel == 1u {
        indirect *= 1.0 - mix(vec3<f32>(0.04), albedo, metallic);
    }
    let light = textureLoad(light_irradiance, pixel, 0).rgb;
    let feedback = textureLoad(gb_emissive, pixel, 0).rgb + (1.0 - metallic) * albedo * (light + env + indirect);
    textureStore(out_ao, pixel, vec4<f32>(ao, 0.0, 0.0, 0.0));
    textureStore(out_env, pixel, vec4<f32>(env, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(out_feedback, pixel, vec4<f32>(min(feedback, vec3<f32>(65000.0)), 1.0));
}

// march.wgsl — the horizon search of one pixel (gtao/hbil): slices, their two sides' horizons,
// ao, bent normal, near-field light and the far field through the visible arcs. A library (with
// common.wgsl, env.wgsl, far.wgsl, params.wgsl and slice.wgsl): it declares no bindings; its
// functions take the layer textures (`depth_layers`, `normal_layers`, `radiance_layers`:
// search.wgsl's `in_depth`, `in_normal`, `in_radiance`), the environment's radiance map, the far
// field's probes and visibility, their sampler, the view (`cam`), the environment's uniform
// (`e`) and the pass's `HorizonParams` (`p`) that they read.
// The derivations sit beside the functions that compute them; sources: technique/horizon/mod.rs.

// What one side of a slice march needs.
struct March {
    texel: vec2<f32>,
    layer: u32,
    x: vec3<f32>,
    dir: vec2<f32>,
    omega_o: vec3<f32>,
    slice_normal: vec3<f32>,
    np: vec2<f32>,
    r_layer: f32,
    step_jitter: f32,
    fade_width: f32,
    // `hidden` (volume or unbaked) with a probe volume: a sender facing away may send its
    // hidden face's light, lit by `sh`, the volume's radiance at x.
    hidden: bool,
    sh: FarSh,
}

// The light a sender's hidden face sends back to x (`hidden=volume`, and `unbaked` for a sender
// the bake never saw): the sender's albedo (the
// G-buffer's `albedo` at its full-resolution pixel) times the volume's E/π about the direction
// from the sender back to x (view-space unit `to_x`). The irradiance is read from the volume's
// SH at x rather than at the sender, which lies within R of x: one lookup per pixel instead of
// one per hidden sender, and the same figures (the book, "Near and far"). The volume lights the
// hidden face as it lights what lies around it, whether it saw the sender or not; only a
// shadow-mapped light on that face is missing.
fn hidden_face_radiance(albedo: texture_2d<f32>, cam: View, p: HorizonParams, m: March, q: vec2<i32>, to_x: vec3<f32>) -> vec3<f32> {
    let rho = textureLoad(albedo, full_pixel(p, m, q), 0).rgb;
    return rho * max(far_irradiance(m.sh, to_world(cam, to_x)), vec3<f32>(0.0));
}

// The full-resolution pixel of layer texel q.
fn full_pixel(p: HorizonParams, m: March, q: vec2<i32>) -> vec2<i32> {
    return vec2<i32>(floor(layer_to_full(p, vec2<f32>(q) + 0.5, m.layer)));
}

// Whether the sender at layer texel q sends its hidden face's light: every sender with
// `hidden=volume`; with `hidden=unbaked` only one the bake never saw (the G-buffer's `material`
// b = 1), which the volume holds nothing of, while the faces of what the bake saw keep the
// paper's light (the book, "Near and far").
fn sends_hidden_face(material: texture_2d<f32>, p: HorizonParams, m: March, q: vec2<i32>) -> bool {
    return HIDDEN == 1u || textureLoad(material, full_pixel(p, m, q), 0).b > 0.5;
}

// The side's horizon angle (x) and its near-field irradiance (yzw, NEAR only).
// Only samples within the near-field radius R count
// (V_R of docs/src/aovs.md); over the last `falloff`·R their rise fades out (GTAO's falloff).
// Steps: t_j = r_px ((j + ξ)/steps)^power along the screen line, r_px the screen length of R at
// the point (capped by `max_pixels`), ξ a per-pixel, per-frame jitter; with 4×4 interleaving the
// march reads the pixel's own quarter-resolution layer, so offsets are multiples of 4 pixels.
// Near field (Sec. 2.3, 3.4): L_d(x′) is read from the source radiance (this frame's direct
// radiance on the first frame, else last frame's diffuse radiance reprojected); a sample whose
// normal faces away from x is replaced by the last accepted one:
// L ← mix(L, L(x′), smoothstep(a, b, −n′·ω)), ω = normalize(x′ − x). With `hidden=volume` and a
// probe volume, a rise's sender that faces away sends its hidden face's light instead:
// mix(L_hidden(x′), L(x′), t) (hidden_face_radiance), unless the march's next sample shows it
// thin: one depth layer takes every occluder for a solid reaching back to x, and behind a thin
// one (a post before a wall) the directions it hides see past it, for which the last accepted
// sender's light stands in better than a hidden face that is not there. The next sample shows
// the sender thin when it lies behind it, its view depth beyond the sender's by more than half
// the distance between the two points (the step goes mostly away from the eye); the rise's light
// is then the paper's. Eq. 19's (1 − F0) is the receiver's, so it is applied once per pixel in
// `outputs`.
fn march_side(depth_layers: texture_2d_array<f32>, normal_layers: texture_2d_array<f32>, radiance_layers: texture_2d_array<f32>, albedo: texture_2d<f32>, material: texture_2d<f32>, cam: View, p: HorizonParams, m: March, side_sign: f32, theta_init: f32, cos_init: f32) -> vec4<f32> {
    let layer_size = vec2<i32>(i32(p.layer_width), i32(p.layer_height));
    var cos_max = cos_init;
    var theta = theta_init;
    var near = vec3<f32>(0.0);
    var radiance = vec3<f32>(0.0);
    // The last hidden-face rise, until the next sample says whether its sender is thin: the
    // paper's light less the hidden face's, times the rise's weight, and the sender (view-space
    // point, view depth; w = 0: none pending).
    var pending = vec3<f32>(0.0);
    var pending_at = vec4<f32>(0.0);
    let r2 = p.radius * p.radius;
    for (var j = 0u; j < STEPS; j++) {
        let t = m.r_layer * pow((f32(j) + m.step_jitter) / f32(STEPS), p.step_power);
        let pos = m.texel + 0.5 + side_sign * m.dir * max(t, 1.0);
        let q = vec2<i32>(floor(pos));
        if any(q < vec2<i32>(0)) || any(q >= layer_size) {
            break;
        }
        let qg = geometry(depth_layers, normal_layers, p, q, m.layer);
        let qd = qg.w;
        if qd <= 0.0 {
            continue;
        }
        // The sample's normal in view space (the plane test needs no unit normal).
        let qn = to_view(cam, qg.xyz);
        let q_centre = view_dir(cam, layer_to_full(p, vec2<f32>(q) + 0.5, m.layer)) * qd;
        // The texel centre is off the slice line by up to half a texel: slide along the
        // sample's tangent plane to the point seen exactly on the line (exact on planes).
        let on_line = view_on_slice_line(cam, p, pos, m.layer, q_centre, qn);
        if on_line.w == 0.0 {
            continue;
        }
        if pending_at.w > 0.0 {
            // Thin: this sample lies behind the pending sender.
            if qd - pending_at.w > 0.5 * length(on_line.xyz - pending_at.xyz) {
                near += pending;
            }
            pending_at.w = 0.0;
        }
        let v = on_line.xyz - m.x;
        let d2 = dot(v, v);
        if d2 >= r2 || d2 < 1e-12 {
            continue;
        }
        let dist = sqrt(d2);
        let vs = v - dot(v, m.slice_normal) * m.slice_normal;
        let cos_s = dot(vs, m.omega_o) * inverseSqrt(max(dot(vs, vs), 1e-18));
        let fade = clamp((p.radius - dist) / m.fade_width, 0.0, 1.0);
        let cos_h = mix(cos_init, cos_s, fade);
        var accept = 1.0;
        var lq = vec3<f32>(0.0);
        if NEAR {
            accept = smoothstep(p.reject_a, p.reject_b, -dot(normalize(qn), v / dist));
            lq = textureLoad(radiance_layers, q, m.layer, 0).rgb;
            radiance = mix(radiance, lq, accept);
        }
        if cos_h > cos_max {
            if NEAR {
                let theta_new = side_sign * acos(clamp(cos_h, -1.0, 1.0));
                var sent = radiance;
                let w = max(slice_g(theta, m.np) - slice_g(theta_new, m.np), 0.0);
                if m.hidden && accept < 1.0 && sends_hidden_face(material, p, m, q) {
                    let hidden = hidden_face_radiance(albedo, cam, p, m, q, -v / dist);
                    sent = mix(hidden, lq, accept);
                    pending = (radiance - sent) * w;
                    pending_at = vec4<f32>(on_line.xyz, qd);
                }
                near += sent * w;
                theta = theta_new;
            }
            cos_max = cos_h;
        }
    }
    if !NEAR && cos_max > cos_init {
        // Only the final horizon matters without near-field light: one acos per side.
        theta = side_sign * acos(clamp(cos_max, -1.0, 1.0));
    }
    return vec4<f32>(theta, near);
}

// AO = Σ_i AO_i / Σ_i U_i and E_near = Σ_i Σ ΔE / Σ_i U_i
// (both carry the 1/π of docs/src/aovs.md), bent normal = normalize(Σ_i D ñx + ω_o ñy), where
// U_i = G(θ_front,init) + G(θ_back,init) is slice i's value for an open hemisphere. The paper's
// mean (1/S) Σ AO_i is unbiased only over uniformly spread φ — a single tilted slice of an open
// plane gives |n′| (cos γ + γ sin γ) ≠ 1 — so with 2 slices per pixel a plane would read as
// noise around 1; the ratio (same expectation, since E[U_i] = 1) is exactly 1 there.
// One pixel's results: bent cone (xyz world bent normal, w ao), near-field irradiance, far field.
struct Horizon {
    cone: vec4<f32>,
    near: vec3<f32>,
    far: vec4<f32>,
}

// The search at layer texel `texel` of `layer` (full-resolution `pixel`, in the image), whose
// geometry `centre` (xyz normal, w view depth > 0) was read by the caller. `pattern` picks the
// slice angles' cell and the step jitter: the pixel, or with HALF its 2×2 block. `env_map`: the
// environment's radiance with box-filtered mips (env_radiance_at), `irradiance_map` its
// pre-convolved diffuse map (env_irradiance_exact); `probes`, `visibility`: the
// far field's (far_sh_here); `smp`: the sampler of both; `albedo`, `material`: the G-buffer's
// (a sender's hidden face, `hidden=volume` or `unbaked`).
fn search_pixel(depth_layers: texture_2d_array<f32>, normal_layers: texture_2d_array<f32>, radiance_layers: texture_2d_array<f32>, albedo: texture_2d<f32>, material: texture_2d<f32>, env_map: texture_2d<f32>, irradiance_map: texture_2d<f32>, probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, cam: View, e: EnvUniforms, p: HorizonParams, texel: vec2<u32>, layer: u32, pixel: vec2<u32>, pattern: vec2<u32>, centre: vec4<f32>) -> Horizon {
    let depth = centre.w;
    // Environment mip of about 32×16 texels (11°) for the arc integration.
    let far_lod = max(e.radiance_mips - 5.0, 0.0);
    let n = normalize(to_view(cam, centre.xyz));
    let x = view_dir(cam, vec2<f32>(pixel) + 0.5) * depth;
    let lf = view_local_frame(x);
    // The light of the visible arcs: the environment at a blurred mip, or the probe volume's
    // radiance at this point (its SH read after the slices, applied to the arcs' moments).
    let volume = FAR && far_volume(probes);
    var moments: FarMoments;

    var m: March;
    m.texel = vec2<f32>(texel);
    m.layer = layer;
    m.x = x;
    m.omega_o = lf.o;
    m.r_layer = march_reach(cam, p, depth);
    m.step_jitter = fract(noise(pattern) + golden(cam.frame_index + 7u));
    m.fade_width = max(p.falloff * p.radius, 1e-6);
    let xw = (cam.world_from_view * vec4<f32>(x, 1.0)).xyz;
    // The volume's SH at x: read after the slices, or before them when hidden faces read it.
    m.hidden = HIDDEN != 0u && volume;
    if m.hidden {
        m.sh = far_sh_here(probes, visibility, smp, cam, xw, normalize(centre.xyz));
    }
    let cell = cell_index(pattern);
    let frame_jitter = golden(cam.frame_index);

    var ao = 0.0;
    var unoccluded = 0.0;
    var bent = vec3<f32>(0.0);
    var near = vec3<f32>(0.0);
    var far = vec3<f32>(0.0);
    for (var k = 0u; k < SLICES; k++) {
        let phi = slice_phi(k, SLICES, cell, frame_jitter);
        let d = cos(phi) * lf.x + sin(phi) * lf.y;
        let np = projected_normal(n, d, lf.o);
        // Normal of the slice plane: samples snapped to texel centres are projected back into it.
        m.slice_normal = cross(d, lf.o);
        m.np = np;
        m.dir = view_screen_dir(x, d);
        let gamma = atan2(np.x, np.y);
        // side 0: front (+dir, θ ≥ 0), side 1: back (−dir, θ ≤ 0).
        let init1 = min(gamma + 0.5 * PI, PI);
        let init0 = max(gamma - 0.5 * PI, -PI);
        unoccluded += dot(np, slice_gxy(init1) + slice_gxy(init0));
        let front = march_side(depth_layers, normal_layers, radiance_layers, albedo, material, cam, p, m, 1.0, init1, cos(init1));
        let back = march_side(depth_layers, normal_layers, radiance_layers, albedo, material, cam, p, m, -1.0, init0, cos(init0));
        near += front.yzw + back.yzw;
        let t1 = front.x;
        let t0 = back.x;
        if FAR {
            // The occluded arcs [θ1, init1] and [init0, θ0] (below the horizons), each in
            // far_steps pieces of equal angle: L at the piece's middle × ∫ (n′·ω) |sin θ| dθ over
            // the piece. The pieces' ends and middles step by equal angles: their (cos, sin) by
            // rotation, each end's slice_g once (four sin/cos a side instead of six a piece).
            let d_world = to_world(cam, d);
            let o_world = to_world(cam, lf.o);
            for (var side = 0u; side < 2u; side++) {
                let start = select(t1, t0, side == 1u);
                let h = (select(init1, init0, side == 1u) - start) / f32(p.far_steps);
                let step = vec2<f32>(cos(h), sin(h));
                let half = vec2<f32>(cos(0.5 * h), sin(0.5 * h));
                // (cos, sin) of the piece's start a, and slice_g(a).
                var ca = vec2<f32>(cos(start), sin(start));
                var ga = slice_g_at(start, ca, np);
                for (var s = 0u; s < p.far_steps; s++) {
                    let b = start + h * f32(s + 1u);
                    let cb = rotate_angle(ca, step);
                    let gb = slice_g_at(b, cb, np);
                    let w = abs(gb - ga);
                    let mid = rotate_angle(ca, half);
                    let omega = mid.y * d_world + mid.x * o_world;
                    if volume {
                        far_moments_add(&moments, omega, w);
                    } else {
                        far += env_radiance_at(env_map, smp, e, omega, far_lod) * w;
                    }
                    ca = cb;
                    ga = gb;
                }
            }
        }
        let g = slice_gxy(t1) + slice_gxy(t0);
        ao += dot(np, g);
        bent += d * g.x + lf.o * g.y;
    }
    // The far field: the open hemisphere's irradiance E(n)/π (the volume's SH, or the
    // environment's pre-convolved map) less the light of the occluded arcs, each slice's integral
    // an unbiased estimate of the hemisphere's (φ uniform, the open slices' mean weight 1):
    //   far = E(n)/π − (1/S) Σ_slices ∫_occluded L (n′·ω) |sin θ| dθ,
    // exact wherever nothing is occluded, whatever the slices. The ratio over the visible arcs,
    // Σ ∫_visible L … / Σ U, was biased where L varies with the slice's weight U (the book, vbgi,
    // "The far field's estimator").
    if FAR {
        let nw = normalize(centre.xyz);
        var open = vec3<f32>(0.0);
        if volume {
            if !m.hidden {
                m.sh = far_sh_here(probes, visibility, smp, cam, xw, nw);
            }
            far = far_apply(m.sh, moments);
            open = far_irradiance(m.sh, nw);
        } else {
            open = env_irradiance_exact(irradiance_map, smp, e, nw);
        }
        far = max(open - far / f32(SLICES), vec3<f32>(0.0));
    }
    // Ratio estimator: divide by the same slices' value for an open hemisphere (their mean is 1
    // over all φ), so that a plane gives exactly 1 with any slice count.
    let norm = max(unoccluded, 1e-6);
    ao = clamp(ao / norm, 0.0, 1.0);
    let b = select(n, normalize(bent), dot(bent, bent) > 1e-12);
    var r: Horizon;
    r.cone = vec4<f32>(to_world(cam, b), ao);
    r.near = near / norm;
    r.far = vec4<f32>(far, 1.0);
    return r;
}

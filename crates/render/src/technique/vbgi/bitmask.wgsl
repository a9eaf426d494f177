// bitmask.wgsl — vbgi's slice march with a visibility bitmask per slice (the `bitmask` kernel):
// ao, bent normal, near-field light from the newly occupied sectors, the far field through the
// unoccupied ones (after Therrien et al. 2023; overview and sources: technique/vbgi/mod.rs).
// Each derivation stands at the lines that compute it.

// bitmask: one invocation per pixel of one layer, the 16 layers stacked vertically as in
// search.wgsl (technique/horizon). Inputs as there, and `in_back`: the view depth of the second
// depth layer (0 where there is none), split like the geometry with interleaving. With HALF
// (`resolution=half`) one invocation per 2×2 block instead, as there.

struct VbgiParams {
    // 0 layer, 1 constant, 2 adaptive.
    thickness: u32,
    thickness_m: f32,
    thickness_ratio: f32,
    _pad0: u32,
}

// Sectors of a slice's half circle (8, 16 or 32 bits of the mask).
override SECTORS: u32 = 32u;

// Two consecutive samples bound one solid when neither lies in front of the other's tangent
// plane by more than this fraction of the step between them (about 14°).
const CONTINUITY: f32 = 0.25;


@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var<uniform> vbgi: VbgiParams;
@group(1) @binding(2) var in_depth: texture_2d_array<f32>;
@group(1) @binding(3) var in_normal: texture_2d_array<f32>;
@group(1) @binding(4) var in_radiance: texture_2d_array<f32>;
@group(1) @binding(5) var in_back: texture_2d_array<f32>;
@group(1) @binding(6) var in_back_radiance: texture_2d_array<f32>;
@group(1) @binding(7) var out_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(8) var out_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(9) var out_far: texture_storage_2d<rgba16float, write>;

// Cosine weighting (`ao` is (1/π) ∫ V cos θ dω, docs/src/aovs.md). In the slice the measure of
// the hemisphere integral is |sin θ| dθ dφ/… and the integrand n·ω = n′·ω(θ) with the projected
// normal n′ = (n·D, n·ω_o) (unnormalised: slices weigh by its length, as in GTAO). With G of
// technique/horizon (slice_g), the weight of the angles [a, b] is W(a, b) = S(b) − S(a),
//     S(θ) = ∫_0^θ (n′·ω(t)) |sin t| dt = sign(θ) G(θ),
// exact on either side of ω_o and across it (G's first term is odd, its second even).
// Uniformly counted sectors (popcount / N, the peers' estimator) give the uniformly weighted
// visibility instead: a wall meeting the floor at 90° reads 0.5 at its base either way, but
// along the floor the uniform count is off the cosine-weighted curve.
fn slice_s(theta: f32, np: vec2<f32>) -> f32 {
    return sign(theta) * slice_g(theta, np);
}

// Bits [s, e) of a u32 (0 ≤ s, e ≤ 32); none when e ≤ s.
fn bit_range(s: u32, e: u32) -> u32 {
    if e <= s {
        return 0u;
    }
    let count = e - s;
    let ones = select((1u << count) - 1u, 0xffffffffu, count >= 32u);
    return ones << s;
}

// The projected-cosine weight of the set bits of `m`: Σ over its runs [s, e) of
// cum[e] − cum[s], with cum the slice's prefix weights. A u32 has at most 16 runs and each trip
// clears one, so the loop's bound is written out (kernels are compiled without wgpu's loop
// bounding: architecture.md, "Loop bounds").
fn mask_weight(m: u32, cum: ptr<function, array<f32, 33>>) -> f32 {
    var w = 0.0;
    var r = m;
    for (var run = 0u; run < 16u && r != 0u; run++) {
        let s = firstTrailingBit(r);
        let rest = ~(r >> s);
        var count = 32u - s;
        if rest != 0u {
            count = min(firstTrailingBit(rest), count);
        }
        w += (*cum)[s + count] - (*cum)[s];
        r &= ~bit_range(s, s + count);
    }
    return w;
}

// The signed slice angle from ω_o of direction `v` (side_sign: + towards D, − away).
fn slice_angle(v: vec3<f32>, slice_normal: vec3<f32>, omega_o: vec3<f32>, side_sign: f32) -> f32 {
    let vs = v - dot(v, slice_normal) * slice_normal;
    return side_sign * fast_acos(dot(vs, omega_o) * inverseSqrt(max(dot(vs, vs), 1e-18)));
}

// acos to within 7e-5 rad (Abramowitz & Stegun 4.4.45), a fraction of a 32-sector bin (0.098 rad).
fn fast_acos(x: f32) -> f32 {
    let a = min(abs(x), 1.0);
    let r = sqrt(1.0 - a) * (1.5707288 + a * (-0.2121144 + a * (0.0742610 - 0.0187293 * a)));
    return select(PI - r, r, x >= 0.0);
}

// The angle range [lo, hi] of the part within R of x of the chord from front point `p` to its
// back, `tau` behind it along the camera ray (tau < 0: to infinity); w = 0 when no part of the
// chord is within R (V_R of docs/src/aovs.md: an occluder counts where it is hit within R).
fn chord(p: vec3<f32>, tau: f32, x: vec3<f32>, eye: vec3<f32>, slice_normal: vec3<f32>, omega_o: vec3<f32>, side_sign: f32) -> vec3<f32> {
    let v = p - x;
    let ray = normalize(p - eye);
    // |v + s ray| = R at s = −b ∓ √(b² − c).
    let b = dot(v, ray);
    let disc = b * b - (dot(v, v) - params.radius * params.radius);
    if disc <= 0.0 {
        return vec3<f32>(0.0);
    }
    let root = sqrt(disc);
    let s0 = max(-b - root, 0.0);
    let s1 = select(-b + root, min(-b + root, tau), tau >= 0.0);
    if s1 <= s0 {
        return vec3<f32>(0.0);
    }
    let front = slice_angle(v + ray * s0, slice_normal, omega_o, side_sign);
    let back = slice_angle(v + ray * s1, slice_normal, omega_o, side_sign);
    return vec3<f32>(min(front, back), max(front, back), 1.0);
}

// Sectors. In slice φ (plane of ω_o and D(φ), angles θ from ω_o, positive towards D, as in
// technique/horizon) the hemisphere above the tangent plane is θ ∈ [γ − π/2, γ + π/2], γ the
// projected normal's angle. It is cut into N = SECTORS sectors of equal angle, sector b covering
// [θ_b, θ_b+1], θ_b = γ − π/2 + π b/N; a u32 per slice holds which are occupied. A march sample
// x′ (within R) with front direction v = x′ − x and back v_b = v + τ r̂ (r̂ the camera ray
// through x′, τ its thickness along the ray: `chord`) occupies the sectors between its angles.
// The sectors an angle range covers, its ends rounded with `jitter` (stochastic rounding: the
// same for all samples of a pixel, so that adjacent ranges tile without gaps; a sector's
// expected coverage is the exact fraction of it in the range).
fn range_bits(range: vec2<f32>, base: f32, jitter: f32) -> u32 {
    let sectors = f32(SECTORS);
    let lo = floor((range.x - base) / PI * sectors + jitter);
    let hi = floor((range.y - base) / PI * sectors + jitter);
    return bit_range(u32(clamp(lo, 0.0, sectors)), u32(clamp(hi, 0.0, sectors)));
}

// The radiance a sender at split texel `q` sends towards the receiver: its front (the radiance
// source) where the front faces the receiver (`accept`, HBIL Sec. 3.4's smoothstep on −n_x′·v̂),
// and where it faces away, with a second layer behind it (`back`), the second layer's direct
// radiance: a receiver behind a thin occluder (a post before a wall, a box seen from behind)
// sees the occluder's rear, which the screen does not show but the depth peel does. Without a
// second layer the rear is unknown and sends nothing; so does it under the open sky, where the
// layer's shading takes the sky unoccluded, too bright for a rear that faces what lies behind
// the occluder (the book, vbgi, "The occluder's rear"). With a probe volume the rear is lit by
// the volume's irradiance at its normal, as every surface of the frame is.
fn sender_radiance(q: vec2<i32>, layer: u32, accept: f32, back: bool) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    if accept > 0.0 {
        l += accept * textureLoad(in_radiance, q, layer, 0).rgb;
    }
    if back && accept < 1.0 {
        l += (1.0 - accept) * textureLoad(in_back_radiance, q, layer, 0).rgb;
    }
    return l;
}

@compute @workgroup_size(8, 8, 1)
fn bitmask(@builtin(global_invocation_id) id: vec3<u32>) {
    let at = march_at(view, params, id.xy);
    if !at.valid {
        return;
    }
    // Named once here: the march below uses them throughout.
    let pixel = at.pixel;
    let texel = at.texel;
    let layer = at.layer;
    let pattern = at.pattern;
    let store_at = at.store_at;
    let centre = geometry(in_depth, in_normal, params, vec2<i32>(texel), layer);
    let depth = centre.w;
    if depth <= 0.0 {
        textureStore(out_cone, store_at, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        textureStore(out_near, store_at, vec4<f32>(0.0));
        textureStore(out_far, store_at, vec4<f32>(0.0));
        return;
    }
    let far_lod = max(env.radiance_mips - 5.0, 0.0);
    let n = normalize(centre.xyz);
    let x = world_position(view, pixel, depth);
    // The light of the free sectors: the environment at a blurred mip, or the probe volume's
    // radiance at this point (its SH read after the slices, applied to the sectors' moments).
    let volume = FAR && far_volume(far_probes);
    let rear_known = far_volume(far_probes);
    var moments: FarMoments;
    let eye = view.camera_position.xyz;
    let forward = -normalize(view.world_from_view[2].xyz);
    let lf = local_frame(view, x);
    let omega_o = lf.o;
    let omega_x = lf.x;
    let omega_y = lf.y;

    let r_layer = march_reach(view, params, depth);
    let cell = cell_index(pattern);
    let frame_jitter = golden(view.frame_index);
    let step_jitter = fract(noise(pattern) + golden(view.frame_index + 7u));
    // Stochastic rounding of the sector boundaries: every sample of the pixel rounds with the
    // same offset, so neighbouring samples' ranges tile without gaps, and over frames a sector's
    // expected coverage is the exact fraction of it that the range covers.
    let round_jitter = fract(noise(pattern + vec2<u32>(17u, 29u)) + golden(view.frame_index + 3u));
    let x_screen = to_screen(view, view.clip_from_world, x);
    let layer_size = vec2<i32>(i32(params.layer_width), i32(params.layer_height));
    let all_sectors = bit_range(0u, SECTORS);
    let groups = min(SECTORS, 16u);
    let per_group = SECTORS / groups;

    var ao = 0.0;
    var unoccluded = 0.0;
    var bent = vec3<f32>(0.0);
    var near = vec3<f32>(0.0);
    var far = vec3<f32>(0.0);
    var cum: array<f32, 33>;
    for (var k = 0u; k < SLICES; k++) {
        let phi = slice_phi(k, SLICES, cell, frame_jitter);
        let d = cos(phi) * omega_x + sin(phi) * omega_y;
        let np = projected_normal(n, d, omega_o);
        let slice_normal = cross(d, omega_o);
        // The hemisphere about the projected normal: θ ∈ [γ − π/2, γ + π/2].
        let gamma = clamp(atan2(np.x, np.y), -0.5 * PI, 0.5 * PI);
        let base = gamma - 0.5 * PI;
        // cum[b] = S(θ_b) − S(θ_0), θ_b = base + π b/N, with (cos θ_b, sin θ_b) by rotation
        // (two sin/cos per slice instead of 2(N + 1)).
        let delta = PI / f32(SECTORS);
        let rot = vec2<f32>(cos(delta), sin(delta));
        var cs = vec2<f32>(cos(base), sin(base));
        var s_base = 0.0;
        for (var b = 0u; b <= SECTORS; b++) {
            let theta = base + delta * f32(b);
            let sv = sign(theta) * slice_g_at(theta, cs, np);
            if b == 0u {
                s_base = sv;
            }
            cum[b] = sv - s_base;
            cs = rotate_angle(cs, rot);
        }
        let dir = slice_screen_dir(view, x, x_screen, d, depth);
        var occupied = 0u;
        for (var side = 0u; side < 2u; side++) {
            let side_sign = select(1.0, -1.0, side == 1u);
            // The previous sample of this side.
            var prev_valid = false;
            var prev_point = vec3<f32>(0.0);
            var prev_normal = vec3<f32>(0.0);
            var prev_range = vec2<f32>(0.0);
            var prev_tau = 0.0;
            var prev_depth = 0.0;
            var prev_texel = vec2<i32>(0);
            var prev_accept = 0.0;
            var prev_back = false;
            for (var j = 0u; j < STEPS; j++) {
                let t = r_layer * pow((f32(j) + step_jitter) / f32(STEPS), params.step_power);
                let pos = vec2<f32>(texel) + 0.5 + side_sign * dir * max(t, 1.0);
                let q = vec2<i32>(floor(pos));
                if any(q < vec2<i32>(0)) || any(q >= layer_size) {
                    break;
                }
                let qg = geometry(in_depth, in_normal, params, q, layer);
                let qd = qg.w;
                if qd <= 0.0 {
                    prev_valid = false;
                    continue;
                }
                let qn = normalize(qg.xyz);
                let q_centre = world_position(view, layer_pixel(params, vec2<u32>(q), layer), qd);
                let on_line = on_slice_line(view, params, pos, layer, q_centre, qn);
                if on_line.w == 0.0 {
                    continue;
                }
                let v = on_line.xyz - x;
                let dist = length(v);
                if dist < 1e-6 {
                    continue;
                }
                // The sample's back: along the camera ray through it, `tau` behind its front
                // (tau < 0: no finite thickness, the back is at infinity). `thickness`:
                //   layer     τ = (z₂ − z₁)/(r̂·forward), z₂ the second depth layer's view depth
                //             (depth peeling: the nearest surface behind the first); none there or
                //             none behind: a solid to infinity (what gtao and hbil assume). A
                //             closed object is exactly as thick as it is, light passes behind it,
                //             and a lone wall never leaks.
                //   constant  τ = `thickness_m` (the peers' single constant)
                //   adaptive  τ = `thickness_ratio` × z₁ (for engines without a second layer: a
                //             thickness that grows with distance, as the depth's resolution does)
                var tau = -1.0;
                var has_back = false;
                switch vbgi.thickness {
                    case 0u: {
                        let back = textureLoad(in_back, q, layer, 0).r;
                        if back > qd {
                            tau = (back - qd) / max(dot(normalize(on_line.xyz - eye), forward), 0.05);
                            has_back = true;
                        }
                    }
                    case 1u: {
                        tau = vbgi.thickness_m;
                    }
                    default: {
                        tau = vbgi.thickness_ratio * qd;
                    }
                }
                let clipped = chord(on_line.xyz, tau, x, eye, slice_normal, omega_o, side_sign);
                if clipped.z == 0.0 {
                    prev_valid = false;
                    continue;
                }
                let own = clipped.xy;
                var range = own;
                // The sender's radiance, read only where it lights a newly occupied sector:
                // E_near += a(x′) L(x′) W(newly occupied by x′). L from the radiance source (last
                // frame's diffuse radiance, reprojected, or this frame's direct: `source`) holds
                // emission, so emissive surfaces light their surroundings as area lights; over
                // frames the bounces add up (HBIL Eq. 17). The sender's cosine is in the sectors
                // (a sender seen edge-on covers few); a(x′) = smoothstep(a, b, −n_x′·v̂) rejects
                // back-facing senders (HBIL Sec. 3.4), which still occupy their sectors and send
                // their rear's light where the second layer shows it (`sender_radiance`).
                let accept = smoothstep(params.reject_a, params.reject_b, -dot(qn, v / dist));
                if prev_valid {
                    let step_v = on_line.xyz - prev_point;
                    let reach = CONTINUITY * length(step_v);
                    if dot(prev_normal, step_v) <= reach && dot(qn, -step_v) <= reach {
                        // One solid: each sample lies on or behind the other's tangent plane
                        // (one surface, or a convex corner of a solid), so the region between
                        // the two chords is occupied too.
                        range = vec2<f32>(min(range.x, prev_range.x), max(range.y, prev_range.y));
                    } else {
                        // A silhouette lies in the unsampled gap between the two: the nearer
                        // surface is extended across the gap on its tangent plane (the farther
                        // sample projected onto it), by no more than its own thickness (a thin
                        // object is about as wide as it is deep).
                        let this_near = qd <= prev_depth;
                        let p_near = select(prev_point, on_line.xyz, this_near);
                        let n_near = select(prev_normal, qn, this_near);
                        let p_far = select(on_line.xyz, prev_point, this_near);
                        let tau_near = select(prev_tau, tau, this_near);
                        var reach_v = p_far - n_near * dot(n_near, p_far - p_near) - p_near;
                        let len = length(reach_v);
                        if tau_near >= 0.0 && len > tau_near {
                            reach_v *= tau_near / len;
                        }
                        let m = p_near + reach_v - x;
                        if dot(m, m) < params.radius * params.radius {
                            // The extension's front and back (its chord, not clipped to R).
                            let ray_m = normalize(m + x - eye);
                            let m_back = select(ray_m, m + ray_m * tau_near, tau_near >= 0.0);
                            let theta_m = slice_angle(m, slice_normal, omega_o, side_sign);
                            let theta_b = slice_angle(m_back, slice_normal, omega_o, side_sign);
                            let near_range = select(prev_range, own, this_near);
                            let ext = vec2<f32>(min(near_range.x, min(theta_m, theta_b)), max(near_range.y, max(theta_m, theta_b)));
                            if this_near {
                                range = vec2<f32>(min(range.x, ext.x), max(range.y, ext.y));
                            } else {
                                let extra = range_bits(ext, base, round_jitter);
                                let fresh = extra & ~occupied;
                                if params.indirect == 1u && fresh != 0u {
                                    let l = sender_radiance(prev_texel, layer, prev_accept, prev_back && rear_known);
                                    near += l * mask_weight(fresh, &cum);
                                }
                                occupied |= extra;
                            }
                        }
                    }
                }
                prev_valid = true;
                prev_point = on_line.xyz;
                prev_normal = qn;
                prev_range = own;
                prev_tau = tau;
                prev_depth = qd;
                prev_texel = q;
                prev_accept = accept;
                prev_back = has_back;
                let bits = range_bits(range, base, round_jitter);
                let fresh = bits & ~occupied;
                if params.indirect == 1u && fresh != 0u {
                    near += sender_radiance(q, layer, accept, has_back && rear_known) * mask_weight(fresh, &cum);
                }
                occupied |= bits;
            }
        }
        let visible = all_sectors & ~occupied;
        ao += mask_weight(visible, &cum);
        unoccluded += cum[SECTORS];
        // Far field and bent normal: each group of sectors' visible weight at the group's middle
        // direction, whose (cos, sin) steps by rotation from the first group's.
        let group_step = vec2<f32>(cos(PI / f32(groups)), sin(PI / f32(groups)));
        let theta0 = base + 0.5 * PI / f32(groups);
        var cg = vec2<f32>(cos(theta0), sin(theta0));
        for (var g = 0u; g < groups; g++) {
            let mid = cg;
            cg = rotate_angle(cg, group_step);
            let omega = mid.y * d + mid.x * omega_o;
            let group_bits = bit_range(g * per_group, (g + 1u) * per_group);
            // The far field takes the light of the group's occupied sectors (below).
            let taken = occupied & group_bits;
            if FAR && taken != 0u {
                let w_taken = mask_weight(taken, &cum);
                if volume {
                    far_moments_add(&moments, omega, w_taken);
                } else {
                    far += env_radiance_at(env_radiance, env_sampler, env, omega, far_lod) * w_taken;
                }
            }
            let m = visible & group_bits;
            if m == 0u {
                continue;
            }
            bent += omega * mask_weight(m, &cum);
        }
    }
    // Ratio estimators over the slices, as hbil's (U = cum[N], the open hemisphere's weight):
    // ao = Σ W(unoccupied) / Σ U, E_near = Σ a L W(newly occupied) / Σ U, bent =
    // normalize(Σ ω_g W(unoccupied in g)). The far field (`far=sectors`, 16 groups, ω_g at the
    // group's middle) is the open hemisphere's irradiance E(n)/π (the environment's
    // pre-convolved map, or the volume's SH) less the light the occupied sectors take, each
    // slice's integral an unbiased estimate of the hemisphere's (φ uniform, E[U] = 1):
    //   far = E(n)/π − (1/S) Σ_slices Σ_g L(ω_g) W(occupied in g).
    // It is exact wherever nothing is occupied, whatever the slices. The ratio
    // Σ L W(unoccupied) / Σ U it replaces is biased where L varies with the slice (with two
    // slices a pixel an open floor read 1 % dark, 0.5 % with eight), and so is the share
    // E(n)/π · Σ L W(unoccupied) / Σ L W(all), exact in the open but brighter than either
    // where much is occupied (the book, vbgi, "The far field's estimator").
    let norm = max(unoccluded, 1e-6);
    if FAR {
        var open = vec3<f32>(0.0);
        if volume {
            let sh = far_sh_here(far_probes, far_visibility, env_sampler, view, x, n);
            far = far_apply(sh, moments);
            open = far_irradiance(sh, n);
        } else {
            open = env_irradiance_exact(env_irradiance_map, env_sampler, env, n);
        }
        far = max(open - far / f32(SLICES), vec3<f32>(0.0));
    }
    ao = clamp(ao / norm, 0.0, 1.0);
    let b = select(n, normalize(bent), dot(bent, bent) > 1e-12);
    textureStore(out_cone, store_at, vec4<f32>(b, ao));
    textureStore(out_near, store_at, vec4<f32>(near / norm, 1.0));
    textureStore(out_far, store_at, vec4<f32>(far, 1.0));
}

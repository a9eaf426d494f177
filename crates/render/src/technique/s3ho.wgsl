// s3ho.wgsl — screen-space spherical-harmonic occlusion (`s3ho`, Herholz, Schairer, Schilling &
// Straßer, "Screen Space Spherical Harmonic Occlusion", seed 002/000: Eq. 2–5) and screen-space
// bent normals and cones (`ssbn`, Klehm et al. 2011) as its baseline. Both use the samples and
// visibility test of screen_samples.wgsl.
//
// SH: real basis of nearfield_scene::sh (Sloan's "Stupid SH Tricks" polynomials without the
// Condon–Shortley phase, polar axis world z, index l(l+1)+m, orthonormality tested there), 4
// bands = 16 coefficients.
//
// `sample_pass` (s3ho): c[S3HO]_i(p) = (4π/2N) Σ_j V_SS(p, p_j, d_max) y_i(s_j)(n·s_j)   (Eq. 2),
//   written as c[cos n] − (2π/N) Σ_j (1 − V_j) y_i(s_j)(n·s_j): the unoccluded part, the SH of the
//   clamped cosine about n, is exact (Funk–Hecke: A_l y_i(n), A = π, 2π/3, π/4, 0), and only the
//   occluded part is sampled. Same expectation as Eq. 2 with less noise, and exact (no false
//   occlusion) on a plane. V_j: `steps` ray-marching points along each direction at λ_j·k/steps;
//   an occluded direction keeps 1 − 1/(1 + lambda·d) of its weight (d: blocker distance) when
//   `lambda` > 0. Storage: 16 half floats, pack2x16float into two rgba32uint targets (the WGSL
//   form of the paper's pack_half into two 32-bit-per-channel targets).
// `filter_pass`: the paper's geometry-aware 8×8 bilateral filter (offsets −3..4) on the coefficients,
//   weights from the distance to the centre's tangent plane and the normals' agreement.
// `shade_pass`: c[Lin] = c[env] + Σ_l c[l] (Eq. 4), E_diff = c[Lin]·c[S3HO] (Eq. 3):
//   env-irradiance = c[env]·c[S3HO]/π; light-irradiance = Σ_l E_l/π · (n·l − h·c_occ(l)) · shadow
//   where c_occ = c[cos n] − c[S3HO] and h(l) is the light's Hanning-windowed SH lobe (Sloan 2008,
//   window (1 + cos(π l/4))/2): the unoccluded part exact, the occluded part through the SH lobe;
//   ao = c[S3HO]_0 / (π y_0) (the DC term is y_0 ∫V cos dω).
// Indirect (Eq. 5): every occluded sample's pixel is a patch with form factor f (SSDO's: πR²/N ·
//   cos θ_s cos θ_r / max(d, distance_clamp)², falloff 1 − d/R) and radiance (ρ_o/π)·(c[cos n_o]·
//   c[Lin]); the sum is computed per colour channel directly (the dot with c[Lin] is linear, so
//   this equals storing 3×16 coefficients and dotting after the filter) and blurred.
// `ssbn`: bent normal b = normalised mean of unoccluded directions, cone cos α = 1 − (visible
//   fraction); env-irradiance = Σ c[env]_lm λ_l(α) y_lm(b)/π with the cone-limited cosine kernel
//   λ_l(α) = 2π ∫_{cos α}^1 t P_l(t) dt; lights weighted by a soft cone test around b. Known
//   failure: the two faces of a 90° corner get the same bent normal and cone, hence one colour.

struct S3hoParams {
    radius: f32,
    samples: u32,
    pattern: u32,
    fade: f32,
    // Ray-marching points per direction.
    steps: u32,
    // Smooth visibility weight (0: off).
    lambda: f32,
    // 0 s3ho, 1 ssbn.
    technique: u32,
    // Indirect extension on/off.
    indirect: u32,
    strength: f32,
    distance_clamp: f32,
    // Depth layers of the main view and additional cameras in the blocker test (passes/layers.rs).
    layers: u32,
    cameras: u32,
}

@group(0) @binding(5) var<uniform> params: S3hoParams;
@group(0) @binding(10) var gb_albedo: texture_2d<f32>;
// `sample` outputs.
@group(0) @binding(20) var out_coeffs0: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(21) var out_coeffs1: texture_storage_2d<rgba32uint, write>;
// ssbn: bent normal xyz, cos α; ao in a second target's r.
@group(0) @binding(22) var out_bent: texture_storage_2d<rgba16float, write>;
@group(0) @binding(23) var out_indirect: texture_storage_2d<rgba16float, write>;
// `filter` and `shade` inputs.
@group(0) @binding(24) var in_coeffs0: texture_2d<u32>;
@group(0) @binding(25) var in_coeffs1: texture_2d<u32>;
@group(0) @binding(26) var in_bent: texture_2d<f32>;
// `shade` outputs.
@group(0) @binding(27) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(0) @binding(28) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
@group(0) @binding(29) var out_ao: texture_storage_2d<r32float, write>;
@group(0) @binding(30) var out_ao_raw: texture_storage_2d<rgba16float, write>;
@group(0) @binding(31) var in_ao_raw: texture_2d<f32>;

fn cfg() -> SampleConfig {
    return SampleConfig(params.samples, params.pattern, params.radius, params.fade, params.layers, params.cameras);
}

// Clamped-cosine band factors A_l (Funk–Hecke), bands 0..3.
fn cosine_band(l: u32) -> f32 {
    switch l {
        case 0u: { return PI; }
        case 1u: { return 2.0 * PI / 3.0; }
        case 2u: { return PI / 4.0; }
        default: { return 0.0; }
    }
}

fn band(i: u32) -> u32 {
    return select(select(select(3u, 2u, i < 9u), 1u, i < 4u), 0u, i < 1u);
}

// SH of the clamped cosine lobe about n.
fn sh_cosine(n: vec3<f32>) -> array<f32, 16> {
    var c = sh_basis(n);
    for (var i = 0u; i < 16u; i++) {
        c[i] *= cosine_band(band(i));
    }
    return c;
}

fn pack16(c: array<f32, 16>) -> array<vec4<u32>, 2> {
    var out: array<vec4<u32>, 2>;
    for (var k = 0u; k < 2u; k++) {
        let b = 8u * k;
        out[k] = vec4<u32>(
            pack2x16float(vec2<f32>(c[b], c[b + 1u])),
            pack2x16float(vec2<f32>(c[b + 2u], c[b + 3u])),
            pack2x16float(vec2<f32>(c[b + 4u], c[b + 5u])),
            pack2x16float(vec2<f32>(c[b + 6u], c[b + 7u])));
    }
    return out;
}

fn unpack16(a: vec4<u32>, b: vec4<u32>) -> array<f32, 16> {
    var c: array<f32, 16>;
    let words = array<u32, 8>(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w);
    for (var k = 0u; k < 8u; k++) {
        let v = unpack2x16float(words[k]);
        c[2u * k] = v.x;
        c[2u * k + 1u] = v.y;
    }
    return c;
}

// Irradiance (E, not /π) at a surface of normal n from the lights, unshadowed, plus the
// environment through c[cos n] — the occluder's incident light for the indirect extension.
fn incident_at(n: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let cn = sh_cosine(n);
    var e = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        e += env_sh[i].rgb * cn[i];
    }
    for (var li = 0u; li < frame.counts.y; li++) {
        let inc = incident(lights[li], p);
        e += inc.irradiance * max(0.0, dot(n, inc.to_light));
    }
    return max(e, vec3<f32>(0.0));
}

@compute @workgroup_size(8, 8, 1)
fn sample_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let here = surface_at(pixel);
    if !here.valid {
        textureStore(out_coeffs0, pixel, vec4<u32>(0u));
        textureStore(out_coeffs1, pixel, vec4<u32>(0u));
        textureStore(out_bent, pixel, vec4<f32>(0.0));
        textureStore(out_ao_raw, pixel, vec4<f32>(0.0));
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        return;
    }
    let c = cfg();
    let tb = tangent_frame(here.n);
    let n = params.samples;
    let d_omega = 2.0 * PI / f32(n);
    var occluded = array<f32, 16>();
    var bent = vec3<f32>(0.0);
    var visible = 0.0;
    var ao_num = 0.0;
    var ao_den = 0.0;
    var indirect = vec3<f32>(0.0);
    let area = PI * params.radius * params.radius / f32(n);
    for (var j = 0u; j < n; j++) {
        let s = sample_local(j, pixel, c);
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let length_j = s.w * params.radius;
        // Ray marching: the first occluded point decides.
        let occ = march_occlusion(here.p, omega, length_j, params.steps, c);
        var v = 1.0 - occ.amount;
        if occ.amount > 0.0 && params.lambda > 0.0 {
            v = max(v, 1.0 - 1.0 / (1.0 + params.lambda * occ.distance));
        }
        let cos_theta = max(s.z, 0.0);
        ao_num += v * cos_theta;
        ao_den += cos_theta;
        visible += v;
        bent += omega * v;
        if v < 1.0 {
            let y = sh_basis(omega);
            for (var i = 0u; i < 16u; i++) {
                occluded[i] += (1.0 - v) * y[i] * cos_theta * d_omega;
            }
            if params.indirect == 1u {
                let sender = occ.sender;
                let transfer = sender_transfer(here, sender, area, params.radius, params.distance_clamp);
                if transfer > 0.0 {
                    var radiance: vec3<f32>;
                    if occ.source == 0u {
                        let rho = textureLoad(gb_albedo, occ.pixel, 0).rgb;
                        radiance = rho / PI * incident_at(sender.n, sender.p);
                    } else {
                        radiance = layer_sender_radiance(occ);
                    }
                    indirect += radiance * (transfer * params.strength * (1.0 - v));
                }
            }
        }
    }
    var coeffs = sh_cosine(here.n);
    for (var i = 0u; i < 16u; i++) {
        coeffs[i] -= occluded[i];
    }
    let packed = pack16(coeffs);
    textureStore(out_coeffs0, pixel, packed[0]);
    textureStore(out_coeffs1, pixel, packed[1]);
    let fraction = visible / f32(n);
    let b = select(here.n, normalize(bent), length(bent) > 1e-6);
    textureStore(out_bent, pixel, vec4<f32>(b, 1.0 - fraction));
    textureStore(out_ao_raw, pixel, vec4<f32>(select(1.0, ao_num / ao_den, ao_den > 0.0), 0.0, 0.0, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(indirect, 1.0));
}

@compute @workgroup_size(8, 8, 1)
fn filter_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let centre = surface_at(pixel);
    if !centre.valid {
        textureStore(out_coeffs0, pixel, vec4<u32>(0u));
        textureStore(out_coeffs1, pixel, vec4<u32>(0u));
        return;
    }
    let z = textureLoad(gb_view_depth, pixel, 0).r;
    let size = vec2<i32>(frame.size.xy);
    var sum = array<f32, 16>();
    var weight = 0.0;
    for (var dy = -3; dy <= 4; dy++) {
        for (var dx = -3; dx <= 4; dx++) {
            let q = vec2<i32>(pixel) + vec2<i32>(dx, dy);
            if any(q < vec2<i32>(0)) || any(q >= size) {
                continue;
            }
            let s = surface_at(vec2<u32>(q));
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

// Hanning window of band l over 4 bands (Sloan 2008).
fn hanning(l: u32) -> f32 {
    return 0.5 * (1.0 + cos(PI * f32(l) / 4.0));
}

// Cone-limited cosine kernel λ_l(α) for bands 0..2 (c = cos α).
fn cone_band(l: u32, c: f32) -> f32 {
    switch l {
        case 0u: { return PI * (1.0 - c * c); }
        case 1u: { return 2.0 * PI * (1.0 - c * c * c) / 3.0; }
        case 2u: { return PI * (0.75 * (1.0 - c * c * c * c) - 0.5 * (1.0 - c * c)); }
        default: { return 0.0; }
    }
}

@compute @workgroup_size(8, 8, 1)
fn shade_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let here = surface_at(pixel);
    if !here.valid {
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        return;
    }
    var env = vec3<f32>(0.0);
    var light = vec3<f32>(0.0);
    var ao = 1.0;
    if params.technique == 0u {
        let c = unpack16(textureLoad(in_coeffs0, pixel, 0), textureLoad(in_coeffs1, pixel, 0));
        for (var i = 0u; i < 16u; i++) {
            env += env_sh[i].rgb * c[i];
        }
        env /= PI;
        ao = clamp(c[0] / (PI * 0.2820948), 0.0, 1.0);
        let cn = sh_cosine(here.n);
        for (var li = 0u; li < frame.counts.y; li++) {
            let l = lights[li];
            let inc = incident(l, here.p);
            let n_l = dot(here.n, inc.to_light);
            if n_l <= 0.0 {
                continue;
            }
            let y = sh_basis(inc.to_light);
            var blocked = 0.0;
            for (var i = 0u; i < 16u; i++) {
                blocked += hanning(band(i)) * y[i] * (cn[i] - c[i]);
            }
            light += inc.irradiance * max(0.0, n_l - blocked) * shadow_visibility(l, here.p, here.n);
        }
    } else {
        let bc = textureLoad(in_bent, pixel, 0);
        let b = normalize(bc.xyz);
        let cos_a = clamp(bc.w, 0.0, 1.0);
        let y = sh_basis(b);
        for (var i = 0u; i < 9u; i++) {
            env += env_sh[i].rgb * (cone_band(band(i), cos_a) * y[i]);
        }
        env = max(env / PI, vec3<f32>(0.0));
        for (var li = 0u; li < frame.counts.y; li++) {
            let l = lights[li];
            let inc = incident(l, here.p);
            let n_l = dot(here.n, inc.to_light);
            if n_l <= 0.0 {
                continue;
            }
            let inside = smoothstep(cos_a - 0.1, cos_a + 0.1, dot(b, inc.to_light));
            light += inc.irradiance * n_l * inside * shadow_visibility(l, here.p, here.n);
        }
        ao = textureLoad(in_ao_raw, pixel, 0).r;
    }
    textureStore(out_env_irradiance, pixel, vec4<f32>(env, 1.0));
    textureStore(out_light_irradiance, pixel, vec4<f32>(light / PI, 1.0));
    textureStore(out_ao, pixel, vec4<f32>(ao));
}

// sample.wgsl — s3ho/ssbn `sample_pass`: N hemisphere samples per pixel against the screen-space
// visibility test → 16 SH coefficients of visibility × cosine (Eq. 2; ssbn: bent normal and cone)
// and the raw indirect light of the occluding pixels (Eq. 5). technique/s3ho/mod.rs has the overview.
//
// `sample_pass` (s3ho): c[S3HO]_i(p) = (4π/2N) Σ_j V_SS(p, p_j, d_max) y_i(s_j)(n·s_j)   (Eq. 2),
//   written as c[cos n] − (2π/N) Σ_j (1 − V_j) y_i(s_j)(n·s_j): the unoccluded part, the SH of the
//   clamped cosine about n, is exact (Funk–Hecke: A_l y_i(n), A = π, 2π/3, π/4, 0), and only the
//   occluded part is sampled. Same expectation as Eq. 2 with less noise, and exact (no false
//   occlusion) on a plane. V_j: `steps` ray-marching points along each direction at λ_j·k/steps;
//   an occluded direction keeps 1 − 1/(1 + lambda·d) of its weight (d: blocker distance) when
//   `lambda` > 0. Storage: 16 half floats, pack2x16float into two rgba32uint targets (the WGSL
//   form of the paper's pack_half into two 32-bit-per-channel targets).
// Indirect (Eq. 5): every occluded sample's pixel is a patch with form factor f (SSDO's: πR²/N ·
//   cos θ_s cos θ_r / max(d, distance_clamp)², falloff 1 − d/R) and radiance (ρ_o/π)·(c[cos n_o]·
//   c[Lin]); the sum is computed per colour channel directly (the dot with c[Lin] is linear, so
//   this equals storing 3×16 coefficients and dotting after the filter) and blurred.
// `ssbn`: bent normal b = normalised mean of unoccluded directions, cone cos α = 1 − (visible
//   fraction); env-irradiance = Σ c[env]_lm λ_l(α) y_lm(b)/π with the cone-limited cosine kernel
//   λ_l(α) = 2π ∫_{cos α}^1 t P_l(t) dt; lights weighted by a soft cone test around b. Known
//   failure: the two faces of a 90° corner get the same bent normal and cone, hence one colour.

@group(1) @binding(0) var<uniform> params: S3hoParams;
@group(1) @binding(1) var<storage, read> sample_sets: array<vec4<f32>>;
@group(1) @binding(2) var gb_normal: texture_2d<f32>;
@group(1) @binding(3) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(4) var gb_albedo: texture_2d<f32>;
@group(1) @binding(5) var<storage, read> layer_views: array<LayerView>;
@group(1) @binding(6) var peel_normal: texture_2d_array<f32>;
@group(1) @binding(7) var peel_depth: texture_2d_array<f32>;
@group(1) @binding(8) var cam_normal: texture_2d_array<f32>;
@group(1) @binding(9) var cam_depth: texture_2d_array<f32>;
@group(1) @binding(10) var peel_radiance: texture_2d_array<f32>;
@group(1) @binding(11) var cam_radiance: texture_2d_array<f32>;
@group(1) @binding(12) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(13) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(14) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(15) var shadow_sampler: sampler_comparison;
@group(1) @binding(16) var out_coeffs0: texture_storage_2d<rgba32uint, write>;
@group(1) @binding(17) var out_coeffs1: texture_storage_2d<rgba32uint, write>;
// ssbn: bent normal xyz, cos α; ao in a second target's r.
@group(1) @binding(18) var out_bent: texture_storage_2d<rgba16float, write>;
@group(1) @binding(19) var out_ao_raw: texture_storage_2d<rgba16float, write>;
@group(1) @binding(20) var out_indirect: texture_storage_2d<rgba16float, write>;
@group(1) @binding(21) var shadow_depths: texture_2d_array<f32>;

fn cfg() -> SampleConfig {
    return SampleConfig(SAMPLES, params.pattern, params.radius, params.fade, params.layers, params.cameras);
}

// Irradiance (E, not /π) at a surface of normal n from the lights, unshadowed, plus the
// environment through c[cos n] (or, with a probe volume, the volume's irradiance at p) — the
// occluder's incident light for the indirect extension.
fn incident_at(n: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    if far_volume(far_probes) {
        e = PI * far_irradiance_here(far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, p, n);
    } else {
        let cn = sh_cosine(n);
        for (var i = 0u; i < 9u; i++) {
            e += env.sh[i].rgb * cn[i];
        }
    }
    for (var li = 0u; li < frame.light_count; li++) {
        let inc = incident(lights[li], p);
        e += inc.irradiance * max(0.0, dot(n, inc.to_light));
    }
    return max(e, vec3<f32>(0.0));
}

@compute @workgroup_size(8, 8, 1)
fn sample_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let here = surface_at(view, gb_normal, gb_view_depth, pixel);
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
    let n = SAMPLES;
    let d_omega = 2.0 * PI / f32(n);
    var occluded = array<f32, 16>();
    var bent = vec3<f32>(0.0);
    var visible = 0.0;
    var ao_num = 0.0;
    var ao_den = 0.0;
    var indirect = vec3<f32>(0.0);
    let area = PI * params.radius * params.radius / f32(n);
    for (var j = 0u; j < n; j++) {
        let s = sample_at(j, pixel, c);
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let length_j = s.w * params.radius;
        // Ray marching: the first occluded point decides.
        let occ = march_occlusion(here.p, omega, length_j, STEPS, c);
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
        }
        if params.indirect == 1u {
            // The bounce's sender (samples.wgsl, bounce_steps): with more layers than one, from
            // at most the paper's 2 marched points; the visibility's march when that is the same.
            var bo = occ;
            var vb = v;
            let bounce_march = bounce_steps(STEPS, 2u, c);
            if bounce_march != STEPS {
                bo = march_occlusion(here.p, omega, length_j, bounce_march, c);
                vb = 1.0 - bo.amount;
                if bo.amount > 0.0 && params.lambda > 0.0 {
                    vb = max(vb, 1.0 - 1.0 / (1.0 + params.lambda * bo.distance));
                }
            }
            if vb < 1.0 {
                let sender = bo.sender;
                let transfer = sender_transfer(here, sender, area, params.radius, params.distance_clamp);
                if transfer > 0.0 {
                    var radiance: vec3<f32>;
                    if bo.source == 0u {
                        let rho = textureLoad(gb_albedo, bo.pixel, 0).rgb;
                        radiance = rho / PI * incident_at(sender.n, sender.p);
                    } else {
                        radiance = layer_sender_radiance(peel_radiance, cam_radiance, bo);
                    }
                    indirect += radiance * (transfer * params.strength * (1.0 - vb));
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

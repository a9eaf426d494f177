// shade.wgsl — s3ho/ssbn `shade_pass`: SH lighting of the environment and the lights with the
// (filtered) coefficients (Eq. 3–4; ssbn: through the bent cone) → env-irradiance,
// light-irradiance and ao. technique/s3ho/mod.rs has the overview.
//
// `shade_pass` (env-irradiance, light-irradiance, ao) → s3ho indirect: bilateral blur →
// `indirect-irradiance`.
//
// The derivations. Screen-space spherical-harmonic occlusion (`s3ho`, Herholz, Schairer,
// Schilling & Straßer, "Screen Space Spherical Harmonic Occlusion", seed 002/000: Eq. 2–5) and
// screen-space bent normals and cones (`ssbn`, Klehm et al. 2011) as its baseline. Both use the samples and
// visibility test of technique/samples.wgsl.
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

@group(1) @binding(0) var<uniform> params: S3hoParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(4) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(5) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(6) var shadow_sampler: sampler_comparison;
@group(1) @binding(7) var in_coeffs0: texture_2d<u32>;
@group(1) @binding(8) var in_coeffs1: texture_2d<u32>;
@group(1) @binding(9) var in_bent: texture_2d<f32>;
@group(1) @binding(10) var in_ao_raw: texture_2d<f32>;
@group(1) @binding(11) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(12) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(13) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(14) var shadow_depths: texture_2d_array<f32>;

// lights.wgsl's shadow_visibility of light l at world p with normal n, from this pass's shadow
// maps: the layer that sees p, its matrix, the frame's normal offset.
fn shadow_map_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let layer = shadow_layer(l, p);
    return shadow_visibility(shadow_maps, shadow_depths, shadow_sampler, frame.shadow_normal_offset, l, layer, shadow_clip_from_world[layer], p, n);
}

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
    if !in_bounds(view, pixel) {
        return;
    }
    let here = surface_at(view, gb_normal, gb_view_depth, pixel);
    if !here.valid {
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        return;
    }
    var env_e = vec3<f32>(0.0);
    var light = vec3<f32>(0.0);
    var ao = 1.0;
    // The far field's radiance: the environment's SH (16 coefficients), or the probe volume's at
    // this point (9; it has no band 3).
    let volume = far_volume(far_probes);
    var far: FarSh;
    if volume {
        far = far_sh_here(far_probes, far_visibility, env_sampler, view, here.p, here.n);
    }
    if params.technique == 0u {
        let c = unpack16(textureLoad(in_coeffs0, pixel, 0), textureLoad(in_coeffs1, pixel, 0));
        if volume {
            for (var i = 0u; i < 9u; i++) {
                env_e += far.c[i].rgb * c[i];
            }
        } else {
            for (var i = 0u; i < 16u; i++) {
                env_e += env.sh[i].rgb * c[i];
            }
        }
        env_e /= PI;
        ao = clamp(c[0] / (PI * 0.2820948), 0.0, 1.0);
        let cn = sh_cosine(here.n);
        for (var li = 0u; li < frame.light_count; li++) {
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
            light += inc.irradiance * max(0.0, n_l - blocked) * shadow_map_visibility(l, here.p, here.n);
        }
    } else {
        let bc = textureLoad(in_bent, pixel, 0);
        let b = normalize(bc.xyz);
        let cos_a = clamp(bc.w, 0.0, 1.0);
        let y = sh_basis(b);
        for (var i = 0u; i < 9u; i++) {
            var l = env.sh[i].rgb;
            if volume {
                l = far.c[i].rgb;
            }
            env_e += l * (cone_band(band(i), cos_a) * y[i]);
        }
        env_e = max(env_e / PI, vec3<f32>(0.0));
        for (var li = 0u; li < frame.light_count; li++) {
            let l = lights[li];
            let inc = incident(l, here.p);
            let n_l = dot(here.n, inc.to_light);
            if n_l <= 0.0 {
                continue;
            }
            let inside = smoothstep(cos_a - 0.1, cos_a + 0.1, dot(b, inc.to_light));
            light += inc.irradiance * n_l * inside * shadow_map_visibility(l, here.p, here.n);
        }
        ao = textureLoad(in_ao_raw, pixel, 0).r;
    }
    textureStore(out_env_irradiance, pixel, vec4<f32>(env_e, 1.0));
    textureStore(out_light_irradiance, pixel, vec4<f32>(light / PI, 1.0));
    textureStore(out_ao, pixel, vec4<f32>(ao));
}

// shade.wgsl — s3ho/ssbn `shade_pass`: SH lighting of the environment and the lights with the
// (filtered) coefficients (Eq. 3–4; ssbn: through the bent cone) → env-irradiance,
// light-irradiance and ao. See technique/s3ho/mod.rs.

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

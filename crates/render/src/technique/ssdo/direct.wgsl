// direct.wgsl — ssdo/ssao `direct`: N hemisphere samples per pixel against the screen-space
// visibility test (samples.wgsl): the cosine-weighted ao, the directional occlusion of the
// environment (visibility or radiance mode; the environment's virtual point lights for ssdo-vpl)
// and the lights' irradiance with screen-space occlusion of their segments (segment.wgsl).
// Formulas, sources and deviations: technique/ssdo/mod.rs.

@group(1) @binding(0) var<uniform> params: SsdoParams;
@group(1) @binding(1) var<storage, read> sample_sets: array<vec4<f32>>;
@group(1) @binding(2) var gb_normal: texture_2d<f32>;
@group(1) @binding(3) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(4) var<storage, read> layer_views: array<LayerView>;
@group(1) @binding(5) var peel_normal: texture_2d_array<f32>;
@group(1) @binding(6) var peel_depth: texture_2d_array<f32>;
@group(1) @binding(7) var cam_normal: texture_2d_array<f32>;
@group(1) @binding(8) var cam_depth: texture_2d_array<f32>;
@group(1) @binding(9) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(10) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(11) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(12) var shadow_sampler: sampler_comparison;
// a = (L_dir rgb: Σ (1/π) L_in V cos Δω, visibility after contrast); b = (cosine-weighted ao
// estimate, 0, 0, 1); light irradiance with screen-space light occlusion.
@group(1) @binding(13) var out_a: texture_storage_2d<rgba16float, write>;
@group(1) @binding(14) var out_b: texture_storage_2d<rgba16float, write>;
@group(1) @binding(15) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(16) var shadow_depths: texture_2d_array<f32>;

// lights.wgsl's shadow_visibility of light l at world p with normal n, from this pass's shadow
// maps: the layer that sees p, its matrix, the frame's normal offset.
fn shadow_map_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let layer = shadow_layer(l, p);
    return shadow_visibility(shadow_maps, shadow_depths, shadow_sampler, frame.shadow_normal_offset, l, layer, shadow_clip_from_world[layer], p, n);
}

@compute @workgroup_size(8, 8, 1)
fn direct(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let here = surface_at(view, gb_normal, gb_view_depth, pixel);
    if !here.valid {
        textureStore(out_a, pixel, vec4<f32>(0.0));
        textureStore(out_b, pixel, vec4<f32>(0.0));
        if params.technique == 1u && params.light_samples > 0u {
            textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        }
        return;
    }
    let tb = tangent_frame(here.n);
    let n = SAMPLES;
    var ao_num = 0.0;
    var ao_den = 0.0;
    var total_light = 0.0;
    var visible_light = 0.0;
    var l_dir = vec3<f32>(0.0);
    // The same sum with V ≡ 1: the quadrature of the unoccluded irradiance by this pixel's set.
    var l_open = vec3<f32>(0.0);
    // The light each unoccluded direction brings: the environment at a blurred mip, its SH
    // radiance (radiance mode, `sample_light=sh`), or the probe volume's radiance at this point.
    let volume = far_volume(far_probes);
    let sh_light = params.mode == 1u && params.sample_light == 0u;
    var far: FarSh;
    if volume && params.technique == 1u {
        far = far_sh_here(far_probes, far_visibility, env_sampler, view, here.p, here.n);
    }
    for (var i = 0u; i < n; i++) {
        let s = sample_at(i, pixel, sample_config(params));
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let lambda = s.w * params.radius;
        let v = 1.0 - march_occlusion(here.p, omega, lambda, STEPS, sample_config(params)).amount;
        let cos_theta = max(s.z, 0.0);
        ao_num += v * cos_theta;
        ao_den += cos_theta;
        if params.technique == 1u {
            var l_in = vec3<f32>(0.0);
            if volume {
                l_in = far_radiance(far, omega);
            } else if sh_light {
                let b = sh_basis(omega);
                for (var k = 0u; k < 16u; k++) {
                    l_in += env.sh[k].rgb * b[k];
                }
            } else {
                l_in = env_radiance_at(env_radiance, env_sampler, env, omega, params.lod);
            }
            let w = max(luminance(l_in), 0.0) * cos_theta;
            total_light += w;
            visible_light += w * v;
            // (1/π) L_in V cos θ Δω with Δω = 2π/N.
            l_dir += l_in * (v * cos_theta * 2.0 / f32(n));
            l_open += l_in * (cos_theta * 2.0 / f32(n));
        }
    }
    let ao = select(1.0, ao_num / ao_den, ao_den > 0.0);
    var visibility: f32;
    if params.technique == 1u {
        let fraction = select(1.0, visible_light / total_light, total_light > 0.0);
        visibility = clamp(pow(fraction, params.contrast), 0.0, 1.0);
    } else {
        // SSAO: A = pow(max(0, 1 − scale·S), contrast), S the cosine-weighted occluded fraction.
        visibility = pow(max(0.0, 1.0 - params.scale * (1.0 - ao)), params.contrast);
    }
    textureStore(out_b, pixel, vec4<f32>(ao, 0.0, 0.0, 1.0));
    if params.vpl_mode == 1u {
        textureStore(out_a, pixel, vec4<f32>(vpl_environment(here), 1.0));
        return;
    }
    if params.technique == 1u && params.mode == 1u && params.normalise == 1u {
        // Self-normalised: each channel's sum over the samples divided by the same sum with
        // V ≡ 1, times the exact unoccluded irradiance — the pre-convolved map's (the SH misses
        // it by its band limit, a few percent under a sun lobe), or the probe volume's. An open
        // point gets that irradiance exactly, whatever this pixel's sample set integrates to;
        // an occluded one loses the share of it its occluded samples carry.
        var exact: vec3<f32>;
        if volume {
            exact = far_irradiance(far, here.n);
        } else {
            exact = env_irradiance_exact(env_irradiance_map, env_sampler, env, here.n);
        }
        let floor = 1e-4 * max(max(exact.r, exact.g), max(exact.b, 1e-20));
        l_dir = select(l_dir, l_dir * exact / l_open, l_open > vec3<f32>(floor));
    }
    textureStore(out_a, pixel, vec4<f32>(max(l_dir, vec3<f32>(0.0)), visibility));

    // Lights: points on a segment towards each light — of length R (paper Sec. 4) or the length
    // the shadow map's bias hides (light_segment=bias, Sec. 5 screen-space shadow correction);
    // the light is blocked as much as its most occluded point, on top of its shadow map.
    if params.technique == 1u && params.light_samples > 0u {
        var irradiance = vec3<f32>(0.0);
        for (var li = 0u; li < frame.light_count; li++) {
            let l = lights[li];
            let inc = incident(l, here.p);
            let n_l = dot(here.n, inc.to_light);
            if n_l <= 0.0 {
                continue;
            }
            let shadowed = shadow_map_visibility(l, here.p, here.n);
            var blocked = 0.0;
            if shadowed > 0.0 {
                blocked = segment_blocked(here, l, inc.to_light);
            }
            irradiance += inc.irradiance * n_l * shadowed * (1.0 - blocked);
        }
        textureStore(out_light_irradiance, pixel, vec4<f32>(irradiance / PI, 1.0));
    }
}

// ssdo-vpl (paper Sec. 5, Fig. 10): (1/π) Σ_k E_k max(0, n·ω_k) V_k with V_k the k-th
// environment light's shadow map, corrected in screen space on its bias segment.
fn vpl_environment(here: Surface) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < params.vpl_count; k++) {
        let l = lights[k];
        let to_light = -l.position;
        let n_l = dot(here.n, to_light);
        if n_l <= 0.0 {
            continue;
        }
        var v = shadow_map_visibility(l, here.p, here.n);
        if v > 0.0 && params.light_samples > 0u {
            v *= 1.0 - segment_blocked(here, l, to_light);
        }
        e += l.color * (n_l * v);
    }
    return e / PI;
}

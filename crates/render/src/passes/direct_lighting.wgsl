// direct_lighting.wgsl — direct light at every G-buffer pixel (compute, 8×8).
//
// For a surface point P with normal n, base colour ρ, metallic m and roughness r:
//   light_irradiance = (1/π) Σ_l E_l(P) · V_shadow        (the `light-irradiance` AOV)
//   specular         = Σ_l f_GGX · E_l · V_shadow + prefiltered_env(R, r) · (F0·A + B)
//   direct_radiance  = emission + ρ · (light_irradiance + E_far(n))
//   env_irradiance   = E_far(n)                            (on entry to the technique)
// E_far is the open sky's SH irradiance env_irradiance_sh(n), or with a probe volume the
// volume's irradiance at P (far.wgsl). It is left in the techniques' env-irradiance output,
// which `none` passes on rather than looking the volume up a second time.
// E_l is the unshadowed irradiance of nearfield_scene::Light::irradiance (same falloff, same spot
// cone and range window). f_GGX is Cook–Torrance with the GGX distribution, the height-correlated
// Smith visibility and Schlick's Fresnel (Karis 2013), F0 = mix(0.04, ρ, m). (A, B) is Karis'
// analytic fit of the split-sum BRDF integral ("Physically Based Shading on Mobile", 2014) in
// place of a lookup table. `direct_radiance` is the outgoing diffuse radiance that near-field
// techniques gather as indirect light (L_o of docs/src/aovs.md): it is kept for the next frame.
// Lights and shadows come from shaders/lights.wgsl.
// Shadows: 3×3 PCF of hardware 2×2 comparisons from the shadow-map array, receiver offset along
// the normal by `frame.shadow_normal_offset` shadow-map texels (see passes/shadow.rs for both
// biases); a disc light's soft shadow (lights.wgsl's disc_shadow).
// The pipeline is specialised for its scene (direct_lighting.rs): LIGHTS, whether the light table
// has any light, lights.wgsl's shadow filters and far.wgsl's FAR_FIELD. Code a scene does not
// need is left out of the kernel rather than branched around (docs/src/architecture.md,
// "Specialised kernels").

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var gb_albedo: texture_2d<f32>;
@group(1) @binding(2) var gb_material: texture_2d<f32>;
@group(1) @binding(3) var gb_emissive: texture_2d<f32>;
@group(1) @binding(4) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(5) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(6) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(7) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(8) var shadow_sampler: sampler_comparison;
@group(1) @binding(9) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(10) var out_specular: texture_storage_2d<rgba16float, write>;
@group(1) @binding(11) var out_direct_radiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(12) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(13) var shadow_depths: texture_2d_array<f32>;
// The far field at the point: rgb its E(n)/π, a its own visibility within R (1 for the sky).
@group(1) @binding(14) var out_far_field: texture_storage_2d<rgba16float, write>;

// lights.wgsl's shadow_visibility of light l at world p with normal n, from this pass's shadow
// maps: the layer that sees p, its matrix, the frame's normal offset.
fn shadow_map_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let layer = shadow_layer(l, p);
    return shadow_visibility(shadow_maps, shadow_depths, shadow_sampler, frame.shadow_normal_offset, l, layer, shadow_clip_from_world[layer], p, n);
}

override LIGHTS: bool = true;

fn d_ggx(n_h: f32, a: f32) -> f32 {
    let a2 = a * a;
    let f = n_h * n_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * f * f);
}

fn v_smith_ggx_correlated(n_v: f32, n_l: f32, a: f32) -> f32 {
    let a2 = a * a;
    let gv = n_l * sqrt(n_v * n_v * (1.0 - a2) + a2);
    let gl = n_v * sqrt(n_l * n_l * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-6);
}

fn f_schlick(f0: vec3<f32>, v_h: f32) -> vec3<f32> {
    return f0 + (1.0 - f0) * pow(1.0 - v_h, 5.0);
}

fn env_brdf_approx(roughness: f32, n_v: f32) -> vec2<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_v)) * r.x + r.y;
    return vec2<f32>(-1.04, 1.04) * a004 + r.zw;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_specular, pixel, vec4<f32>(0.0));
        textureStore(out_direct_radiance, pixel, vec4<f32>(0.0));
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_far_field, pixel, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let n = normalize(nw.xyz);
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let mr = textureLoad(gb_material, pixel, 0);
    let metallic = mr.r;
    let roughness = clamp(mr.g, 0.03, 1.0);
    let a = roughness * roughness;
    let emission = textureLoad(gb_emissive, pixel, 0).rgb;
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    let p = world_position(view, pixel, depth);
    let v = normalize(view.camera_position.xyz - p);
    let n_v = max(dot(n, v), 1e-4);
    let f0 = mix(vec3<f32>(0.04), albedo, metallic);

    var irradiance = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    for (var i = 0u; LIGHTS && i < frame.light_count; i++) {
        let l = lights[i];
        let inc = incident(l, p);
        let n_l = dot(n, inc.to_light);
        if n_l <= 0.0 {
            continue;
        }
        let e = inc.irradiance * n_l * shadow_map_visibility(l, p, n);
        irradiance += e;
        let h = normalize(v + inc.to_light);
        let spec = d_ggx(max(dot(n, h), 0.0), a) * v_smith_ggx_correlated(n_v, n_l, a)
            * f_schlick(f0, max(dot(v, h), 0.0));
        specular += spec * e;
    }
    let light_irradiance = irradiance / PI;
    let r = reflect(-v, n);
    let ab = env_brdf_approx(roughness, n_v);
    specular += env_specular_at(env_specular, env_sampler, env, r, roughness) * (f0 * ab.x + ab.y);
    // The senders' light: the far field, the open sky's SH irradiance or the probe volume's.
    var far_e = vec3<f32>(0.0);
    var far_ao = 1.0;
    if far_volume(far_probes) {
        far_e = far_irradiance_here(far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, p, n);
        far_ao = far_ao_here(far_probes, far_visibility, env_sampler, view, p, n);
    } else {
        far_e = env_irradiance_sh(env, n);
    }
    let direct = emission + albedo * (light_irradiance + far_e);
    textureStore(out_light_irradiance, pixel, vec4<f32>(light_irradiance, 1.0));
    textureStore(out_specular, pixel, vec4<f32>(specular, 1.0));
    textureStore(out_direct_radiance, pixel, vec4<f32>(direct, 1.0));
    textureStore(out_env_irradiance, pixel, vec4<f32>(far_e, 1.0));
    textureStore(out_far_field, pixel, vec4<f32>(far_e, far_ao));
}

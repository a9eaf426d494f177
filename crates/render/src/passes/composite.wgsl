// composite.wgsl — assembles the linear HDR frame (the `radiance` AOV).
//
//   radiance = emission + (1 − m) · ρ · (env_irradiance + light_irradiance + indirect_irradiance)
//              + specular
// on surfaces (the irradiance terms are already divided by π, so ρ × term is Lambertian
// radiance), and the environment seen through the pixel (mip 0) on background. Specular light is
// not occluded by the near-field technique (as in the SSDO textbook chapter: "specular untouched").
// After a technique that writes only ao (gtao; AO_SCALES_FAR), env_irradiance and
// indirect_irradiance are formed here (irradiance_terms.wgsl).

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var gb_albedo: texture_2d<f32>;
@group(1) @binding(2) var gb_material: texture_2d<f32>;
@group(1) @binding(3) var gb_emissive: texture_2d<f32>;
@group(1) @binding(4) var light_irradiance: texture_2d<f32>;
@group(1) @binding(5) var specular: texture_2d<f32>;
@group(1) @binding(6) var env_irradiance: texture_2d<f32>;
@group(1) @binding(7) var indirect_irradiance: texture_2d<f32>;
@group(1) @binding(8) var out_radiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(9) var ao: texture_2d<f32>;
@group(1) @binding(10) var far_field: texture_2d<f32>;

// Whether the technique wrote only ao (irradiance_terms.wgsl).
override AO_SCALES_FAR: bool = false;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        // Background: alpha 0 marks it for EXR output and metrics.
        let bg = min(env_radiance_at(env_radiance, env_sampler, env, view_ray(view, pixel), 0.0), vec3<f32>(65000.0));
        textureStore(out_radiance, pixel, vec4<f32>(bg, 0.0));
        return;
    }
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let metallic = textureLoad(gb_material, pixel, 0).r;
    let light = textureLoad(light_irradiance, pixel, 0).rgb;
    let t = technique_terms(env_irradiance, indirect_irradiance, ao, far_field, AO_SCALES_FAR, far_volume(far_probes), pixel, albedo, light);
    let irradiance = t.env + light + t.indirect;
    let radiance = textureLoad(gb_emissive, pixel, 0).rgb
        + (1.0 - metallic) * albedo * irradiance
        + textureLoad(specular, pixel, 0).rgb;
    textureStore(out_radiance, pixel, vec4<f32>(min(radiance, vec3<f32>(65000.0)), 1.0));
}

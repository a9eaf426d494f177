// aov.wgsl — copies one AOV (selection.aov, numbered as crate::Aov) into an rgba32float image
// for output: rgb = the AOV's value exactly as docs/src/aovs.md defines it, a = 1 on surfaces,
// 0 on background (where rgb = 0, except for `radiance`, which shows the environment).
//
//   1 radiance  2 albedo  3 normal (world, unit)  4 depth (view depth, m)  5 ao
//   6 env-irradiance  7 light-irradiance  8 indirect-irradiance
//   9 diffuse = ρ · (env-irradiance + light-irradiance + indirect-irradiance)
//   10 motion (pixels, rg)  11 specular  12 direct-radiance (kept for the next frame)
//   13 lambertian = emission + ρ · (env-irradiance + light-irradiance + indirect-irradiance)
//   14 far-irradiance (the technique's far-field term: the env-irradiance image)

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var gb_albedo: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var gb_motion: texture_2d<f32>;
@group(1) @binding(4) var radiance: texture_2d<f32>;
@group(1) @binding(5) var ao: texture_2d<f32>;
@group(1) @binding(6) var env_irradiance: texture_2d<f32>;
@group(1) @binding(7) var light_irradiance: texture_2d<f32>;
@group(1) @binding(8) var indirect_irradiance: texture_2d<f32>;
@group(1) @binding(9) var specular: texture_2d<f32>;
@group(1) @binding(10) var direct_radiance: texture_2d<f32>;
@group(1) @binding(11) var gb_emissive: texture_2d<f32>;
@group(1) @binding(12) var out_aov: texture_storage_2d<rgba32float, write>;
@group(1) @binding(13) var far_field: texture_2d<f32>;

// Which AOV to copy (crate::passes::aov::AovSelection): the pass's own, written before it runs,
// so that reading an AOV leaves the frame's uniforms as the frame was rendered with.
struct AovSelection {
    aov: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}
@group(1) @binding(14) var<uniform> selection: AovSelection;

// Whether the technique wrote only ao (gtao): its env- and indirect-irradiance are then formed
// here (irradiance_terms.wgsl).
override AO_SCALES_FAR: bool = false;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let surface = textureLoad(gb_normal, pixel, 0).w;
    let terms = technique_terms(env_irradiance, indirect_irradiance, ao, far_field, AO_SCALES_FAR, far_volume(far_probes), pixel, textureLoad(gb_albedo, pixel, 0).rgb, textureLoad(light_irradiance, pixel, 0).rgb);
    var v = vec3<f32>(0.0);
    switch selection.aov {
        case 1u: {
            v = textureLoad(radiance, pixel, 0).rgb;
        }
        case 2u: {
            v = textureLoad(gb_albedo, pixel, 0).rgb;
        }
        case 3u: {
            v = textureLoad(gb_normal, pixel, 0).xyz;
        }
        case 4u: {
            v = vec3<f32>(textureLoad(gb_view_depth, pixel, 0).r);
        }
        case 5u: {
            v = vec3<f32>(textureLoad(ao, pixel, 0).r);
        }
        case 6u, 14u: {
            v = terms.env;
        }
        case 7u: {
            v = textureLoad(light_irradiance, pixel, 0).rgb;
        }
        case 8u: {
            v = terms.indirect;
        }
        case 9u: {
            v = textureLoad(gb_albedo, pixel, 0).rgb * (terms.env + textureLoad(light_irradiance, pixel, 0).rgb + terms.indirect);
        }
        case 10u: {
            v = vec3<f32>(textureLoad(gb_motion, pixel, 0).rg, 0.0);
        }
        case 11u: {
            v = textureLoad(specular, pixel, 0).rgb;
        }
        case 12u: {
            v = textureLoad(direct_radiance, pixel, 0).rgb;
        }
        case 13u: {
            v = textureLoad(gb_emissive, pixel, 0).rgb
                + textureLoad(gb_albedo, pixel, 0).rgb * (terms.env + textureLoad(light_irradiance, pixel, 0).rgb + terms.indirect);
        }
        default: {
        }
    }
    if surface == 0.0 && selection.aov != 1u {
        v = vec3<f32>(0.0);
    }
    textureStore(out_aov, pixel, vec4<f32>(v, surface));
}

// tonemap.wgsl — linear HDR radiance → display sRGB (the `final` AOV).
//
//   c = radiance · 2^exposure, then one operator (frame.post.y):
//     0 `aces`    Narkowicz' fit of the ACES filmic curve ("ACES Filmic Tone Mapping Curve", 2015),
//                 applied per channel to c · 0.6 (his scale for scene-referred input);
//     1 `neutral` Khronos PBR Neutral (2024): hue-preserving, leaves colours below 0.76 untouched;
//     2 `linear`  clamp to [0, 1].
//   then the sRGB transfer function; stored as rgba8unorm (already encoded).

@group(0) @binding(8) var radiance: texture_2d<f32>;
@group(0) @binding(9) var out_final: texture_storage_2d<rgba8unorm, write>;

fn aces_fitted(x: vec3<f32>) -> vec3<f32> {
    let v = x * 0.6;
    return clamp((v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn pbr_neutral(c_in: vec3<f32>) -> vec3<f32> {
    let start_compression = 0.8 - 0.04;
    let desaturation = 0.15;
    let x = min(c_in.r, min(c_in.g, c_in.b));
    let offset = select(0.04, x - 6.25 * x * x, x < 0.08);
    var c = c_in - offset;
    let peak = max(c.r, max(c.g, c.b));
    if peak < start_compression {
        return c;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    c *= new_peak / peak;
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(c, vec3<f32>(new_peak), g);
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let c = max(textureLoad(radiance, pixel, 0).rgb, vec3<f32>(0.0)) * exp2(frame.post.x);
    var mapped: vec3<f32>;
    switch u32(frame.post.y) {
        case 1u: {
            mapped = pbr_neutral(c);
        }
        case 2u: {
            mapped = c;
        }
        default: {
            mapped = aces_fitted(c);
        }
    }
    let encoded = srgb_encode(clamp(mapped, vec3<f32>(0.0), vec3<f32>(1.0)));
    textureStore(out_final, pixel, vec4<f32>(encoded, 1.0));
}

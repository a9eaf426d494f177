// tonemap_ops.wgsl — display transforms shared by the tonemap and display passes, a library of
// pure functions (no bindings; the operator arrives as a parameter):
//   `aces`    Narkowicz' fit of the ACES filmic curve ("ACES Filmic Tone Mapping Curve", 2015),
//             applied per channel to c · 0.6 (his scale for scene-referred input);
//   `neutral` Khronos PBR Neutral (2024): hue-preserving, leaves colours below 0.76 untouched;
//   `linear`  clamp to [0, 1];
// and the sRGB transfer function.

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

// Operator `op` (crate::Tonemap::index: 0 aces, 1 neutral, 2 linear) on linear radiance `c`,
// then sRGB-encoded: the bytes of a display image.
fn tonemap_encode(c: vec3<f32>, op: u32) -> vec3<f32> {
    var mapped: vec3<f32>;
    switch op {
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
    return srgb_encode(clamp(mapped, vec3<f32>(0.0), vec3<f32>(1.0)));
}

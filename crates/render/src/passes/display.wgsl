// display.wgsl — turns one or two images into display bytes (sRGB-encoded rgba8), side by side:
// image A left of column `split`, image B from it on, a divider line between (an A/B view).
// Each side has its own mode:
//   0 encoded  already display bytes (`final`), copied
//   1 colour   linear radiance/irradiance: · 2^exposure, tonemap operator, sRGB
//   2 linear   linear values in [0, 1] (albedo): clamp, sRGB
//   3 normal   unit vectors: 0.5 + 0.5 n, as bytes
//   4 scalar   r in [lo, hi] → false colour (viridis, 9 stops, interpolated in display space)
//   5 vector   rg signed in [−hi, hi] → 0.5 + 0.5 v / hi in red and green
// With `coverage` (alpha = surface coverage, AOV images), background pixels of modes 2..5 are a
// grey checkerboard so that a value of 0 stays distinguishable from no surface.

struct DisplayParams {
    // Output width and height (pixels), the split column (≥ width: A only), the divider's
    // half-width (pixels).
    width: u32,
    height: u32,
    split: u32,
    divider: u32,
    // Mode of side A and of side B, tonemap operator, coverage bits (1: A, 2: B).
    mode_a: u32,
    mode_b: u32,
    tonemap: u32,
    coverage: u32,
    // Exposure (EV), false-colour range lo..hi.
    exposure: f32,
    lo: f32,
    hi: f32,
    _pad0: f32,
}

@group(1) @binding(0) var<uniform> params: DisplayParams;
@group(1) @binding(1) var image_a: texture_2d<f32>;
@group(1) @binding(2) var image_b: texture_2d<f32>;
@group(1) @binding(3) var out_display: texture_storage_2d<rgba8unorm, write>;

fn viridis(t_in: f32) -> vec3<f32> {
    var stops = array<vec3<f32>, 9>(
        vec3<f32>(68.0, 1.0, 84.0),
        vec3<f32>(72.0, 36.0, 117.0),
        vec3<f32>(59.0, 82.0, 139.0),
        vec3<f32>(44.0, 114.0, 142.0),
        vec3<f32>(33.0, 145.0, 140.0),
        vec3<f32>(40.0, 174.0, 128.0),
        vec3<f32>(94.0, 201.0, 98.0),
        vec3<f32>(173.0, 220.0, 48.0),
        vec3<f32>(253.0, 231.0, 37.0),
    );
    let t = clamp(t_in, 0.0, 1.0) * 8.0;
    let i = min(u32(t), 7u);
    return mix(stops[i], stops[i + 1u], t - f32(i)) / 255.0;
}

fn shade(v: vec4<f32>, mode: u32, coverage: bool, pixel: vec2<u32>) -> vec3<f32> {
    if coverage && mode >= 2u && v.a <= 0.0 {
        let checker = ((pixel.x / 8u) + (pixel.y / 8u)) % 2u;
        return vec3<f32>(select(0.16, 0.22, checker == 1u));
    }
    switch mode {
        case 0u: {
            return v.rgb;
        }
        case 1u: {
            let c = max(v.rgb, vec3<f32>(0.0)) * exp2(params.exposure);
            return tonemap_encode(c, params.tonemap);
        }
        case 2u: {
            return srgb_encode(clamp(v.rgb, vec3<f32>(0.0), vec3<f32>(1.0)));
        }
        case 3u: {
            return clamp(0.5 + 0.5 * v.xyz, vec3<f32>(0.0), vec3<f32>(1.0));
        }
        case 4u: {
            let span = max(params.hi - params.lo, 1e-20);
            return viridis((v.r - params.lo) / span);
        }
        default: {
            let m = max(params.hi, 1e-20);
            return vec3<f32>(clamp(0.5 + 0.5 * v.rg / m, vec2<f32>(0.0), vec2<f32>(1.0)), 0.5);
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if pixel.x >= params.width || pixel.y >= params.height {
        return;
    }
    let split = params.split;
    var c: vec3<f32>;
    if pixel.x < split {
        c = shade(textureLoad(image_a, pixel, 0), params.mode_a, (params.coverage & 1u) != 0u, pixel);
    } else {
        c = shade(textureLoad(image_b, pixel, 0), params.mode_b, (params.coverage & 2u) != 0u, pixel);
    }
    if split < params.width && abs(f32(pixel.x) + 0.5 - f32(split)) < f32(params.divider) {
        c = vec3<f32>(0.92);
    }
    textureStore(out_display, pixel, vec4<f32>(c, 1.0));
}

// lights.wgsl — punctual lights and their shadow maps, a library shared by direct_lighting.wgsl,
// the extra layers' shading and the near-field techniques that occlude lights in screen space. It
// declares no bindings: its functions take one light (`GpuLight`, an element of the light table)
// and what they read of the shadow maps as parameters. A pass that uses them declares, in its
// group 1 (Rust: `LightResources`, crate::contract::lights),
//   lights: array<GpuLight> (storage, read), shadow_clip_from_world: array<mat4x4<f32>>
//   (storage, read), shadow_maps: texture_depth_2d_array, shadow_sampler: sampler_comparison,
//   shadow_depths: texture_2d_array<f32> (the same maps, unfilterable: the loads of the disc
//   search, which GL cannot make from a depth texture),
// loops over `lights` itself, and passes the layer's matrix, shadow_clip_from_world[layer] with
// layer = shadow_layer(l, p), to shadow_visibility, and the frame's shadow normal offset (in
// shadow-map texels) to shadow_visibility and shadow_bias_length.
// `GpuLight` mirrors crate::gpu_scene::GpuLight; the irradiance formulas mirror
// nearfield_scene::Light (falloff, spot cone, range window).

struct GpuLight {
    // Position (point, spot) or direction of travel (directional); kind 0 directional, 1 point,
    // 2 spot.
    position: vec3<f32>,
    kind: f32,
    // Spot axis; range (m), 0 = unlimited.
    direction: vec3<f32>,
    range: f32,
    // Colour × intensity (lux or candela); tan of a directional disc light's angular radius (0:
    // punctual), which sizes its soft shadow.
    color: vec3<f32>,
    tan_radius: f32,
    // cos(inner), cos(outer) of a spot's cone; first shadow layer (−1: none); shadow texel size:
    // world metres for a directional light, metres per metre of distance for spot and point
    // lights.
    cos_inner: f32,
    cos_outer: f32,
    shadow_layer: f32,
    shadow_texel: f32,
}


// Unshadowed irradiance on a surface facing the light (Light::normal_irradiance) and the unit
// direction towards the light.
struct Incident {
    irradiance: vec3<f32>,
    to_light: vec3<f32>,
}

fn incident(l: GpuLight, p: vec3<f32>) -> Incident {
    var r: Incident;
    let kind = u32(l.kind);
    if kind == 0u {
        r.to_light = -l.position;
        r.irradiance = l.color;
        return r;
    }
    let d = l.position - p;
    let dist2 = max(dot(d, d), 1e-8);
    let dist = sqrt(dist2);
    r.to_light = d / max(dist, 1e-6);
    var e = l.color / dist2;
    if kind == 2u {
        let t = clamp((dot(l.direction, -r.to_light) - l.cos_outer) / max(l.cos_inner - l.cos_outer, 1e-4), 0.0, 1.0);
        e *= t * t;
    }
    if l.range > 0.0 {
        let q = dist / l.range;
        let w = clamp(1.0 - q * q * q * q, 0.0, 1.0);
        e *= w * w;
    }
    r.irradiance = e;
    return r;
}

// Index of the cube face (+X, −X, +Y, −Y, +Z, −Z) that sees direction v.
fn cube_face(v: vec3<f32>) -> u32 {
    let a = abs(v);
    if a.x >= a.y && a.x >= a.z {
        return select(1u, 0u, v.x > 0.0);
    }
    if a.y >= a.z {
        return select(3u, 2u, v.y > 0.0);
    }
    return select(5u, 4u, v.z > 0.0);
}

// The shadow-map layer of light l that sees world point p: its first layer, plus the cube face
// for a point light; 0 for an unshadowed light (shadow_visibility does not read it then).
fn shadow_layer(l: GpuLight, p: vec3<f32>) -> u32 {
    let first = l.shadow_layer;
    if first < 0.0 {
        return 0u;
    }
    var layer = u32(first);
    if u32(l.kind) == 1u {
        let from_light = p - l.position;
        layer += cube_face(from_light);
    }
    return layer;
}

// The shadow filters a pass's lights need: a pass specialises its pipeline with them from its
// light table (crate::contract::lights::shadow_filter_constants), and a kernel that leaves them at true
// keeps both. A backend that runs a kernel as SIMD over pixels (lavapipe) executes both sides of
// an `if` for every pixel, so a filter that no light uses costs as much as one that is used
// unless the pipeline leaves it out (docs/src/architecture.md, "Specialised kernels").
// DISC_SHADOWS: some light is a directional disc (disc_shadow); PUNCTUAL_SHADOWS: some light
// is not (the 3×3 PCF).
override DISC_SHADOWS: bool = true;
override PUNCTUAL_SHADOWS: bool = true;

// Shadow-map visibility of light l at world point p with normal n: `layer` = shadow_layer(l, p)
// and `clip_from_world` its matrix (shadow_clip_from_world[layer]); `maps`/`depths` the shadow
// maps (filtered comparisons, unfilterable loads), `smp` their comparison sampler;
// `normal_offset` the receiver offset along n in shadow-map texels (frame.shadow_normal_offset).
fn shadow_visibility(maps: texture_depth_2d_array, depths: texture_2d_array<f32>, smp: sampler_comparison, normal_offset: f32, l: GpuLight, layer: u32, clip_from_world: mat4x4<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let first = l.shadow_layer;
    if first < 0.0 {
        return 1.0;
    }
    let kind = u32(l.kind);
    var texel_world = l.shadow_texel;
    if kind != 0u {
        let from_light = p - l.position;
        texel_world *= length(from_light);
    }
    let offset_p = p + n * (normal_offset * texel_world);
    let c = clip_from_world * vec4<f32>(offset_p, 1.0);
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 || ndc.z < 0.0 {
        return 1.0;
    }
    if DISC_SHADOWS && kind == 0u && l.tan_radius > 0.0 {
        return disc_shadow(maps, depths, smp, l, layer, clip_from_world, offset_p, n, uv, ndc.z);
    }
    if !PUNCTUAL_SHADOWS {
        return 1.0;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(maps));
    var sum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let o = vec2<f32>(f32(i), f32(j)) * texel;
            sum += textureSampleCompareLevel(maps, smp, uv + o, layer, ndc.z);
        }
    }
    return sum / 9.0;
}

// Visibility of a directional disc light (the environment's sun) of angular radius r,
// tan r = l.tan_radius, from its orthographic layer: percentage-closer soft shadows (Fernando
// 2005). (1) Blocker search: the mean depth of the texels (the centre and a spiral of
// DISC_SEARCH_SAMPLES over the disc's cone from p up to the light's near plane, at most
// DISC_SEARCH_TEXELS) nearer the light than the receiver that
// can hide part of the disc from p (lateral offset ≤ depth gap · tan r); none: lit, 1.
// (2) The penumbra's half width at p is
// (receiver − blocker distance) · tan r. (3) A PCF of that radius (at least one texel): n×n
// bilinear comparisons at most a texel apart, n = 3 for a one-texel radius, 4 up to 1.5, else 5.
// Both compare against the receiver's plane (its depth slope over the map from n), not a flat
// depth, so wide kernels do not shadow a surface by itself.
const DISC_SEARCH_TEXELS: f32 = 24.0;
const DISC_SEARCH_SAMPLES: i32 = 32;

fn disc_shadow(maps: texture_depth_2d_array, depths: texture_2d_array<f32>, smp: sampler_comparison, l: GpuLight, layer: u32, clip_from_world: mat4x4<f32>, p: vec3<f32>, n: vec3<f32>, uv: vec2<f32>, z: f32) -> f32 {
    let m = clip_from_world;
    let dims = vec2<f32>(textureDimensions(maps));
    // Metres of depth per unit of the map's depth (orthographic: a constant).
    let metres_per_depth = 1.0 / max(length(vec3<f32>(m[0].z, m[1].z, m[2].z)), 1e-12);
    let texel_world = l.shadow_texel;
    // The receiver plane's depth slope per uv unit: project two steps along the surface.
    let t1 = normalize(cross(n, select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.y) > 0.9)));
    let t2 = cross(n, t1);
    let c1 = m * vec4<f32>(p + t1 * texel_world, 1.0);
    let c2 = m * vec4<f32>(p + t2 * texel_world, 1.0);
    let d1 = vec3<f32>(c1.x * 0.5 + 0.5, 0.5 - c1.y * 0.5, c1.z) - vec3<f32>(uv, z);
    let d2 = vec3<f32>(c2.x * 0.5 + 0.5, 0.5 - c2.y * 0.5, c2.z) - vec3<f32>(uv, z);
    let det = d1.x * d2.y - d2.x * d1.y;
    var slope = vec2<f32>(0.0);
    if abs(det) > 1e-12 {
        slope = vec2<f32>(d1.z * d2.y - d2.z * d1.y, d2.z * d1.x - d1.z * d2.x) / det;
    }
    // Surfaces nearly edge-on to the light: cap the slope at 10 texels of depth per texel.
    let cap = 10.0 * texel_world / metres_per_depth * dims.x;
    slope = clamp(slope, vec2<f32>(-cap), vec2<f32>(cap));
    // Two texels of depth slack for the map's own quantisation and bias.
    let slack = 2.0 * texel_world / metres_per_depth;

    let search_world = l.tan_radius * z * metres_per_depth;
    let search = clamp(search_world / texel_world, 1.0, DISC_SEARCH_TEXELS) / dims;
    var blockers = 0.0;
    var blocker_depth = 0.0;
    for (var k = 0; k <= DISC_SEARCH_SAMPLES; k++) {
        // The centre, then a golden-angle spiral filling the search disc evenly.
        let rk = sqrt(f32(k) / f32(DISC_SEARCH_SAMPLES));
        let ak = f32(k) * 2.39996323;
        let o = vec2<f32>(cos(ak), sin(ak)) * rk * search;
        let q = clamp(uv + o, vec2<f32>(0.0), vec2<f32>(1.0) - 0.5 / dims);
        let d = textureLoad(depths, vec2<i32>(q * dims), layer, 0).r;
        let gap = z + dot(slope, o) - d;
        // A blocker counts only where it can hide part of the disc from p: its lateral offset
        // is within gap · tan r (plus a texel).
        let lateral = length(o * dims) * texel_world;
        if gap > slack && lateral <= gap * metres_per_depth * l.tan_radius + texel_world {
            blockers += 1.0;
            blocker_depth += d;
        }
    }
    // Without blockers the receiver is lit, and the filter gets no trips: it is not put behind
    // an early return, since a SIMD backend (lavapipe) runs both sides of an `if` for every lane
    // but leaves a loop once no lane is left in it.
    let gap = max(z - blocker_depth / max(blockers, 1.0), 0.0) * metres_per_depth;
    let filter_texels = clamp(gap * l.tan_radius / texel_world, 1.0, DISC_SEARCH_TEXELS);
    let kernel = filter_texels / dims;
    // Taps per side: as few as keep neighbours at most a texel apart (their bilinear footprints
    // meet), at most 5: 3 for a one-texel penumbra, 4 up to 1.5 texels, then 5.
    let taps = select(0, min(i32(ceil(2.0 * filter_texels)) + 1, 5), blockers > 0.0);
    let step = 2.0 * kernel / f32(max(taps - 1, 1));
    var sum = 0.0;
    for (var j = 0; j < taps; j++) {
        for (var i = 0; i < taps; i++) {
            let o = vec2<f32>(f32(i), f32(j)) * step - kernel;
            sum += textureSampleCompareLevel(maps, smp, uv + o, layer, z + dot(slope, o));
        }
    }
    return select(1.0, sum / f32(max(taps * taps, 1)), blockers > 0.0);
}

// Length along the light direction from p within which `shadow_visibility` cannot see an
// occluder (SSDO paper Sec. 5, Fig. 8): the paper's b = (t/2)·tan α for a texel of world size t
// at p and the angle α between n and the light, plus the two biases this shadow map adds — the
// rasterizer's slope-scaled depth bias (2 texels of depth slope: 2t·tan α, shadow.rs) and the
// receiver offset along n (`normal_offset` texels, frame.shadow_normal_offset: its component
// along the light, t·k·cos α). tan α is capped at 10 (α ≈ 84°). 0 for an unshadowed light.
fn shadow_bias_length(normal_offset: f32, l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    if l.shadow_layer < 0.0 {
        return 0.0;
    }
    var texel_world = l.shadow_texel;
    let kind = u32(l.kind);
    var to_light = -l.position;
    if kind != 0u {
        texel_world *= length(p - l.position);
        to_light = normalize(l.position - p);
    }
    let cos_a = clamp(dot(n, to_light), 1e-4, 1.0);
    let tan_a = min(sqrt(max(0.0, 1.0 - cos_a * cos_a)) / cos_a, 10.0);
    return texel_world * (2.5 * tan_a + normal_offset * cos_a);
}

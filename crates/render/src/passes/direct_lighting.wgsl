// direct_lighting.wgsl — direct light at every G-buffer pixel (compute, 8×8).
//
// For a surface point P with normal n, base colour ρ, metallic m and roughness r:
//   light_irradiance = (1/π) Σ_l E_l(P) · V_shadow        (the `light-irradiance` AOV)
//   specular         = Σ_l f_GGX · E_l · V_shadow + prefiltered_env(R, r) · (F0·A + B)
//   direct_radiance  = emission + ρ · (light_irradiance + env_irradiance_sh(n))
// E_l is the unshadowed irradiance of nearfield_scene::Light::irradiance (same falloff, same spot
// cone and range window). f_GGX is Cook–Torrance with the GGX distribution, the height-correlated
// Smith visibility and Schlick's Fresnel (Karis 2013), F0 = mix(0.04, ρ, m). (A, B) is Karis'
// analytic fit of the split-sum BRDF integral ("Physically Based Shading on Mobile", 2014) in
// place of a lookup table. `direct_radiance` is the outgoing diffuse radiance that near-field
// techniques gather as indirect light (DESIGN.md's L_o): it is kept for the next frame.
// Shadows: 3×3 PCF of hardware 2×2 comparisons from the shadow-map array, receiver offset along
// the normal by `frame.post.z` shadow-map texels (see passes/shadow.rs for both biases).

struct GpuLight {
    // xyz: position (point, spot) or direction of travel (directional); w: kind 0 dir, 1 point, 2 spot.
    position: vec4<f32>,
    // xyz: spot axis; w: range (m), 0 = unlimited.
    direction: vec4<f32>,
    // rgb: colour × intensity (lux or candela); w: unused.
    color: vec4<f32>,
    // cos(inner), cos(outer), first shadow layer (−1: none), shadow texel size: world metres for a
    // directional light, metres per metre of distance for spot and point lights.
    cone: vec4<f32>,
}

@group(0) @binding(8) var gb_normal: texture_2d<f32>;
@group(0) @binding(9) var gb_albedo: texture_2d<f32>;
@group(0) @binding(10) var gb_material: texture_2d<f32>;
@group(0) @binding(11) var gb_emissive: texture_2d<f32>;
@group(0) @binding(12) var gb_view_depth: texture_2d<f32>;
@group(0) @binding(13) var<storage, read> lights: array<GpuLight>;
@group(0) @binding(14) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(0) @binding(15) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(16) var shadow_sampler: sampler_comparison;
@group(0) @binding(17) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
@group(0) @binding(18) var out_specular: texture_storage_2d<rgba16float, write>;
@group(0) @binding(19) var out_direct_radiance: texture_storage_2d<rgba16float, write>;

// Unshadowed irradiance on a surface facing the light (Light::normal_irradiance) and the unit
// direction towards the light.
struct Incident {
    irradiance: vec3<f32>,
    to_light: vec3<f32>,
}

fn incident(l: GpuLight, p: vec3<f32>) -> Incident {
    var r: Incident;
    let kind = u32(l.position.w);
    if kind == 0u {
        r.to_light = -l.position.xyz;
        r.irradiance = l.color.rgb;
        return r;
    }
    let d = l.position.xyz - p;
    let dist2 = max(dot(d, d), 1e-8);
    let dist = sqrt(dist2);
    r.to_light = d / max(dist, 1e-6);
    var e = l.color.rgb / dist2;
    if kind == 2u {
        let t = clamp((dot(l.direction.xyz, -r.to_light) - l.cone.y) / max(l.cone.x - l.cone.y, 1e-4), 0.0, 1.0);
        e *= t * t;
    }
    if l.direction.w > 0.0 {
        let q = dist / l.direction.w;
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

fn shadow_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let first = l.cone.z;
    if first < 0.0 {
        return 1.0;
    }
    let kind = u32(l.position.w);
    var layer = u32(first);
    var texel_world = l.cone.w;
    if kind != 0u {
        let from_light = p - l.position.xyz;
        texel_world *= length(from_light);
        if kind == 1u {
            layer += cube_face(from_light);
        }
    }
    let offset_p = p + n * (frame.post.z * texel_world);
    let c = shadow_clip_from_world[layer] * vec4<f32>(offset_p, 1.0);
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 || ndc.z < 0.0 {
        return 1.0;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(shadow_maps));
    var sum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let o = vec2<f32>(f32(i), f32(j)) * texel;
            sum += textureSampleCompareLevel(shadow_maps, shadow_sampler, uv + o, layer, ndc.z);
        }
    }
    return sum / 9.0;
}

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
    if !in_bounds(pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_specular, pixel, vec4<f32>(0.0));
        textureStore(out_direct_radiance, pixel, vec4<f32>(0.0));
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
    let p = world_position(pixel, depth);
    let v = normalize(frame.camera_position.xyz - p);
    let n_v = max(dot(n, v), 1e-4);
    let f0 = mix(vec3<f32>(0.04), albedo, metallic);

    var irradiance = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    for (var i = 0u; i < frame.counts.y; i++) {
        let l = lights[i];
        let inc = incident(l, p);
        let n_l = dot(n, inc.to_light);
        if n_l <= 0.0 {
            continue;
        }
        let e = inc.irradiance * n_l * shadow_visibility(l, p, n);
        irradiance += e;
        let h = normalize(v + inc.to_light);
        let spec = d_ggx(max(dot(n, h), 0.0), a) * v_smith_ggx_correlated(n_v, n_l, a)
            * f_schlick(f0, max(dot(v, h), 0.0));
        specular += spec * e;
    }
    let light_irradiance = irradiance / PI;
    let r = reflect(-v, n);
    let ab = env_brdf_approx(roughness, n_v);
    specular += env_specular_at(r, roughness) * (f0 * ab.x + ab.y);
    let direct = emission + albedo * (light_irradiance + env_irradiance_sh(n));
    textureStore(out_light_irradiance, pixel, vec4<f32>(light_irradiance, 1.0));
    textureStore(out_specular, pixel, vec4<f32>(specular, 1.0));
    textureStore(out_direct_radiance, pixel, vec4<f32>(direct, 1.0));
}

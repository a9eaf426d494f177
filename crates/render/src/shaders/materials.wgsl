// materials.wgsl — the scene's vertices and materials as the raster passes read them (G-buffer,
// depth peeling and additional cameras, reflective shadow maps), after gpu_material.wgsl. Textures
// live in two 2D arrays (sRGB and linear) whose layers are
// resized to a common size; u32::MAX marks "no texture".
//
// It declares no bindings: surface_material takes the fragment's material (one element of the
// material table) and the two texture arrays and sampler it reads. A pass that uses it declares,
// in its group 1, materials: array<GpuMaterial> (storage, read), srgb_textures and
// linear_textures: texture_2d_array<f32>, material_sampler: sampler, and passes
// materials[in.material] and those.

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) material: u32,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) material: u32,
    // Where the surface point was in the previous frame (world): `world` unless the G-buffer,
    // which reads the previous positions of moving objects, says otherwise.
    @location(4) previous: vec3<f32>,
}

// A vertex seen through `clip_from_world` (the camera, a layer's view or a light's).
fn transform_vertex(v: VertexIn, clip_from_world: mat4x4<f32>) -> VertexOut {
    var o: VertexOut;
    o.clip = clip_from_world * vec4<f32>(v.position, 1.0);
    o.world = v.position;
    o.previous = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.material = v.material;
    return o;
}

// What the material gives at a fragment: base colour, metallic, roughness, emission. Discards
// fragments below the alpha cutoff. `m` is the fragment's material (materials[in.material]),
// `srgb_maps`/`linear_maps` the sRGB and linear texture arrays, `smp` their sampler.
struct SurfaceMaterial {
    base: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
}

fn surface_material(m: GpuMaterial, srgb_maps: texture_2d_array<f32>, linear_maps: texture_2d_array<f32>, smp: sampler, in: VertexOut, duv_dx: vec2<f32>, duv_dy: vec2<f32>) -> SurfaceMaterial {
    var base = m.base_color;
    if m.base_color_texture != NO_TEXTURE {
        base *= textureSampleGrad(srgb_maps, smp, in.uv, m.base_color_texture, duv_dx, duv_dy);
    }
    if base.a < m.alpha_cutoff {
        discard;
    }
    var metallic = m.metallic;
    var roughness = m.roughness;
    if m.metallic_roughness_texture != NO_TEXTURE {
        let mr = textureSampleGrad(linear_maps, smp, in.uv, m.metallic_roughness_texture, duv_dx, duv_dy);
        roughness *= mr.g;
        metallic *= mr.b;
    }
    var emissive = m.emissive;
    if m.emissive_texture != NO_TEXTURE {
        emissive *= textureSampleGrad(srgb_maps, smp, in.uv, m.emissive_texture, duv_dx, duv_dy).rgb;
    }
    return SurfaceMaterial(base.rgb, metallic, roughness, emissive);
}

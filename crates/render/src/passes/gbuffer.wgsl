// gbuffer.wgsl — rasterizes the scene into the G-buffer (the only raster pass besides shadows).
//
// Targets (formats in passes/gbuffer.rs, `GBuffer`):
//   0 normal      rgba16float  xyz = world-space unit shading normal facing the viewer side of
//                              the surface (flipped on back faces of double-sided materials),
//                              w = 1 on surfaces, 0 on background
//   1 albedo      rgba8unorm-srgb  base colour ρ (factor × texture), a = 1
//   2 material    rgba8unorm   r = metallic, g = perceptual roughness, b = 0, a = 1
//   3 emissive    rgba16float  emitted radiance (linear), a = 1
//   4 motion      rg16float    previous − current pixel position (pixels) of this surface point
//   5 view_depth  r32float     distance along −Z in view space (m); 0 on background
// Material data: `GpuMaterial` (gpu_scene.rs). Textures live in two 2D arrays (sRGB and linear)
// whose layers are resized to a common size; u32::MAX marks "no texture".

struct GpuMaterial {
    base_color: vec4<f32>,
    // rgb: emissive factor (strength applied); w: alpha cutoff (< 0: opaque).
    emissive: vec4<f32>,
    // metallic, roughness, unused, unused.
    params: vec4<f32>,
    // Layers: base colour (sRGB array), metallic-roughness (linear array), emissive (sRGB array).
    textures: vec4<u32>,
}

@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(2) var srgb_textures: texture_2d_array<f32>;
@group(0) @binding(3) var linear_textures: texture_2d_array<f32>;
@group(0) @binding(4) var material_sampler: sampler;

const NO_TEXTURE: u32 = 0xffffffffu;

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
}

// A vertex seen through `clip_from_world` (the camera, a layer's view or a light's).
fn transform_vertex(v: VertexIn, clip_from_world: mat4x4<f32>) -> VertexOut {
    var o: VertexOut;
    o.clip = clip_from_world * vec4<f32>(v.position, 1.0);
    o.world = v.position;
    o.normal = v.normal;
    o.uv = v.uv;
    o.material = v.material;
    return o;
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return transform_vertex(v, frame.clip_from_world);
}

struct GBufferOut {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) material: vec4<f32>,
    @location(3) emissive: vec4<f32>,
    @location(4) motion: vec4<f32>,
    @location(5) view_depth: vec4<f32>,
}

// What the material gives at a fragment: base colour, metallic, roughness, emission. Discards
// fragments below the alpha cutoff.
struct SurfaceMaterial {
    base: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
}

fn surface_material(in: VertexOut, duv_dx: vec2<f32>, duv_dy: vec2<f32>) -> SurfaceMaterial {
    let m = materials[in.material];
    var base = m.base_color;
    if m.textures.x != NO_TEXTURE {
        base *= textureSampleGrad(srgb_textures, material_sampler, in.uv, m.textures.x, duv_dx, duv_dy);
    }
    if base.a < m.emissive.w {
        discard;
    }
    var metallic = m.params.x;
    var roughness = m.params.y;
    if m.textures.y != NO_TEXTURE {
        let mr = textureSampleGrad(linear_textures, material_sampler, in.uv, m.textures.y, duv_dx, duv_dy);
        roughness *= mr.g;
        metallic *= mr.b;
    }
    var emissive = m.emissive.rgb;
    if m.textures.z != NO_TEXTURE {
        emissive *= textureSampleGrad(srgb_textures, material_sampler, in.uv, m.textures.z, duv_dx, duv_dy).rgb;
    }
    return SurfaceMaterial(base.rgb, metallic, roughness, emissive);
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> GBufferOut {
    // Gradients first, in uniform control flow; the texture fetches are conditional.
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let m = surface_material(in, duv_dx, duv_dy);
    var n = normalize(in.normal);
    if !front {
        n = -n;
    }
    var o: GBufferOut;
    o.normal = vec4<f32>(n, 1.0);
    o.albedo = vec4<f32>(m.base, 1.0);
    o.material = vec4<f32>(m.metallic, m.roughness, 0.0, 1.0);
    o.emissive = vec4<f32>(m.emissive, 1.0);
    o.motion = vec4<f32>(to_screen(frame.prev_clip_from_world, in.world) - in.clip.xy, 0.0, 0.0);
    o.view_depth = vec4<f32>(-(frame.view_from_world * vec4<f32>(in.world, 1.0)).z, 0.0, 0.0, 0.0);
    return o;
}

// ---- Extra layers (passes/layers.rs): depth peeling of the main view and additional cameras.
// One `LayerView` (common.wgsl) per pass (dynamic offset); `prev_depth` is the depth buffer of the layer before
// (peeling only). Targets: 0 normal (rgba16float: xyz oriented as layers.rs documents, w = 1),
// 1 albedo (rgba8unorm-srgb), 2 emissive (rgba16float), 3 view depth (r32float, 0 = none).

@group(0) @binding(5) var<uniform> layer_view: LayerView;
@group(0) @binding(6) var prev_depth: texture_depth_2d;

@vertex
fn vs_layer(v: VertexIn) -> VertexOut {
    return transform_vertex(v, layer_view.clip_from_world);
}

struct LayerOut {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
    @location(3) view_depth: vec4<f32>,
}

@fragment
fn fs_layer(in: VertexOut) -> LayerOut {
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let depth = -(layer_view.view_from_world * vec4<f32>(in.world, 1.0)).z;
    if layer_view.flags.x == 1u {
        // View depth of the layer before, from its depth buffer (directx-style perspective:
        // d = f (t − n) / ((f − n) t)  ⇔  t = f n / (f − d (f − n))).
        let d = textureLoad(prev_depth, vec2<u32>(in.clip.xy), 0);
        let near = layer_view.projection.x;
        let far = layer_view.projection.y;
        let before = far * near / (far - d * (far - near));
        // The layer before is re-rasterized with the same matrix, so its fragments land on the
        // stored depth to within a few ulps; a relative view-depth tolerance alone fails where the
        // buffer's resolution (≈ t² ulp / near) is coarser than it (small near planes).
        if d >= 1.0 || in.clip.z <= d + 4.0 * 1.2e-7 || depth <= before * (1.0 + 1e-4) + 1e-6 {
            discard;
        }
    }
    let m = surface_material(in, duv_dx, duv_dy);
    let eye = layer_view.world_from_view[3].xyz;
    var n = normalize(in.normal);
    if dot(n, eye - in.world) < 0.0 {
        n = -n;
    }
    if layer_view.flags.y == 1u {
        n = -n;
    }
    var o: LayerOut;
    o.normal = vec4<f32>(n, 1.0);
    o.albedo = vec4<f32>(m.base, 1.0);
    o.emissive = vec4<f32>(m.emissive, 1.0);
    o.view_depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    return o;
}

// ---- Reflective shadow maps (passes/rsm.rs): the scene seen from a light. Targets (all
// rgba32float, read back by the CPU): 0 world position (w = 1 on surfaces), 1 unit normal turned
// towards the light, 2 base colour ρ.

struct RsmView {
    clip_from_world: mat4x4<f32>,
    // xyz: light position (w = 1) or direction towards the light (w = 0).
    to_light: vec4<f32>,
}

@group(0) @binding(7) var<uniform> rsm_view: RsmView;

@vertex
fn vs_rsm(v: VertexIn) -> VertexOut {
    return transform_vertex(v, rsm_view.clip_from_world);
}

struct RsmOut {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) albedo: vec4<f32>,
}

@fragment
fn fs_rsm(in: VertexOut) -> RsmOut {
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let m = surface_material(in, duv_dx, duv_dy);
    let l = rsm_view.to_light.xyz - in.world * rsm_view.to_light.w;
    var n = normalize(in.normal);
    if dot(n, l) < 0.0 {
        n = -n;
    }
    var o: RsmOut;
    o.position = vec4<f32>(in.world, 1.0);
    o.normal = vec4<f32>(n, 0.0);
    o.albedo = vec4<f32>(m.base, 1.0);
    return o;
}

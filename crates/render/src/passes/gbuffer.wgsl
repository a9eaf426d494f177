// gbuffer.wgsl — rasterizes the scene into the G-buffer (the only raster pass besides shadows).
//
// Targets (formats in passes/gbuffer.rs, `GBuffer`):
//   0 normal      rgba16float  xyz = world-space unit shading normal facing the viewer side of
//                              the surface (flipped on back faces of double-sided materials),
//                              w = 1 on surfaces, 0 on background
//   1 albedo      rgba8unorm-srgb  base colour ρ (factor × texture), a = 1
//   2 material    rgba8unorm   r = metallic, g = perceptual roughness, b = 1 on a surface the far
//                              field's bake never saw (a dynamic mesh, GpuMaterial.dynamic), a = 1
//   3 emissive    rgba16float  emitted radiance (linear), a = 1
//   4 motion      rg16float    previous − current pixel position (pixels) of this surface point,
//                              moved by the camera and by its object's own motion
//   5 view_depth  r32float     distance along −Z in view space (m); 0 on background
// Material data: shaders/materials.wgsl.

@group(1) @binding(0) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(1) var srgb_textures: texture_2d_array<f32>;
@group(1) @binding(2) var linear_textures: texture_2d_array<f32>;
@group(1) @binding(3) var material_sampler: sampler;

// The second vertex buffer: each vertex's world position in the previous frame (the scene's own
// positions where nothing moves), what the motion target is made of.
@vertex
fn vs_main(v: VertexIn, @location(4) previous: vec3<f32>) -> VertexOut {
    var o = transform_vertex(v, view.clip_from_world);
    o.previous = previous;
    return o;
}

struct GBufferOut {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) material: vec4<f32>,
    @location(3) emissive: vec4<f32>,
    @location(4) motion: vec4<f32>,
    @location(5) view_depth: vec4<f32>,
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> GBufferOut {
    // Gradients first, in uniform control flow; the texture fetches are conditional.
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let m = surface_material(materials[in.material], srgb_textures, linear_textures, material_sampler, in, duv_dx, duv_dy);
    var n = normalize(in.normal);
    if !front {
        n = -n;
    }
    var o: GBufferOut;
    o.normal = vec4<f32>(n, 1.0);
    o.albedo = vec4<f32>(m.base, 1.0);
    o.material = vec4<f32>(m.metallic, m.roughness, materials[in.material].dynamic, 1.0);
    o.emissive = vec4<f32>(m.emissive, 1.0);
    o.motion = vec4<f32>(to_screen(view, view.prev_clip_from_world, in.previous) - in.clip.xy, 0.0, 0.0);
    o.view_depth = vec4<f32>(-(view.view_from_world * vec4<f32>(in.world, 1.0)).z, 0.0, 0.0, 0.0);
    return o;
}

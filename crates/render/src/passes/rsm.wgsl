// rsm.wgsl — reflective shadow maps (passes/rsm.rs, raster): the scene seen from a light. Targets (all
// rgba32float, read back by the CPU): 0 world position (w = 1 on surfaces), 1 unit normal turned
// towards the light, 2 base colour ρ.

struct RsmView {
    clip_from_world: mat4x4<f32>,
    // xyz: light position (w = 1) or direction towards the light (w = 0).
    to_light: vec4<f32>,
}

@group(1) @binding(0) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(1) var srgb_textures: texture_2d_array<f32>;
@group(1) @binding(2) var linear_textures: texture_2d_array<f32>;
@group(1) @binding(3) var material_sampler: sampler;
@group(1) @binding(4) var<uniform> rsm_view: RsmView;

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
    let m = surface_material(materials[in.material], srgb_textures, linear_textures, material_sampler, in, duv_dx, duv_dy);
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

// shadow.wgsl — renders one shadow-map layer (depth only) per draw call.
//
// Every shadowed light owns layers of one depth32float 2D array: a directional light one
// (orthographic, fitted to the scene's bounding sphere), a spot light one (perspective over its
// outer cone), a point light six (90° cube faces +X, −X, +Y, −Y, +Z, −Z). The layer's
// light_clip_from_world arrives through a dynamic uniform offset. Alpha-masked materials are
// tested as in the G-buffer so that foliage casts leaf-shaped shadows. Biases: see shadow.rs.

struct ShadowView {
    light_clip_from_world: mat4x4<f32>,
}

@group(1) @binding(0) var<uniform> view: ShadowView;
@group(1) @binding(1) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(2) var srgb_textures: texture_2d_array<f32>;
@group(1) @binding(3) var material_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) material: u32,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) material: u32,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var o: VertexOut;
    o.clip = view.light_clip_from_world * vec4<f32>(v.position, 1.0);
    o.uv = v.uv;
    o.material = v.material;
    return o;
}

@fragment
fn fs_main(in: VertexOut) {
    let m = materials[in.material];
    if m.alpha_cutoff >= 0.0 && m.base_color_texture != NO_TEXTURE {
        let a = m.base_color.a * textureSampleLevel(srgb_textures, material_sampler, in.uv, m.base_color_texture, 0.0).a;
        if a < m.alpha_cutoff {
            discard;
        }
    }
}

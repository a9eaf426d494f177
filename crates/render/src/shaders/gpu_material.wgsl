// gpu_material.wgsl — `GpuMaterial`, one material of the scene as the raster passes read it
// (mirrors crate::gpu_scene::GpuMaterial; a naga test checks the offsets). A library: no bindings.

struct GpuMaterial {
    base_color: vec4<f32>,
    // Emissive factor (strength applied); alpha cutoff (< 0: opaque).
    emissive: vec3<f32>,
    alpha_cutoff: f32,
    metallic: f32,
    roughness: f32,
    // 1 on the meshes the far field's bake never saw (dynamic), 0 on the rest.
    dynamic: f32,
    _pad1: f32,
    // Layers: base colour (sRGB array), metallic-roughness (linear array), emissive (sRGB array);
    // NO_TEXTURE: none.
    base_color_texture: u32,
    metallic_roughness_texture: u32,
    emissive_texture: u32,
    _pad2: u32,
}

const NO_TEXTURE: u32 = 0xffffffffu;

// merge.wgsl — the 16 layers back to full resolution.
// Derivations and sources: technique/horizon/mod.rs.

// merge: layers → full resolution.

@group(1) @binding(0) var layered_cone: texture_2d_array<f32>;
@group(1) @binding(1) var layered_near: texture_2d_array<f32>;
@group(1) @binding(2) var layered_far: texture_2d_array<f32>;
@group(1) @binding(3) var merged_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(4) var merged_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(5) var merged_far: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn merge(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let texel = pixel / 4u;
    let layer = (pixel.x % 4u) + 4u * (pixel.y % 4u);
    textureStore(merged_cone, pixel, textureLoad(layered_cone, texel, layer, 0));
    textureStore(merged_near, pixel, textureLoad(layered_near, texel, layer, 0));
    textureStore(merged_far, pixel, textureLoad(layered_far, texel, layer, 0));
}

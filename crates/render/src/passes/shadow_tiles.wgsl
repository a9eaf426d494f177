// shadow_tiles.wgsl — the depth tiles of one shadow-map layer (compute, 8×8, one tile per
// invocation): for each SHADOW_TILE² block of texels, its nearest and farthest depth, stored as
// (nearest, farthest, 0, 0). lights.wgsl's disc_tiles_decide reads them to settle a disc light's
// soft shadow without its blocker search where the whole neighbourhood is lit or in umbra. Run
// after the layer is drawn (passes/shadow.rs), for disc lights' layers only.

@group(1) @binding(0) var depth: texture_2d<f32>;
@group(1) @binding(1) var out_tiles: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let tiles = textureDimensions(out_tiles);
    if any(id.xy >= tiles) {
        return;
    }
    let dims = vec2<i32>(textureDimensions(depth));
    let lo = vec2<i32>(id.xy) * SHADOW_TILE;
    let hi = min(lo + SHADOW_TILE, dims);
    var range = vec2<f32>(3.0e38, -3.0e38);
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            let d = textureLoad(depth, vec2<i32>(x, y), 0).r;
            range = vec2<f32>(min(range.x, d), max(range.y, d));
        }
    }
    textureStore(out_tiles, id.xy, vec4<f32>(range, 0.0, 0.0));
}

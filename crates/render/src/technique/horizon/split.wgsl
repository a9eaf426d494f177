// split.wgsl — the 4×4 deinterleave (HBIL Sec. 3.3): full-resolution geometry and radiance into 16 quarter-resolution layers.
// Sources: technique/horizon/mod.rs; the derivations sit beside the code (slice.wgsl, march.wgsl).

// split: full resolution → 16 layers (layer = (x % 4) + 4 (y % 4), texel = (x / 4, y / 4)).

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var full_depth: texture_2d<f32>;
@group(1) @binding(2) var full_normal: texture_2d<f32>;
@group(1) @binding(3) var full_radiance: texture_2d<f32>;
@group(1) @binding(4) var split_geometry: texture_storage_2d_array<rgba32float, write>;
@group(1) @binding(5) var split_radiance: texture_storage_2d_array<rgba16float, write>;

// xyz: normal, w: view depth (0 on background) — one fetch per horizon sample.

@compute @workgroup_size(8, 8, 1)
fn split(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = id.xy;
    if texel.x >= params.layer_width || texel.y >= params.layer_height {
        return;
    }
    for (var layer = 0u; layer < 16u; layer++) {
        let pixel = texel * 4u + vec2<u32>(layer % 4u, layer / 4u);
        var depth = 0.0;
        var normal = vec4<f32>(0.0);
        var radiance = vec4<f32>(0.0);
        if in_bounds(view, pixel) {
            normal = textureLoad(full_normal, pixel, 0);
            depth = select(0.0, textureLoad(full_depth, pixel, 0).r, normal.w != 0.0);
            if params.indirect == 1u {
                radiance = textureLoad(full_radiance, pixel, 0);
            }
        }
        textureStore(split_geometry, texel, layer, vec4<f32>(normal.xyz, depth));
        if params.indirect == 1u {
            textureStore(split_radiance, texel, layer, radiance);
        }
    }
}

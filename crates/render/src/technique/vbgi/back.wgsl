// back.wgsl — the second depth layer's view depth and direct radiance into the 16 interleaved
// layers (vbgi with `thickness=layer` and interleaving; layout as split.wgsl in
// technique/horizon).

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var full_back: texture_2d_array<f32>;
@group(1) @binding(2) var split_back: texture_storage_2d_array<r32float, write>;
@group(1) @binding(3) var full_back_radiance: texture_2d_array<f32>;
@group(1) @binding(4) var split_back_radiance: texture_storage_2d_array<rgba16float, write>;

// Whether the rear's radiance is deinterleaved too (with a probe volume; vbgi's march).
override REAR: bool = true;

@compute @workgroup_size(8, 8, 1)
fn back(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = id.xy;
    if texel.x >= params.layer_width || texel.y >= params.layer_height {
        return;
    }
    for (var layer = 0u; layer < 16u; layer++) {
        let pixel = texel * 4u + vec2<u32>(layer % 4u, layer / 4u);
        var depth = 0.0;
        var radiance = vec4<f32>(0.0);
        if in_bounds(view, pixel) {
            depth = textureLoad(full_back, pixel, 0, 0).r;
            if REAR {
                radiance = textureLoad(full_back_radiance, pixel, 0, 0);
            }
        }
        textureStore(split_back, texel, layer, vec4<f32>(depth, 0.0, 0.0, 0.0));
        if REAR {
            textureStore(split_back_radiance, texel, layer, radiance);
        }
    }
}

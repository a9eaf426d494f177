// tonemap.wgsl — linear HDR radiance → display sRGB (the `final` AOV).
//
//   c = radiance · 2^exposure, then one operator (frame.tonemap; tonemap_ops.wgsl), then the sRGB
//   transfer function; stored as rgba8unorm (already encoded).

@group(1) @binding(0) var radiance: texture_2d<f32>;
@group(1) @binding(1) var out_final: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let c = max(textureLoad(radiance, pixel, 0).rgb, vec3<f32>(0.0)) * exp2(frame.exposure);
    textureStore(out_final, pixel, vec4<f32>(tonemap_encode(c, u32(frame.tonemap)), 1.0));
}

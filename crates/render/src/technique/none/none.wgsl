// none.wgsl — the `none` near-field technique: no occlusion and no indirect light.
//
//   ao = 1, env_irradiance = E_far(n)/π unoccluded, indirect_irradiance = 0.
// E_far is what the frame's direct pass left in env_irradiance on entry (NearFieldOutputs): the
// environment's order-2 SH irradiance, or a probe volume's at P (a classic irradiance-volume
// render), so `none` writes env_irradiance only on background pixels.
// Every other technique writes the same three outputs with its own estimate; `none` is the
// baseline that shows what the near field changes.

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(2) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(3) var out_indirect_irradiance: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_indirect_irradiance, pixel, vec4<f32>(0.0));
        return;
    }
    textureStore(out_ao, pixel, vec4<f32>(1.0));
    textureStore(out_indirect_irradiance, pixel, vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

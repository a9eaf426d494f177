// resolve.wgsl — svgf's filtered results into the technique's AOVs (passes/denoise/mod.rs).

@group(1) @binding(0) var final_signal: texture_2d<f32>;
@group(1) @binding(1) var final_env: texture_2d<f32>;
@group(1) @binding(2) var final_indirect: texture_2d<f32>;
@group(1) @binding(3) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(4) var out_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(5) var out_indirect: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let s = textureLoad(final_signal, pixel, 0);
    textureStore(out_ao, pixel, vec4<f32>(clamp(s.x, 0.0, 1.0), 0.0, 0.0, 0.0));
    textureStore(out_env, pixel, vec4<f32>(textureLoad(final_env, pixel, 0).rgb, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(textureLoad(final_indirect, pixel, 0).rgb, 1.0));
}

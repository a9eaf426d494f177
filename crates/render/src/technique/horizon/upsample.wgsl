// upsample.wgsl — `resolution=half` with the bilateral blur (the `upsample` kernel): the
// search's results, one texel per 2×2 block, brought to every pixel (half.wgsl) before the blur.
// Without the blur accumulate.wgsl upsamples on its way in and this pass does not run.
// Sources: technique/horizon/mod.rs; the derivations sit beside the code (slice.wgsl, march.wgsl).

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var half_cone: texture_2d<f32>;
@group(1) @binding(4) var half_near: texture_2d<f32>;
@group(1) @binding(5) var half_far: texture_2d<f32>;
@group(1) @binding(6) var out_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(7) var out_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(8) var out_far: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn upsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    let h = half_upsample(gb_normal, gb_view_depth, half_cone, half_near, half_far, far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, env, pixel, nw, depth);
    textureStore(out_cone, pixel, h.cone);
    if NEAR {
        textureStore(out_near, pixel, vec4<f32>(h.near, 1.0));
    }
    if FAR {
        textureStore(out_far, pixel, h.far);
    }
}

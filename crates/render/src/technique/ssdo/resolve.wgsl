// resolve.wgsl — ssdo/ssao `resolve`: the blurred `direct` results → env-irradiance
// (visibility × the far field's irradiance — the sky's SH or the probe volume's — in visibility
// mode; L_dir in radiance mode and for ssdo-vpl) and ao.

@group(1) @binding(0) var<uniform> params: SsdoParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var in_a: texture_2d<f32>;
@group(1) @binding(4) var in_b: texture_2d<f32>;
@group(1) @binding(5) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(1) @binding(6) var out_ao: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        return;
    }
    let a = textureLoad(in_a, pixel, 0);
    let n = normalize(nw.xyz);
    var env_e = vec3<f32>(0.0);
    if far_volume(far_probes) {
        let p = world_position(view, pixel, textureLoad(gb_view_depth, pixel, 0).r);
        env_e = a.w * far_irradiance_here(far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, p, n);
    } else {
        env_e = a.w * env_irradiance_sh(env, n);
    }
    if params.technique == 1u && (params.mode == 1u || params.vpl_mode == 1u) {
        env_e = a.rgb;
    }
    textureStore(out_env_irradiance, pixel, vec4<f32>(env_e, 1.0));
    textureStore(out_ao, pixel, vec4<f32>(textureLoad(in_b, pixel, 0).r));
}

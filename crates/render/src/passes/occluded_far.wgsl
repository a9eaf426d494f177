// occluded_far.wgsl — env-irradiance and indirect-irradiance for a technique that writes only
// ao (gtao, which declares ao and the bent normal): what nearfield's own frame composes from
// them. The technique's own rule (gtao, Jimenez et al. 2016: ao scales the unoccluded light):
//
//   env_irradiance = ao · E_far(n)/π,   indirect_irradiance = 0,
//
// with E_far the sky's order-2 SH irradiance (env_irradiance_sh), or with a probe volume its
// SH at P (far_sh_here) — the expression the horizon kernel evaluated when it wrote these itself,
// so the images are the same bit for bit.

@group(1) @binding(0) var gb_normal: texture_2d<f32>;
@group(1) @binding(1) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(2) var in_ao: texture_2d<f32>;
@group(1) @binding(3) var out_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(4) var out_indirect: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(out_env, pixel, vec4<f32>(0.0));
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let ao = textureLoad(in_ao, pixel, 0).r;
    var e: vec3<f32>;
    if far_volume(far_probes) {
        let x = world_position(view, pixel, depth);
        e = ao * far_irradiance(far_sh_here(far_probes, far_visibility, env_sampler, view, x, n), n);
    } else {
        e = ao * env_irradiance_sh(env, n);
    }
    textureStore(out_env, pixel, vec4<f32>(e, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

// resolve.wgsl — the temporal running mean of one pixel and the far field through its bent cone,
// from this frame's raw results (for the `accumulate` kernel, which reads the G-buffer, writes
// the history and the AOVs: accumulate.wgsl). A library (after common.wgsl, env.wgsl, far.wgsl
// and params.wgsl): it declares no bindings; its functions take the textures, the sampler, the
// view (`cam`), the environment's uniform (`e`) and the pass's `HorizonParams` (`p`) they read.
// Derivations: slice.wgsl, march.wgsl and accumulate.wgsl.

fn energy_compensation(a: f32) -> f32 {
    return a * (1.0 + pow(max(1.0 - a, 0.0), 0.75) * 0.5);
}

// The far field's irradiance through the bent cone: the environment (sky) or the probe volume at
// world point x (its radiance SH in place of the environment's; the volume has no band 3).
// `probes`, `visibility`: the far field's (far_sh_here); `irradiance_map`: the environment's
// pre-convolved diffuse map (env_irradiance_exact); `smp`: the sampler of both.
fn cone_far_field(probes: texture_2d<f32>, visibility: texture_2d<f32>, irradiance_map: texture_2d<f32>, smp: sampler, cam: View, e: EnvUniforms, p: HorizonParams, x: vec3<f32>, n: vec3<f32>, bent: vec3<f32>, ao: f32, far: vec4<f32>) -> vec3<f32> {
    if FAR {
        // The far field through the slices' visible arcs (FAR is set exactly when p.far is
        // FAR_SLICES): the rest is left out of the pipeline.
        return max(far.rgb, vec3<f32>(0.0));
    }
    let volume = far_volume(probes);
    var f: FarSh;
    if volume {
        f = far_sh_here(probes, visibility, smp, cam, x, n);
    }
    switch p.far {
        case FAR_SH: {
            let cos_alpha = select(1.0 - ao, sqrt(1.0 - ao), p.aperture == 1u);
            if volume {
                return far_irradiance_cone(f, bent, cos_alpha);
            }
            return env_irradiance_cone(e, bent, cos_alpha);
        }
        case FAR_ENVMAP: {
            if volume {
                return far_irradiance(f, bent) * energy_compensation(ao);
            }
            return env_irradiance_exact(irradiance_map, smp, e, bent) * energy_compensation(ao);
        }
        default: {
            if volume {
                return ao * far_irradiance(f, n);
            }
            return ao * env_irradiance_sh(e, n);
        }
    }
}

// One pixel's running means: bent cone (xyz bent normal, w ao), near field (rgb, w frames in the
// mean) and far field.
struct Accumulated {
    cone: vec4<f32>,
    near: vec4<f32>,
    far: vec4<f32>,
}

// This frame's raw cone, near field (NEAR) and far field (FAR) of the surface point x (unit
// normal n, view depth `depth`) blended into last frame's means, fetched where x was from the
// taps of `prev_geometry` that pass the disocclusion test; this frame's values alone without
// history (first frame, camera cut, temporal off) or without a passing tap.
fn temporal_mean(prev_geometry: texture_2d<f32>, prev_cone: texture_2d<f32>, prev_near: texture_2d<f32>, prev_far: texture_2d<f32>, cam: View, p: HorizonParams, x: vec3<f32>, n: vec3<f32>, depth: f32, raw_cone: vec4<f32>, raw_near: vec3<f32>, raw_far: vec4<f32>) -> Accumulated {
    var cone = raw_cone;
    var far = raw_far;
    // Without near-field light (gtao) the near texture only keeps the frame count (w).
    var near = vec4<f32>(raw_near, 1.0);
    if p.temporal == 1u && cam.history_valid == 1u {
        let taps = history_taps(cam, prev_geometry, to_screen(cam, cam.prev_clip_from_world, x), x, n, depth, p.reject_depth, p.reject_normal);
        var sum_cone = vec4<f32>(0.0);
        var sum_near = vec4<f32>(0.0);
        var sum_far = vec4<f32>(0.0);
        for (var k = 0u; k < 4u; k++) {
            let w = taps.weights[k];
            if w > 0.0 {
                let q = taps.base + tap_offset(k);
                sum_cone += w * textureLoad(prev_cone, q, 0);
                sum_near += w * textureLoad(prev_near, q, 0);
                if FAR {
                    sum_far += w * textureLoad(prev_far, q, 0);
                }
            }
        }
        let weight = taps.total;
        if weight > 1e-3 {
            let hist_cone = sum_cone / weight;
            let hist_near = sum_near / weight;
            let count = min(hist_near.w + 1.0, p.max_history);
            let a = 1.0 / count;
            cone = mix(hist_cone, cone, a);
            far = mix(sum_far / weight, far, a);
            near = vec4<f32>(mix(hist_near.rgb, near.rgb, a), count);
        }
    }
    var r: Accumulated;
    r.cone = cone;
    r.near = near;
    r.far = far;
    return r;
}

// resolve.wgsl — the temporal running mean and the AOVs of one pixel, from this frame's raw
// results (the `accumulate` kernel). The including module
// declares the bindings (accumulate.wgsl's names). Derivations: technique/horizon/mod.rs and
// accumulate.wgsl.

fn energy_compensation(a: f32) -> f32 {
    return a * (1.0 + pow(max(1.0 - a, 0.0), 0.75) * 0.5);
}

// The far field's irradiance through the bent cone: the environment (sky) or the probe volume at
// world point x (its radiance SH in place of the environment's; the volume has no band 3).
fn cone_far_field(x: vec3<f32>, n: vec3<f32>, bent: vec3<f32>, ao: f32, far: vec4<f32>) -> vec3<f32> {
    let volume = far_volume() && params.far != FAR_SLICES;
    var f: FarSh;
    if volume {
        f = far_sh_here(x, n);
    }
    switch params.far {
        case FAR_SH: {
            let cos_alpha = select(1.0 - ao, sqrt(1.0 - ao), params.aperture == 1u);
            if volume {
                return far_irradiance_cone(f, bent, cos_alpha);
            }
            return env_irradiance_cone(bent, cos_alpha);
        }
        case FAR_ENVMAP: {
            if volume {
                return far_irradiance(f, bent) * energy_compensation(ao);
            }
            return env_irradiance_exact(bent) * energy_compensation(ao);
        }
        case FAR_SLICES: {
            if FAR {
                return max(far.rgb, vec3<f32>(0.0));
            }
            return vec3<f32>(0.0);
        }
        default: {
            if volume {
                return ao * far_irradiance(f, n);
            }
            return ao * env_irradiance_sh(n);
        }
    }
}

// The AOVs of one pixel (world point x, unit normal n) from its accumulated cone, near and far
// field.
fn write_outputs(pixel: vec2<u32>, x: vec3<f32>, n: vec3<f32>, cone: vec4<f32>, near: vec4<f32>, far: vec4<f32>) {
    let ao = clamp(cone.w, 0.0, 1.0);
    let bent = select(n, normalize(cone.xyz), dot(cone.xyz, cone.xyz) > 1e-12);
    let env = cone_far_field(x, n, bent, ao, far);
    textureStore(out_ao, pixel, vec4<f32>(ao, 0.0, 0.0, 0.0));
    textureStore(out_env, pixel, vec4<f32>(env, 1.0));
    if !NEAR {
        // gtao: no near-field light, and no next frame that gathers this one's radiance.
        textureStore(out_indirect, pixel, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let metallic = textureLoad(gb_material, pixel, 0).r;
    var indirect = near.rgb;
    if params.fresnel == 1u {
        indirect *= 1.0 - mix(vec3<f32>(0.04), albedo, metallic);
    }
    let light = textureLoad(light_irradiance, pixel, 0).rgb;
    let feedback = textureLoad(gb_emissive, pixel, 0).rgb + (1.0 - metallic) * albedo * (light + env + indirect);
    textureStore(out_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(out_feedback, pixel, vec4<f32>(min(feedback, vec3<f32>(65000.0)), 1.0));
}

// This frame's raw cone, near field (NEAR) and far field (FAR) of `pixel` → history and AOVs.
fn resolve(pixel: vec2<u32>, raw_cone: vec4<f32>, raw_near: vec3<f32>, raw_far: vec4<f32>) {
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(acc_cone, pixel, vec4<f32>(0.0));
        textureStore(acc_near, pixel, vec4<f32>(0.0));
        textureStore(acc_geometry, pixel, vec4<f32>(0.0));
        if FAR {
            textureStore(acc_far, pixel, vec4<f32>(0.0));
        }
        textureStore(out_ao, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        textureStore(out_env, pixel, vec4<f32>(0.0));
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        if NEAR {
            textureStore(out_feedback, pixel, vec4<f32>(0.0));
        }
        return;
    }
    let n = normalize(nw.xyz);
    let x = world_position(pixel, depth);
    var cone = raw_cone;
    var far = raw_far;
    // Without near-field light (gtao) the near texture only keeps the frame count (w).
    var near = vec4<f32>(raw_near, 1.0);
    if params.temporal == 1u && view.history_valid == 1u {
        let taps = history_taps(prev_geometry, to_screen(view.prev_clip_from_world, x), x, n, depth, params.reject_depth, params.reject_normal);
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
            let count = min(hist_near.w + 1.0, params.max_history);
            let a = 1.0 / count;
            cone = mix(hist_cone, cone, a);
            far = mix(sum_far / weight, far, a);
            near = vec4<f32>(mix(hist_near.rgb, near.rgb, a), count);
        }
    }
    textureStore(acc_cone, pixel, cone);
    textureStore(acc_near, pixel, near);
    textureStore(acc_geometry, pixel, vec4<f32>(n, depth));
    if FAR {
        textureStore(acc_far, pixel, far);
    }
    write_outputs(pixel, x, n, cone, near, far);
}

// accumulate.wgsl — the temporal running mean with disocclusion rejection, and the AOVs from it.
// Sources: technique/horizon/mod.rs; the derivations sit beside the code (slice.wgsl, march.wgsl).

// accumulate: running mean over up to `max_history` frames of the bent cone (xyz bent normal,
// w ao), the near-field irradiance (w = frames in the mean) and the far field. Last frame's
// accumulation is fetched where this surface point was (previous camera), bilinearly from the
// taps that pass the disocclusion test `same_surface` (common.wgsl) with the tap's surface point
// rebuilt from last frame's depth and camera: near this point's tangent plane (reject_depth ×
// depth), with a normal within acos(reject_normal), and within a few pixel footprints of it.
// No passing tap (or no history: first frame, camera cut, temporal off) restarts the mean at
// this frame's value. The accumulated values then give the AOVs in the same invocation:
//
// The AOVs and the diffuse radiance for the next frame:
//   ao                   accumulated cone .w
//   env-irradiance       far = 0 (gtao):   ao × E_SH(n)/π
//                        far = 1 (sh):     SH irradiance through the bent cone (Sec. 2.2.4),
//                                          aperture cos α = 1 − ao (Eq. 12) or, `matched`,
//                                          cos α = √(1 − ao). Deviation: Eq. 12 equates the
//                                          cone's solid angle with 2π ao, which holds for the
//                                          uniformly weighted AO of Eq. 1, but the AO here is
//                                          the cosine-weighted one of Eq. 9; a cone about the
//                                          normal has cosine-weighted visibility sin² α, so
//                                          Eq. 12 makes the cone too wide (ao = ½: 60° where
//                                          45° holds ½) and a uniform sky too bright (0.75
//                                          for ao = ½). `matched` takes the cone whose
//                                          cosine-weighted visibility is ao: exact for a
//                                          uniform environment.
//                        far = 2 (envmap): pre-convolved map at the bent normal × F0(ao),
//                                          F0(a) = a (1 + (1 − a)^0.75 / 2) (Sec. 2.2.3)
//                        far = 3 (slices): the environment integrated over each slice's
//                                          visible arcs (horizon pass), accumulated like ao —
//                                          directional, so light from one side (a sun) is
//                                          shadowed by the horizons that hide it
//   indirect-irradiance  accumulated E_near × (1 − F0) with F0 = mix(0.04, ρ, metallic) when
//                        `fresnel` is on (Eq. 19)
//   feedback             L_d = emission + (1 − metallic) ρ (light + env + indirect) irradiance
//                        (Eq. 17), gathered by the next frame

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(3) var raw_cone: texture_2d<f32>;
@group(1) @binding(4) var raw_near: texture_2d<f32>;
@group(1) @binding(5) var raw_far: texture_2d<f32>;
@group(1) @binding(6) var prev_cone: texture_2d<f32>;
@group(1) @binding(7) var prev_near: texture_2d<f32>;
@group(1) @binding(8) var prev_far: texture_2d<f32>;
@group(1) @binding(9) var prev_geometry: texture_2d<f32>;
@group(1) @binding(10) var acc_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(11) var acc_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(12) var acc_far: texture_storage_2d<rgba16float, write>;
@group(1) @binding(13) var acc_geometry: texture_storage_2d<rgba32float, write>;
@group(1) @binding(14) var gb_albedo: texture_2d<f32>;
@group(1) @binding(15) var gb_material: texture_2d<f32>;
@group(1) @binding(16) var gb_emissive: texture_2d<f32>;
@group(1) @binding(17) var light_irradiance: texture_2d<f32>;
@group(1) @binding(18) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(19) var out_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(20) var out_indirect: texture_storage_2d<rgba16float, write>;
@group(1) @binding(21) var out_feedback: texture_storage_2d<rgba16float, write>;
// The bent normal (xyz unit world, w = 1), written where params.bent_normal is 1.
@group(1) @binding(22) var out_bent: texture_storage_2d<rgba16float, write>;

// Whether this frame's accumulation is kept for the next (acc_*): false only for a technique
// without near-field light (gtao) whose running mean is off, which no later pass reads.
override HISTORY: bool = true;

// The AOVs of one pixel (world point x, unit normal n) from its accumulated cone, near and far
// field (the far field through the cone: resolve.wgsl's cone_far_field).
fn write_outputs(pixel: vec2<u32>, x: vec3<f32>, n: vec3<f32>, cone: vec4<f32>, near: vec4<f32>, far: vec4<f32>) {
    let ao = clamp(cone.w, 0.0, 1.0);
    let bent = select(n, normalize(cone.xyz), dot(cone.xyz, cone.xyz) > 1e-12);
    textureStore(out_ao, pixel, vec4<f32>(ao, 0.0, 0.0, 0.0));
    if params.bent_normal == 1u {
        textureStore(out_bent, pixel, vec4<f32>(bent, 1.0));
    }
    if !NEAR {
        // gtao writes ao and the bent normal only: no near-field light, no next frame that
        // gathers this one's radiance; nearfield's frame forms env-irradiance from the ao and
        // the far field the direct pass left (passes/composite.wgsl, AO_SCALES_FAR).
        return;
    }
    let env_irradiance = cone_far_field(far_probes, far_visibility, env_irradiance_map, env_sampler, view, env, params, x, n, bent, ao, far);
    textureStore(out_env, pixel, vec4<f32>(env_irradiance, 1.0));
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let metallic = textureLoad(gb_material, pixel, 0).r;
    var indirect = near.rgb;
    if params.fresnel == 1u {
        indirect *= 1.0 - mix(vec3<f32>(0.04), albedo, metallic);
    }
    let light = textureLoad(light_irradiance, pixel, 0).rgb;
    let feedback = textureLoad(gb_emissive, pixel, 0).rgb + (1.0 - metallic) * albedo * (light + env_irradiance + indirect);
    textureStore(out_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(out_feedback, pixel, vec4<f32>(min(feedback, vec3<f32>(65000.0)), 1.0));
}

// This frame's raw cone, near field (NEAR) and far field (FAR) of `pixel` (G-buffer normal `nw`,
// view depth `depth`) → history (resolve.wgsl's temporal_mean) and AOVs.
fn resolve(pixel: vec2<u32>, nw: vec4<f32>, depth: f32, raw_cone: vec4<f32>, raw_near: vec3<f32>, raw_far: vec4<f32>) {
    if nw.w == 0.0 || depth <= 0.0 {
        if HISTORY {
            textureStore(acc_cone, pixel, vec4<f32>(0.0));
            textureStore(acc_near, pixel, vec4<f32>(0.0));
            textureStore(acc_geometry, pixel, vec4<f32>(0.0));
        }
        if HISTORY && FAR {
            textureStore(acc_far, pixel, vec4<f32>(0.0));
        }
        textureStore(out_ao, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        if params.bent_normal == 1u {
            textureStore(out_bent, pixel, vec4<f32>(0.0));
        }
        if NEAR {
            textureStore(out_env, pixel, vec4<f32>(0.0));
            textureStore(out_indirect, pixel, vec4<f32>(0.0));
            textureStore(out_feedback, pixel, vec4<f32>(0.0));
        }
        return;
    }
    let n = normalize(nw.xyz);
    let x = world_position(view, pixel, depth);
    // Without history the running mean is off (keeps_history): this frame's values alone, and
    // the history taps are left out of the kernel rather than masked off (architecture.md,
    // "Specialised kernels").
    var acc: Accumulated;
    acc.cone = raw_cone;
    acc.near = vec4<f32>(raw_near, 1.0);
    acc.far = raw_far;
    if HISTORY {
        acc = temporal_mean(prev_geometry, prev_cone, prev_near, prev_far, view, params, x, n, depth, raw_cone, raw_near, raw_far);
        textureStore(acc_cone, pixel, acc.cone);
        textureStore(acc_near, pixel, acc.near);
        textureStore(acc_geometry, pixel, vec4<f32>(n, depth));
    }
    if HISTORY && FAR {
        textureStore(acc_far, pixel, acc.far);
    }
    write_outputs(pixel, x, n, acc.cone, acc.near, acc.far);
}

@compute @workgroup_size(8, 8, 1)
fn accumulate(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if HALF {
        // resolution=half without the blur: this frame's values from the searched 2×2 blocks
        // around the pixel (half.wgsl), raw_* holding one texel per block.
        let h = half_upsample(gb_normal, gb_view_depth, raw_cone, raw_near, raw_far, far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, env, pixel, nw, depth);
        resolve(pixel, nw, depth, h.cone, h.near, h.far);
        return;
    }
    var far = vec4<f32>(0.0);
    if FAR {
        far = textureLoad(raw_far, pixel, 0);
    }
    var near = vec3<f32>(0.0);
    if NEAR {
        near = textureLoad(raw_near, pixel, 0).rgb;
    }
    resolve(pixel, nw, depth, textureLoad(raw_cone, pixel, 0), near, far);
}

// outputs.wgsl — the AOVs and the diffuse radiance the next frame gathers.
// Derivations and sources: technique/horizon/mod.rs.

// outputs: the AOVs and the diffuse radiance for the next frame.
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
@group(1) @binding(2) var gb_albedo: texture_2d<f32>;
@group(1) @binding(3) var gb_material: texture_2d<f32>;
@group(1) @binding(4) var gb_emissive: texture_2d<f32>;
@group(1) @binding(5) var light_irradiance: texture_2d<f32>;
@group(1) @binding(6) var final_cone: texture_2d<f32>;
@group(1) @binding(7) var final_near: texture_2d<f32>;
@group(1) @binding(8) var final_far: texture_2d<f32>;
@group(1) @binding(9) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(10) var out_env: texture_storage_2d<rgba16float, write>;
@group(1) @binding(11) var out_indirect: texture_storage_2d<rgba16float, write>;
@group(1) @binding(12) var out_feedback: texture_storage_2d<rgba16float, write>;

fn energy_compensation(a: f32) -> f32 {
    return a * (1.0 + pow(max(1.0 - a, 0.0), 0.75) * 0.5);
}

@compute @workgroup_size(8, 8, 1)
fn outputs(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_ao, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        textureStore(out_env, pixel, vec4<f32>(0.0));
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        textureStore(out_feedback, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let cone = textureLoad(final_cone, pixel, 0);
    let ao = clamp(cone.w, 0.0, 1.0);
    let bent = select(n, normalize(cone.xyz), dot(cone.xyz, cone.xyz) > 1e-12);
    var env = vec3<f32>(0.0);
    switch params.far {
        case 1u: {
            let cos_alpha = select(1.0 - ao, sqrt(1.0 - ao), params.aperture == 1u);
            env = env_irradiance_cone(bent, cos_alpha);
        }
        case 2u: {
            let e = textureSampleLevel(env_irradiance_map, env_sampler, env_uv(bent), 0.0).rgb;
            env = e * frame.env_intensity * energy_compensation(ao);
        }
        case 3u: {
            env = textureLoad(final_far, pixel, 0).rgb;
        }
        default: {
            env = ao * env_irradiance_sh(n);
        }
    }
    let albedo = textureLoad(gb_albedo, pixel, 0).rgb;
    let metallic = textureLoad(gb_material, pixel, 0).r;
    var indirect = textureLoad(final_near, pixel, 0).rgb;
    if params.fresnel == 1u {
        indirect *= 1.0 - mix(vec3<f32>(0.04), albedo, metallic);
    }
    let light = textureLoad(light_irradiance, pixel, 0).rgb;
    let feedback = textureLoad(gb_emissive, pixel, 0).rgb + (1.0 - metallic) * albedo * (light + env + indirect);
    textureStore(out_ao, pixel, vec4<f32>(ao, 0.0, 0.0, 0.0));
    textureStore(out_env, pixel, vec4<f32>(env, 1.0));
    textureStore(out_indirect, pixel, vec4<f32>(indirect, 1.0));
    textureStore(out_feedback, pixel, vec4<f32>(min(feedback, vec3<f32>(65000.0)), 1.0));
}

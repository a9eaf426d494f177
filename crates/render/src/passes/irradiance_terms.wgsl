// irradiance_terms.wgsl — a library for the passes that read the technique's irradiance images
// (composite, aov). It declares no bindings. After a technique that writes only ao (gtao:
// `ao_only`, the passes' AO_SCALES_FAR), nearfield's frame forms its two other images where
// they are read, by the technique's own rule (Jimenez et al. 2016: ao scales the unoccluded
// light): env-irradiance = ao · E_far(n)/π, from the far field that the direct pass left in the
// env-irradiance image, and indirect-irradiance = 0.

// The technique's env-irradiance at `pixel`.
fn technique_env(env_irradiance: texture_2d<f32>, ao: texture_2d<f32>, ao_only: bool, pixel: vec2<u32>) -> vec3<f32> {
    let e = textureLoad(env_irradiance, pixel, 0).rgb;
    if ao_only {
        return textureLoad(ao, pixel, 0).r * e;
    }
    return e;
}

// The technique's indirect-irradiance at `pixel`.
fn technique_indirect(indirect_irradiance: texture_2d<f32>, ao_only: bool, pixel: vec2<u32>) -> vec3<f32> {
    if ao_only {
        return vec3<f32>(0.0);
    }
    return textureLoad(indirect_irradiance, pixel, 0).rgb;
}

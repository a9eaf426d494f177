// irradiance_terms.wgsl — a library for the passes that read the technique's irradiance images
// (composite, aov), after common.wgsl. It declares no bindings. After a technique that writes only
// ao (gtao: `ao_only`, the passes' AO_SCALES_FAR), nearfield's frame forms its two other images
// where they are read, by the technique's own rule (Jimenez et al. 2016: ao scales the
// unoccluded light): env-irradiance = ao · E_far(n)/π, from the far field the direct pass left
// (`far_field`: rgb E_far(n)/π, a the far field's own visibility within R), and
// indirect-irradiance = 0.
//
// Near and far counted once, with a probe volume (FAR_RULE, the technique's FarRule): the
// volume's irradiance E_far already holds the occlusion its probes see within R (its own
// visibility ao_far, far_field's alpha) and the light of those occluders. A technique changes
// the image only by what the volume does not hold (the book, "Near and far"):
//   1 occlusion    (ssao, gtao, ssdo, ssbn, instant-radiosity): v = env / E_far, the
//                  technique's visibility; the image takes min(E_far, E(v)), E(ao_far) =
//                  E_far, the occluders the volume holds lit as the receiver (its albedo, its
//                  light, GTAO's multi-bounce fit: `occluded_light`), split into env' =
//                  E_open · v, the open directions' light, and the rest, the occluders' light
//                  and the bounces, which joins the near light; its own bounce (ssdo,
//                  instant-radiosity) keeps the share the volume does not hold, h as below:
//                  indirect' = (1 − h) indirect + E(v) − E_open · v
//   2 directional  (s3ho): h = min(1, (1 − ao_far) / (1 − ao)) of the occlusion found is
//                  the volume's too: the image takes mix(env, E_far, h), env its far part (the
//                  open directions' light), the rest near: indirect' = (1 − h) indirect +
//                  mix(env, E_far, h) − env
//   0              (hbil, vbgi: near light that replaces the volume's; `none`, ssdo-vpl:
//                  their own): as written.
override FAR_RULE: u32 = 0u;

// GTAO's multi-bounce fit (Jimenez et al. 2016, Eq. 10) over the visibility: the light of a
// receiver of visibility a under a uniform environment, with the bounces between it and its
// occluders (their albedo taken as the receiver's), is E_open · a · bounces(a, ρ). Its value is
// F(a) = a · bounces(a, ρ), the fit's polynomial divided by a (kept ≥ 1: F(a) ≥ a).
fn bounces(a: f32, albedo: vec3<f32>) -> vec3<f32> {
    let ca = 2.0404 * albedo - 0.3324;
    let cb = -4.7951 * albedo + 0.6417;
    let cc = 2.7552 * albedo + 0.6903;
    return max(vec3<f32>(1.0), (a * ca + cb) * a + cc);
}

// A technique's two irradiance terms at a pixel as the image counts them: `env`, its far-field
// term (its env-irradiance), and `indirect`, the near light it adds (its indirect-irradiance);
// the image is ρ · (env + light + indirect).
struct Terms {
    env: vec3<f32>,
    indirect: vec3<f32>,
}

// The occlusion rule (1): the light at a receiver whose cosine-weighted visibility within R is v,
// where the volume's irradiance `far` holds visibility `far_ao`. GTAO's multi-bounce fit takes the
// occluders lit as the receiver by the same environment; the rule adds the lights for the share
// of the occlusion the volume holds (held_share: geometry the bake saw, lit where the receiver
// is), which sends ρ · light (the receiver's direct irradiance) back with the same bounces; the
// rest (an object the bake never saw, detail below the probes' spacing) is taken unlit:
//   E(a) = E_open · F(a) + h ρ · light · (1 − a) · bounces(a)
// with E_open, the light of the open directions, solved from E(far_ao) = far. Without lights
// E(v) / E(far_ao) = F(v) / F(far_ao). The rule only takes light away (v below far_ao, min with
// far).
fn occluded_light(v: f32, far_ao: f32, far: vec3<f32>, light: vec3<f32>, albedo: vec3<f32>) -> Terms {
    let a = min(v, far_ao);
    let lit = held_share(v, far_ao) * albedo * light;
    let held = bounces(far_ao, albedo);
    let open = max(vec3<f32>(0.0), far - lit * (1.0 - far_ao) * held) / max(far_ao * held, vec3<f32>(1e-3));
    let e = min(far, (open * a + lit * (1.0 - a)) * bounces(a, albedo));
    // Split as the image counts it: the open directions' light (far) and the rest (near).
    var t: Terms;
    t.env = min(e, open * a);
    t.indirect = e - t.env;
    return t;
}

// The share of the occlusion a technique finds (ao) that the far field already holds (its own
// visibility within R, far_ao): 1 where the technique finds none.
fn held_share(ao: f32, far_ao: f32) -> f32 {
    if ao >= 0.999 {
        return 1.0;
    }
    return clamp((1.0 - far_ao) / (1.0 - ao), 0.0, 1.0);
}

// Whether the frame counts the technique's light against a probe volume (`volume`: the frame has
// one, far.wgsl's far_volume), by `rule`.
fn counts(rule: u32, volume: bool) -> bool {
    return FAR_RULE == rule && volume;
}

// The technique's terms at `pixel`. Under the occlusion rule with a volume, E(v) splits into the
// light of the directions it finds open, E_open · v (the far part), and the rest, the light the
// occluders send back with the bounces between them and the receiver (near, with the share
// (1 − h) of the technique's own bounce).
fn technique_terms(env_irradiance: texture_2d<f32>, indirect_irradiance: texture_2d<f32>, ao: texture_2d<f32>, far_field: texture_2d<f32>, ao_only: bool, volume: bool, pixel: vec2<u32>, albedo: vec3<f32>, light: vec3<f32>) -> Terms {
    let far = textureLoad(far_field, pixel, 0);
    let a = textureLoad(ao, pixel, 0).r;
    var t: Terms;
    if ao_only {
        t.env = a * far.rgb;
        t.indirect = vec3<f32>(0.0);
    } else {
        t.env = textureLoad(env_irradiance, pixel, 0).rgb;
        t.indirect = textureLoad(indirect_irradiance, pixel, 0).rgb;
    }
    if counts(1u, volume) {
        let v = clamp(luminance(t.env) / max(luminance(far.rgb), 1e-12), 0.0, 1.0);
        let split = occluded_light(v, far.a, far.rgb, light, albedo);
        t.env = split.env;
        t.indirect = (1.0 - held_share(a, far.a)) * t.indirect + split.indirect;
    } else if counts(2u, volume) {
        // The technique's own light of the open directions is the far part; what the held share
        // takes back from the volume is its occluders' light, near.
        let h = held_share(a, far.a);
        let whole = mix(t.env, far.rgb, h);
        let open = min(t.env, whole);
        t.indirect = (1.0 - h) * t.indirect + (whole - open);
        t.env = open;
    }
    return t;
}

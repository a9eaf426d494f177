// ssdo.wgsl — screen-space ambient occlusion (`ssao`) and screen-space directional occlusion with
// one indirect bounce (`ssdo`). Sources: Ritschel, Grosch & Seidel 2009, "Approximating Dynamic
// Global Illumination in Image Space" (seed 003: Sec. 3 directional occlusion and indirect
// bounce, Sec. 4 light segments, M×N interleaved sample sets) and the SSDO chapter of seed 001
// (tangent frame, stratified elevation + golden-ratio azimuth, interleaved gradient noise, three
// "visible" conditions, visibility and radiance modes, environment at a blurred mip, bounce from
// the blurred direct radiance, distance clamp, falloff, strength).
//
// Entry points, in frame order: `direct` → (bilateral blur) → `resolve` → `bounce` → (blur).
// SSAO runs `direct` and `resolve` only; the two techniques share sample generation and the
// visibility test and differ in what they do with the samples.
//
// Deviations, and why:
// - Visibility test. The paper's rule — a sample point is an occluder when projecting it onto the
//   surface seen at its pixel moves it towards the viewer — is evaluated against that surface's
//   tangent plane (position and normal from the G-buffer) rather than its depth at the pixel
//   centre: the same verdict for curved surfaces at pixel scale, but exact on planes whatever the
//   view angle (no false occlusion on a flat floor at any radius).
// - Sample lengths: the paper draws λ ∈ [0, r_max] at random without naming the distribution;
//   we take λ = r_max·u^(1/3), points uniform in the hemisphere's volume. Uniform λ leaves most
//   points close to P and misses planar occluders a ray within R would meet (ao 0.78 instead of
//   0.56 at a tenth of R from a wall); volume-uniform points halve that gap.
// - The paper's smooth-step fade acts on the blocker's distance from P, from `fade`·R to R: where
//   the segment from P to the sample crosses the tangent plane of the surface seen (when P is in
//   front of that plane), else the distance to that surface point (so surfaces far in front of P,
//   whose pixels a sample may project onto, fade out instead of casting halos).
// - The bounce's sender cosine uses the direction from the sender to the receiver (the chapter's
//   listing dots the sender normal with receiver→sender, which rejects front-facing senders).

struct SsdoParams {
    // Hemisphere radius R (m).
    radius: f32,
    // Directions per pixel N.
    samples: u32,
    // 0 visibility mode, 1 radiance mode.
    mode: u32,
    // 0 ssao, 1 ssdo.
    technique: u32,
    // Mip of the box-filtered environment read per sample.
    lod: f32,
    // Exponent applied to the visibility (SSDO) or to 1 − scale·S (SSAO).
    contrast: f32,
    // SSAO's scale on the occlusion sum S.
    scale: f32,
    // Fraction of R where the occluder fade starts.
    fade: f32,
    // Bounce strength.
    strength: f32,
    // Smallest sender distance used in 1/d² (m).
    distance_clamp: f32,
    // 0 chapter pattern, 1 interleaved M×N sets (M = 4×4).
    pattern: u32,
    // Points on each light's segment (0: no screen-space light occlusion).
    light_samples: u32,
    // Depth layers of the main view (1..=4) and additional cameras (0..=4), passes/layers.rs.
    layers: u32,
    cameras: u32,
    // Light segment: 0 length R (Sec. 4 screen-space shadows), 1 the shadow map's bias
    // (Sec. 5 screen-space shadow correction).
    light_segment: u32,
    // Virtual point lights: 0 none; 1 ssdo-vpl, the environment is `vpl_count` directional
    // lights in the direct pass's light table (bindings 13..=16 then hold them, not the scene's
    // lights); 2 instant-radiosity, the bounce pass's light table holds `vpl_count` cosine
    // emitters (spot lights about their normals with colour Φ/π).
    vpl_mode: u32,
    vpl_count: u32,
    // instant-radiosity: smallest distance in a VPL's 1/d² (m).
    vpl_clamp: f32,
    // 1: the bounce pass gathers sender pixels (ssdo with bounce=on).
    near: u32,
    // Points tested per direction (ray marching, the first occluded decides); 1: the paper's
    // single point at λ.
    steps: u32,
}

@group(0) @binding(5) var<uniform> params: SsdoParams;
@group(0) @binding(10) var gb_albedo: texture_2d<f32>;
@group(0) @binding(11) var gb_emissive: texture_2d<f32>;
// `direct` outputs: a = (L_dir rgb: Σ (1/π) L_in V cos Δω, visibility after contrast);
// b = (cosine-weighted ao estimate, 0, 0, 1); light irradiance with screen-space light occlusion.
@group(0) @binding(20) var out_a: texture_storage_2d<rgba16float, write>;
@group(0) @binding(21) var out_b: texture_storage_2d<rgba16float, write>;
@group(0) @binding(22) var out_light_irradiance: texture_storage_2d<rgba16float, write>;
// `resolve`: blurred a and b → env_irradiance and ao.
@group(0) @binding(24) var in_a: texture_2d<f32>;
@group(0) @binding(25) var in_b: texture_2d<f32>;
@group(0) @binding(26) var out_env_irradiance: texture_storage_2d<rgba16float, write>;
@group(0) @binding(27) var out_ao: texture_storage_2d<r32float, write>;
// `bounce`: the resolved (blurred) direct irradiance of senders → raw indirect irradiance.
@group(0) @binding(28) var env_irradiance: texture_2d<f32>;
@group(0) @binding(29) var light_irradiance: texture_2d<f32>;
@group(0) @binding(30) var out_indirect: texture_storage_2d<rgba16float, write>;

fn sample_config() -> SampleConfig {
    return SampleConfig(params.samples, params.pattern, params.radius, params.fade, params.layers, params.cameras);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

@compute @workgroup_size(8, 8, 1)
fn direct(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let here = surface_at(pixel);
    if !here.valid {
        textureStore(out_a, pixel, vec4<f32>(0.0));
        textureStore(out_b, pixel, vec4<f32>(0.0));
        if params.technique == 1u && params.light_samples > 0u {
            textureStore(out_light_irradiance, pixel, vec4<f32>(0.0));
        }
        return;
    }
    let tb = tangent_frame(here.n);
    let n = params.samples;
    var ao_num = 0.0;
    var ao_den = 0.0;
    var total_light = 0.0;
    var visible_light = 0.0;
    var l_dir = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let s = sample_local(i, pixel, sample_config());
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let lambda = s.w * params.radius;
        let v = 1.0 - march_occlusion(here.p, omega, lambda, params.steps, sample_config()).amount;
        let cos_theta = max(s.z, 0.0);
        ao_num += v * cos_theta;
        ao_den += cos_theta;
        if params.technique == 1u {
            let l_in = env_radiance_at(omega, params.lod);
            let w = luminance(l_in) * cos_theta;
            total_light += w;
            visible_light += w * v;
            // (1/π) L_in V cos θ Δω with Δω = 2π/N.
            l_dir += l_in * (v * cos_theta * 2.0 / f32(n));
        }
    }
    let ao = select(1.0, ao_num / ao_den, ao_den > 0.0);
    var visibility: f32;
    if params.technique == 1u {
        let fraction = select(1.0, visible_light / total_light, total_light > 0.0);
        visibility = clamp(pow(fraction, params.contrast), 0.0, 1.0);
    } else {
        // SSAO: A = pow(max(0, 1 − scale·S), contrast), S the cosine-weighted occluded fraction.
        visibility = pow(max(0.0, 1.0 - params.scale * (1.0 - ao)), params.contrast);
    }
    textureStore(out_b, pixel, vec4<f32>(ao, 0.0, 0.0, 1.0));
    if params.vpl_mode == 1u {
        textureStore(out_a, pixel, vec4<f32>(vpl_environment(here), 1.0));
        return;
    }
    textureStore(out_a, pixel, vec4<f32>(l_dir, visibility));

    // Lights: points on a segment towards each light — of length R (paper Sec. 4) or the length
    // the shadow map's bias hides (light_segment=bias, Sec. 5 screen-space shadow correction);
    // the light is blocked as much as its most occluded point, on top of its shadow map.
    if params.technique == 1u && params.light_samples > 0u {
        var irradiance = vec3<f32>(0.0);
        for (var li = 0u; li < frame.counts.y; li++) {
            let l = lights[li];
            let inc = incident(l, here.p);
            let n_l = dot(here.n, inc.to_light);
            if n_l <= 0.0 {
                continue;
            }
            let shadowed = shadow_visibility(l, here.p, here.n);
            var blocked = 0.0;
            if shadowed > 0.0 {
                blocked = segment_blocked(here, l, inc.to_light);
            }
            irradiance += inc.irradiance * n_l * shadowed * (1.0 - blocked);
        }
        textureStore(out_light_irradiance, pixel, vec4<f32>(irradiance / PI, 1.0));
    }
}

// Amount of light towards `to_light` that the screen-space test finds blocked on the segment
// the shadow map's bias hides (paper Sec. 5, Fig. 8): the most occluded of `light_samples`
// points on P → P + b·l, or on P → P + R·l (Sec. 4) for light_segment 0.
fn segment_blocked(here: Surface, l: GpuLight, to_light: vec3<f32>) -> f32 {
    var seg_length = params.radius;
    if params.light_segment == 1u {
        seg_length = shadow_bias_length(l, here.p, here.n);
    }
    if u32(l.position.w) != 0u {
        seg_length = min(seg_length, distance(l.position.xyz, here.p));
    }
    var blocked = 0.0;
    for (var k = 0u; k < params.light_samples; k++) {
        let t = (f32(k) + 0.5) / f32(params.light_samples) * seg_length;
        blocked = max(blocked, occlusion(here.p, to_light, t, sample_config()).amount);
    }
    return blocked;
}

// ssdo-vpl (paper Sec. 5, Fig. 10): (1/π) Σ_k E_k max(0, n·ω_k) V_k with V_k the k-th
// environment light's shadow map, corrected in screen space on its bias segment.
fn vpl_environment(here: Surface) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < params.vpl_count; k++) {
        let l = lights[k];
        let to_light = -l.position.xyz;
        let n_l = dot(here.n, to_light);
        if n_l <= 0.0 {
            continue;
        }
        var v = shadow_visibility(l, here.p, here.n);
        if v > 0.0 && params.light_samples > 0u {
            v *= 1.0 - segment_blocked(here, l, to_light);
        }
        e += l.color.rgb * (n_l * v);
    }
    return e / PI;
}

@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    if nw.w == 0.0 {
        textureStore(out_env_irradiance, pixel, vec4<f32>(0.0));
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        return;
    }
    let a = textureLoad(in_a, pixel, 0);
    var env = a.w * env_irradiance_sh(normalize(nw.xyz));
    if params.technique == 1u && (params.mode == 1u || params.vpl_mode == 1u) {
        env = a.rgb;
    }
    textureStore(out_env_irradiance, pixel, vec4<f32>(env, 1.0));
    textureStore(out_ao, pixel, vec4<f32>(textureLoad(in_b, pixel, 0).r));
}

@compute @workgroup_size(8, 8, 1)
fn bounce(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(pixel) {
        return;
    }
    let here = surface_at(pixel);
    if !here.valid {
        textureStore(out_indirect, pixel, vec4<f32>(0.0));
        return;
    }
    var l_ind = vec3<f32>(0.0);
    if params.near == 1u {
        l_ind = screen_bounce(here, pixel);
    }
    if params.vpl_mode == 2u {
        l_ind += radiosity_bounce(here);
    }
    textureStore(out_indirect, pixel, vec4<f32>(l_ind, 1.0));
}

// One bounce from the sender patches (SSDO Sec. 3) in irradiance/π units. With Instant
// Radiosity (vpl_mode 2) the light that senders reflect of the scene's lights is already in
// the VPLs beyond `vpl_clamp`: it takes only what the VPLs' clamp removes
// (`clamp_remainder_transfer`); environment light and emission keep the full transfer. A
// peeled layer's or additional camera's radiance is not split by source and counts as light.
fn screen_bounce(here: Surface, pixel: vec2<u32>) -> vec3<f32> {
    let tb = tangent_frame(here.n);
    let n = params.samples;
    let radiosity = params.vpl_mode == 2u;
    // Sender patch area: the hemisphere's base disc split into N parts.
    let area = PI * params.radius * params.radius / f32(n);
    var l_ind = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let s = sample_local(i, pixel, sample_config());
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let occ = march_occlusion(here.p, omega, s.w * params.radius, params.steps, sample_config());
        if occ.amount <= 0.0 {
            continue;
        }
        let transfer = sender_transfer(here, occ.sender, area, params.radius, params.distance_clamp);
        var remainder = transfer;
        if radiosity {
            remainder = clamp_remainder_transfer(here, occ.sender, area, params.distance_clamp, params.vpl_clamp);
        }
        if transfer <= 0.0 && remainder <= 0.0 {
            continue;
        }
        var l_pixel: vec3<f32>;
        if occ.source == 0u {
            // Sender radiance: its blurred direct irradiance × albedo (Lambertian), plus emission.
            let albedo = textureLoad(gb_albedo, occ.pixel, 0).rgb;
            let from_env = albedo * textureLoad(env_irradiance, occ.pixel, 0).rgb + textureLoad(gb_emissive, occ.pixel, 0).rgb;
            let from_lights = albedo * textureLoad(light_irradiance, occ.pixel, 0).rgb;
            l_pixel = from_env * transfer + from_lights * remainder;
        } else {
            l_pixel = layer_sender_radiance(occ) * remainder;
        }
        l_ind += l_pixel * (params.strength * occ.amount);
    }
    return l_ind;
}

// Instant Radiosity (Keller 1997; SSDO paper Sec. 5, Fig. 11): (1/π) Σ_k (Φ_k/π) cos θ_k cos θ_x
// V_k / max(d², vpl_clamp²), V_k the k-th VPL's shadow map (PCF) corrected in screen space on
// its bias segment (`light_samples` points, as for the scene's lights). The clamp keeps the
// singularity of receivers near a VPL out of the image; screen_bounce adds back what it removes.
fn radiosity_bounce(here: Surface) -> vec3<f32> {
    let c2 = params.vpl_clamp * params.vpl_clamp;
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < params.vpl_count; k++) {
        let l = lights[k];
        let d = l.position.xyz - here.p;
        let dist2 = dot(d, d);
        if dist2 <= 0.0 {
            continue;
        }
        let dir = d * inverseSqrt(dist2);
        let cos_x = dot(here.n, dir);
        let cos_v = -dot(l.direction.xyz, dir);
        if cos_x <= 0.0 || cos_v <= 0.0 {
            continue;
        }
        var v = shadow_visibility(l, here.p, here.n);
        if v > 0.0 && params.light_samples > 0u {
            v *= 1.0 - segment_blocked(here, l, dir);
        }
        e += l.color.rgb * (cos_x * cos_v * v / max(dist2, c2));
    }
    return e / PI;
}

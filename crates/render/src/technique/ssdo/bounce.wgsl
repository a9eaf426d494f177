// bounce.wgsl — ssdo `bounce`: one indirect bounce from the sender patches (pixels that occlude
// a sample, SSDO Sec. 3; senders.wgsl) lit by the resolved direct irradiance, plus, for
// instant-radiosity, the virtual point lights of the reflective shadow maps. Raw
// indirect-irradiance, blurred after. Formulas and sources: technique/ssdo/mod.rs.

@group(1) @binding(0) var<uniform> params: SsdoParams;
@group(1) @binding(1) var<storage, read> sample_sets: array<vec4<f32>>;
@group(1) @binding(2) var gb_normal: texture_2d<f32>;
@group(1) @binding(3) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(4) var<storage, read> layer_views: array<LayerView>;
@group(1) @binding(5) var peel_normal: texture_2d_array<f32>;
@group(1) @binding(6) var peel_depth: texture_2d_array<f32>;
@group(1) @binding(7) var cam_normal: texture_2d_array<f32>;
@group(1) @binding(8) var cam_depth: texture_2d_array<f32>;
@group(1) @binding(9) var peel_radiance: texture_2d_array<f32>;
@group(1) @binding(10) var cam_radiance: texture_2d_array<f32>;
@group(1) @binding(11) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(12) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(13) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(14) var shadow_sampler: sampler_comparison;
@group(1) @binding(15) var gb_albedo: texture_2d<f32>;
@group(1) @binding(16) var gb_emissive: texture_2d<f32>;
// The resolved (blurred) direct irradiance of senders.
@group(1) @binding(17) var env_irradiance: texture_2d<f32>;
@group(1) @binding(18) var light_irradiance: texture_2d<f32>;
@group(1) @binding(19) var out_indirect: texture_storage_2d<rgba16float, write>;
@group(1) @binding(20) var shadow_depths: texture_2d_array<f32>;

// lights.wgsl's shadow_visibility of light l at world p with normal n, from this pass's shadow
// maps: the layer that sees p, its matrix, the frame's normal offset.
fn shadow_map_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let layer = shadow_layer(l, p);
    return shadow_visibility(shadow_maps, shadow_depths, shadow_sampler, frame.shadow_normal_offset, l, layer, shadow_clip_from_world[layer], p, n);
}

@compute @workgroup_size(8, 8, 1)
fn bounce(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let here = surface_at(view, gb_normal, gb_view_depth, pixel);
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
    let n = SAMPLES;
    let radiosity = params.vpl_mode == 2u;
    // Sender patch area: the hemisphere's base disc split into N parts.
    let area = PI * params.radius * params.radius / f32(n);
    var l_ind = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let s = sample_at(i, pixel, sample_config(params));
        let omega = normalize(tb.t * s.x + tb.b * s.y + here.n * s.z);
        let occ = march_occlusion(here.p, omega, s.w * params.radius, bounce_steps(STEPS, 1u, sample_config(params)), sample_config(params));
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
            l_pixel = layer_sender_radiance(peel_radiance, cam_radiance, occ) * remainder;
        }
        l_ind += l_pixel * (params.strength * occ.amount);
    }
    return l_ind;
}

// Instant Radiosity (Keller 1997; SSDO paper Sec. 5, Fig. 11): (1/π) Σ_k (Φ_k/π) cos θ_k cos θ_x
// V_k / max(d², vpl_clamp²), V_k the k-th VPL's shadow map (PCF) corrected in screen space on
// its bias segment (`light_samples` points, as for the scene's lights). The clamp keeps the
// singularity of receivers near a VPL out of the image; screen_bounce adds back what it removes.
// With a probe volume (far.wgsl) the lights' first bounce beyond R is the volume's (its bounces
// hold it): only the VPLs within R count, and of those the frame keeps the share of the occlusion
// the volume does not hold (the occlusion rule, passes/irradiance_terms.wgsl), so that no light
// is counted twice.
fn radiosity_bounce(here: Surface) -> vec3<f32> {
    let c2 = params.vpl_clamp * params.vpl_clamp;
    let reach2 = select(3.4e38, params.radius * params.radius, far_volume(far_probes));
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < params.vpl_count; k++) {
        let l = lights[k];
        let d = l.position - here.p;
        let dist2 = dot(d, d);
        if dist2 <= 0.0 || dist2 > reach2 {
            continue;
        }
        let dir = d * inverseSqrt(dist2);
        let cos_x = dot(here.n, dir);
        let cos_v = -dot(l.direction, dir);
        if cos_x <= 0.0 || cos_v <= 0.0 {
            continue;
        }
        var v = shadow_map_visibility(l, here.p, here.n);
        if v > 0.0 && params.light_samples > 0u {
            v *= 1.0 - segment_blocked(here, l, dir);
        }
        e += l.color * (cos_x * cos_v * v / max(dist2, c2));
    }
    return e / PI;
}

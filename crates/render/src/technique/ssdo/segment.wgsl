// segment.wgsl — the screen-space test of a segment towards a light (ssdo's Sec. 4 light
// occlusion and Sec. 5 shadow correction), shared by the `direct` and `bounce` passes. Needs
// samples.wgsl and lights.wgsl, and `params: SsdoParams` declared by the including pass.

fn sample_config() -> SampleConfig {
    return SampleConfig(SAMPLES, params.pattern, params.radius, params.fade, params.layers, params.cameras);
}

// Amount of light towards `to_light` that the screen-space test finds blocked on the segment
// the shadow map's bias hides (paper Sec. 5, Fig. 8): the most occluded of `light_samples`
// points on P → P + b·l, or on P → P + R·l (Sec. 4) for light_segment 0.
fn segment_blocked(here: Surface, l: GpuLight, to_light: vec3<f32>) -> f32 {
    var seg_length = params.radius;
    if params.light_segment == 1u {
        seg_length = shadow_bias_length(l, here.p, here.n);
    }
    if u32(l.kind) != 0u {
        seg_length = min(seg_length, distance(l.position, here.p));
    }
    var blocked = 0.0;
    for (var k = 0u; k < params.light_samples; k++) {
        let t = (f32(k) + 0.5) / f32(params.light_samples) * seg_length;
        blocked = max(blocked, occlusion(here.p, to_light, t, sample_config()).amount);
    }
    return blocked;
}

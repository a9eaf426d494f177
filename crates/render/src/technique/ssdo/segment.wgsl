// segment.wgsl — the screen-space test of a segment towards a light (ssdo's Sec. 4 light
// occlusion and Sec. 5 shadow correction), shared by the `direct` and `bounce` passes, a library
// (after samples.wgsl, lights.wgsl and params.wgsl). It declares no bindings: its functions take
// the pass's `SsdoParams` (and the frame's shadow normal offset). The test itself,
// `segment_blocked(here, l, to_light) -> f32`, runs samples.wgsl's blocker test over the pass's
// views (`occlusion`), which loops over a storage array: it is glue in both passes, written the
// same in each: the amount of light towards `to_light` that the screen-space test finds blocked
// on the segment the shadow map's bias hides (paper Sec. 5, Fig. 8), the most occluded of
// `light_samples` points (k + ½)/light_samples · segment_length on P → P + b·l, or on P → P + R·l
// (Sec. 4) for light_segment 0.

fn sample_config(p: SsdoParams) -> SampleConfig {
    return SampleConfig(SAMPLES, p.pattern, p.radius, p.fade, p.layers, p.cameras);
}

// Length of the segment towards light l that segment_blocked tests from `here`: R
// (light_segment 0) or the shadow map's bias length (shadow_bias_length, with the frame's
// `normal_offset` in shadow-map texels), at most the distance to a point or spot light.
fn segment_length(p: SsdoParams, normal_offset: f32, here: Surface, l: GpuLight) -> f32 {
    var seg_length = p.radius;
    if p.light_segment == 1u {
        seg_length = shadow_bias_length(normal_offset, l, here.p, here.n);
    }
    if u32(l.kind) != 0u {
        seg_length = min(seg_length, distance(l.position, here.p));
    }
    return seg_length;
}

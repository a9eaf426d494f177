// segment_glue.wgsl — glue shared by ssdo `direct` and `bounce`: segment.wgsl's test of the
// segment towards a light, run with the pass's occlusion (layers_glue.wgsl). It declares no
// bindings; it reads the pass's `params` (SsdoParams) and group 0's `frame`.

// The occlusion of the segment from `here` towards light l (the direction `to_light`).
fn segment_blocked(here: Surface, l: GpuLight, to_light: vec3<f32>) -> f32 {
    let seg_length = segment_length(params, frame.shadow_normal_offset, here, l);
    var blocked = 0.0;
    for (var k = 0u; k < params.light_samples; k++) {
        let t = (f32(k) + 0.5) / f32(params.light_samples) * seg_length;
        blocked = max(blocked, occlusion(here.p, to_light, t, sample_config(params)).amount);
    }
    return blocked;
}

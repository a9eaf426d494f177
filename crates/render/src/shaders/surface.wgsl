// surface.wgsl — the G-buffer surface at a pixel: world position and unit normal. A pass that
// includes it declares, in its group 1: gb_normal: texture_2d<f32> (rgba16float, xyz world
// normal, w = 0 on background) and gb_view_depth: texture_2d<f32> (r32float, m).

struct Surface {
    p: vec3<f32>,
    n: vec3<f32>,
    valid: bool,
}

fn surface_at(pixel: vec2<u32>) -> Surface {
    var s: Surface;
    let nw = textureLoad(gb_normal, pixel, 0);
    s.valid = nw.w != 0.0;
    s.n = normalize(nw.xyz);
    s.p = world_position(pixel, textureLoad(gb_view_depth, pixel, 0).r);
    return s;
}

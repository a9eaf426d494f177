// surface.wgsl — the G-buffer surface at a pixel: world position and unit normal, a library (after
// common.wgsl). It declares no bindings: surface_at takes the view and the two G-buffer targets it
// reads, `normal`: texture_2d<f32> (rgba16float, xyz world normal, w = 0 on background) and
// `depth`: texture_2d<f32> (r32float, view depth in m); a pass passes its gb_normal and
// gb_view_depth.

struct Surface {
    p: vec3<f32>,
    n: vec3<f32>,
    valid: bool,
}

fn surface_at(cam: View, normal: texture_2d<f32>, depth: texture_2d<f32>, pixel: vec2<u32>) -> Surface {
    var s: Surface;
    let nw = textureLoad(normal, pixel, 0);
    s.valid = nw.w != 0.0;
    s.n = normalize(nw.xyz);
    s.p = world_position(cam, pixel, textureLoad(depth, pixel, 0).r);
    return s;
}

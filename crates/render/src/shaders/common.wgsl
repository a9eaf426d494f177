// common.wgsl — a library prepended to every screen-space and G-buffer shader: the `View` and
// `Frame` structs and view-space helpers. It declares no bindings; each helper takes the `View`
// it reads as its first parameter (nearfield binds its own in group 0,
// shaders/frame_bindings.wgsl; a host binds its own the same way: docs/src/architecture.md).
//
// `View` and `Frame` mirror `crate::frame::ViewUniforms` and `FrameUniforms` field for field (a
// naga layout test checks the offsets). Conventions (docs/src/conventions.md): right-handed world, +Y up, view space looks
// down −Z, pixel centres at (x + 0.5, y + 0.5) with row 0 at the top, wgpu clip depth 0..1.

// The view the near-field kernels read (crate::frame::ViewUniforms): the camera of this and
// last frame, the image, the frame's index and seed. Nothing of exposure, tone mapping, AOVs or
// lights.
struct View {
    clip_from_world: mat4x4<f32>,
    world_from_clip: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    world_from_view: mat4x4<f32>,
    // Last frame's camera, for motion vectors and reprojection.
    prev_clip_from_world: mat4x4<f32>,
    prev_view_from_world: mat4x4<f32>,
    prev_world_from_view: mat4x4<f32>,
    // xyz: camera position (world); w: unused.
    camera_position: vec4<f32>,
    // width, height (pixels) and their inverses.
    size: vec2<f32>,
    inv_size: vec2<f32>,
    // Near and far plane (m), aspect (w/h), tan(yfov / 2).
    near: f32,
    far: f32,
    aspect: f32,
    tan_half_fov: f32,
    // Last frame's near, far, aspect, tan(yfov / 2).
    prev_near: f32,
    prev_far: f32,
    prev_aspect: f32,
    prev_tan_half_fov: f32,
    // Frame index and noise seed.
    frame_index: u32,
    seed: u32,
    // 1 when last frame's buffers may be reused (0 on the first frame and after a camera cut);
    // frames since the last cut.
    history_valid: u32,
    frames_since_cut: u32,
}

// The rest of nearfield's own frame (crate::frame::FrameUniforms), read by nearfield's own
// passes (lighting, tone mapping) and by the techniques that shade with the light
// table (ssdo, s3ho): nothing a horizon kernel reads.
struct Frame {
    // Exposure (EV), tonemap operator (0 aces, 1 neutral, 2 linear), shadow normal offset (in
    // shadow-map texels).
    exposure: f32,
    tonemap: u32,
    shadow_normal_offset: f32,
    // Lights in the light table.
    light_count: u32,
}

// One view of the extra layers (passes/layers/, `LayerView` there): a peeled depth layer of the
// main camera or an additional camera. 256 bytes, so that one buffer serves as a storage array and
// as a uniform with dynamic offsets.
struct LayerView {
    clip_from_world: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    world_from_view: mat4x4<f32>,
    // Width, height (pixels) and their inverses.
    size: vec2<f32>,
    inv_size: vec2<f32>,
    // Near and far plane (m), aspect, tan(yfov / 2).
    near: f32,
    far: f32,
    aspect: f32,
    tan_half_fov: f32,
    // 1: peel against the layer before.
    peel: u32,
    // 1: an exit layer (normal stored facing away from the camera).
    exit: u32,
    // 1: a single-sided back face behind the G-buffer's layer (which culls them) is never that
    // layer re-rasterized: the peel keeps it however close it lies (peel.wgsl).
    after_front: u32,
    _pad1: u32,
    _pad2: vec4<f32>,
}

// World position of `pixel` at view depth `depth` in layer view `v`.
fn layer_position(v: LayerView, pixel: vec2<u32>, depth: f32) -> vec3<f32> {
    let p = (vec2<f32>(pixel) + 0.5) * v.inv_size;
    let ndc = vec2<f32>(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y);
    let t = v.tan_half_fov;
    let pv = vec3<f32>(ndc.x * t * v.aspect, ndc.y * t, -1.0) * depth;
    return (v.world_from_view * vec4<f32>(pv, 1.0)).xyz;
}

const PI: f32 = 3.14159265358979;

// View-space position of pixel `pixel` (integer coordinates) at view depth `view_depth` (> 0, m).
fn view_position(cam: View, pixel: vec2<u32>, view_depth: f32) -> vec3<f32> {
    let p = (vec2<f32>(pixel) + 0.5) * cam.inv_size;
    let ndc = vec2<f32>(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y);
    let t = cam.tan_half_fov;
    return vec3<f32>(ndc.x * t * cam.aspect, ndc.y * t, -1.0) * view_depth;
}

// Last frame's view-space position of pixel `pixel` at view depth `view_depth`.
fn prev_view_position(cam: View, pixel: vec2<u32>, view_depth: f32) -> vec3<f32> {
    let p = (vec2<f32>(pixel) + 0.5) * cam.inv_size;
    let ndc = vec2<f32>(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y);
    let t = cam.prev_tan_half_fov;
    return vec3<f32>(ndc.x * t * cam.prev_aspect, ndc.y * t, -1.0) * view_depth;
}

// Pixel coordinates (continuous, centres at +0.5) of world point `p` through `clip_from_world`.
fn to_screen(cam: View, clip_from_world: mat4x4<f32>, p: vec3<f32>) -> vec2<f32> {
    let c = clip_from_world * vec4<f32>(p, 1.0);
    let ndc = c.xy / c.w;
    return vec2<f32>(0.5 * ndc.x + 0.5, 0.5 - 0.5 * ndc.y) * cam.size;
}

fn world_position(cam: View, pixel: vec2<u32>, view_depth: f32) -> vec3<f32> {
    return (cam.world_from_view * vec4<f32>(view_position(cam, pixel, view_depth), 1.0)).xyz;
}

// Unit world direction from the camera through the centre of `pixel`.
fn view_ray(cam: View, pixel: vec2<u32>) -> vec3<f32> {
    return normalize((cam.world_from_view * vec4<f32>(view_position(cam, pixel, 1.0), 0.0)).xyz);
}

fn in_bounds(cam: View, pixel: vec2<u32>) -> bool {
    return f32(pixel.x) < cam.size.x && f32(pixel.y) < cam.size.y;
}

// The side of one pixel, in metres, at view depth `depth`.
fn pixel_footprint(cam: View, depth: f32) -> f32 {
    return depth * 2.0 * cam.tan_half_fov * cam.inv_size.y;
}

// Whether `p` (a point last frame saw, with normal `pn`) is the surface point `x` (normal `n`,
// view depth `depth`) this frame sees, or close enough to it to stand in for it: within
// `max_plane` × depth of x's tangent plane, normals within acos(`min_cos`), and no farther from
// x along the surface than 2.5 pixel footprints (stretched by 1/cos of the viewing angle, at
// most 10×). The last test tells a neighbouring pixel of the same plane from a point of that
// plane far behind a silhouette.
fn same_surface(cam: View, x: vec3<f32>, n: vec3<f32>, depth: f32, p: vec3<f32>, pn: vec3<f32>, max_plane: f32, min_cos: f32) -> bool {
    if abs(dot(p - x, n)) > max_plane * depth || dot(pn, n) < min_cos {
        return false;
    }
    let footprint = pixel_footprint(cam, depth);
    let facing = max(abs(dot(n, normalize(cam.camera_position.xyz - x))), 0.1);
    let d = p - x;
    let reach = 2.5 * footprint / facing;
    return dot(d, d) <= reach * reach;
}

// Last frame's bilinear taps around `prev` (continuous pixel position, centres at +0.5) that show
// the surface point x (normal n, view depth `depth`) by `same_surface`, rebuilt from
// `prev_geometry` (xyz normal, w view depth) and last frame's camera: the top-left tap and the
// four bilinear weights, 0 for a rejected tap (tap k sits at base + tap_offset(k)).
struct HistoryTaps {
    base: vec2<i32>,
    weights: vec4<f32>,
    total: f32,
}

fn tap_offset(k: u32) -> vec2<i32> {
    return vec2<i32>(i32(k % 2u), i32(k / 2u));
}

fn history_taps(cam: View, prev_geometry: texture_2d<f32>, prev: vec2<f32>, x: vec3<f32>, n: vec3<f32>, depth: f32, max_plane: f32, min_cos: f32) -> HistoryTaps {
    var t: HistoryTaps;
    let p = prev - 0.5;
    t.base = vec2<i32>(floor(p));
    let f = p - floor(p);
    t.total = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let o = tap_offset(k);
        let q = t.base + o;
        t.weights[k] = 0.0;
        // A tap of bilinear weight below 1e-3 is not fetched (it would move the mean by less than
        // that; a still camera lands on pixel centres, where three of the four weigh ~0).
        let w = select(1.0 - f.x, f.x, o.x == 1) * select(1.0 - f.y, f.y, o.y == 1);
        if w < 1e-3 || any(q < vec2<i32>(0)) || any(q >= vec2<i32>(cam.size)) {
            continue;
        }
        let g = textureLoad(prev_geometry, q, 0);
        if g.w <= 0.0 {
            continue;
        }
        let pw = (cam.prev_world_from_view * vec4<f32>(prev_view_position(cam, vec2<u32>(q), g.w), 1.0)).xyz;
        if !same_surface(cam, x, n, depth, pw, g.xyz, max_plane, min_cos) {
            continue;
        }
        t.weights[k] = w;
        t.total += w;
    }
    return t;
}

// Rec. 709 luminance of a linear RGB colour.
fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// slice.wgsl — what the slice marches of gtao/hbil (search.wgsl) and vbgi (vbgi/bitmask.wgsl)
// share: layer texels, the point on the slice line, the slice integral G.
// Derivations and sources: technique/horizon/mod.rs. The including kernel declares `params`
// (HorizonParams), `in_depth` and `in_normal`.

// Normal (xyz) and view depth (w) of a layer texel.
fn geometry(q: vec2<i32>, layer: u32) -> vec4<f32> {
    let g = textureLoad(in_normal, q, layer, 0);
    if params.scale == 1u {
        return vec4<f32>(g.xyz, select(0.0, textureLoad(in_depth, q, layer, 0).r, g.w != 0.0));
    }
    return g;
}

fn layer_pixel(texel: vec2<u32>, layer: u32) -> vec2<u32> {
    return texel * params.scale + vec2<u32>(layer % params.scale, layer / params.scale);
}

// The surface point seen through layer position `pos` (continuous texel coordinates), taken on
// the tangent plane (point `centre`, normal `n`) of the texel it falls in;
// w = 0 when the ray through `pos` misses that plane (it passes above a horizon line: the texel
// centre is not what the slice sees there, and the sample is skipped).
fn on_slice_line(pos: vec2<f32>, layer: u32, centre: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let r = to_world(view_dir(layer_to_full(pos, layer)));
    let eye = view.camera_position.xyz;
    let denom = dot(n, r);
    let along = dot(n, centre - eye) / denom;
    if abs(denom) < 1e-4 * length(r) || along <= 0.0 {
        return vec4<f32>(centre, 0.0);
    }
    return vec4<f32>(eye + r * along, 1.0);
}

// ½ nx (θ − sin θ cos θ) + ½ ny sin² θ.
fn slice_g(theta: f32, n: vec2<f32>) -> f32 {
    let s = sin(theta);
    let c = cos(theta);
    return 0.5 * n.x * (theta - s * c) + 0.5 * n.y * s * s;
}

// The local camera frame at x (technique/horizon/mod.rs): ω_o towards the eye,
// ω_x = normalize(Y × ω_o) with Y the camera's up vector, ω_y = ω_o × ω_x.
struct LocalFrame {
    o: vec3<f32>,
    x: vec3<f32>,
    y: vec3<f32>,
}

fn local_frame(x: vec3<f32>) -> LocalFrame {
    var f: LocalFrame;
    f.o = normalize(view.camera_position.xyz - x);
    let up = normalize(view.world_from_view[1].xyz);
    var ox = cross(up, f.o);
    if dot(ox, ox) < 1e-8 {
        ox = normalize(view.world_from_view[0].xyz);
    }
    f.x = normalize(ox);
    f.y = cross(f.o, f.x);
    return f;
}

// Screen length of R at view depth `depth` in layer texels, as if the occluder were up to R
// nearer the camera (capped by `max_pixels` at full resolution).
fn march_reach(depth: f32) -> f32 {
    let focal = 0.5 * view.size.y / view.tan_half_fov;
    let r_px = min(params.max_pixels, params.radius * focal / max(depth - params.radius, 0.2 * depth));
    return r_px / f32(params.scale);
}

// Unit screen direction (pixels) of slice direction `d` at x (x_screen: x on screen).
fn slice_screen_dir(x: vec3<f32>, x_screen: vec2<f32>, d: vec3<f32>, depth: f32) -> vec2<f32> {
    var dir = to_screen(view.clip_from_world, x + d * (0.01 * depth)) - x_screen;
    if dot(dir, dir) < 1e-12 {
        dir = vec2<f32>(1.0, 0.0);
    }
    return normalize(dir);
}

// View-space forms of the above (the horizon search works in view space: the eye at the origin,
// looking down −Z, +Y up; positions from depth and directions through pixels need no matrix).

// A world direction in view space, and back.
fn to_view(v: vec3<f32>) -> vec3<f32> {
    return (view.view_from_world * vec4<f32>(v, 0.0)).xyz;
}

fn to_world(v: vec3<f32>) -> vec3<f32> {
    return (view.world_from_view * vec4<f32>(v, 0.0)).xyz;
}

// The view-space direction (z = −1) through full-resolution position `full` (pixel units).
fn view_dir(full: vec2<f32>) -> vec3<f32> {
    let uv = full * view.inv_size;
    let t = view.tan_half_fov;
    return vec3<f32>((2.0 * uv.x - 1.0) * t * view.aspect, (1.0 - 2.0 * uv.y) * t, -1.0);
}

// Full-resolution position of layer position `pos` (continuous texel coordinates).
fn layer_to_full(pos: vec2<f32>, layer: u32) -> vec2<f32> {
    let scale = f32(params.scale);
    return (pos - 0.5) * scale + vec2<f32>(f32(layer % params.scale), f32(layer / params.scale)) + 0.5;
}

// on_slice_line in view space: the point seen through layer position `pos` on the tangent plane
// (point `centre`, normal `n`, both view space) of the texel it falls in; w = 0 on a miss.
fn view_on_slice_line(pos: vec2<f32>, layer: u32, centre: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let r = view_dir(layer_to_full(pos, layer));
    let denom = dot(n, r);
    let along = dot(n, centre) / denom;
    if abs(denom) < 1e-4 * length(r) || along <= 0.0 {
        return vec4<f32>(centre, 0.0);
    }
    return vec4<f32>(r * along, 1.0);
}

// local_frame at view-space x: ω_o towards the eye, ω_x = normalize(Y × ω_o), ω_y = ω_o × ω_x.
fn view_local_frame(x: vec3<f32>) -> LocalFrame {
    var f: LocalFrame;
    f.o = normalize(-x);
    var ox = vec3<f32>(f.o.z, 0.0, -f.o.x);
    if dot(ox, ox) < 1e-8 {
        ox = vec3<f32>(1.0, 0.0, 0.0);
    }
    f.x = normalize(ox);
    f.y = cross(f.o, f.x);
    return f;
}

// Unit screen direction (pixels, rows down) of view-space direction `d` at view-space x: the
// derivative of the projection along d (d ⟂ ω_o, so it never vanishes).
fn view_screen_dir(x: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let dir = vec2<f32>(x.x * d.z - d.x * x.z, d.y * x.z - x.y * d.z);
    if dot(dir, dir) < 1e-20 {
        return vec2<f32>(1.0, 0.0);
    }
    return normalize(dir);
}

// ½ (θ − sin θ cos θ) and ½ sin² θ: G(θ) for n′ = (1, 0) and (0, 1), so that
// G(θ, n′) = n′ · slice_gxy(θ) (one sin and cos for every n′).
fn slice_gxy(theta: f32) -> vec2<f32> {
    let s = sin(theta);
    let c = cos(theta);
    return vec2<f32>(0.5 * (theta - s * c), 0.5 * s * s);
}

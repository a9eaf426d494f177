// slice.wgsl — what the slice marches of gtao/hbil (search.wgsl) and vbgi (vbgi/bitmask.wgsl)
// share: the invocation's pixel, layer texels, the point on the slice line, the slice integral
// G. A library (after common.wgsl, params.wgsl and half.wgsl): it declares no bindings; its
// functions take the view (`cam`), the pass's `HorizonParams` (`p`) and the layer textures they
// read (`depth_layers`, `normal_layers`: search.wgsl's `in_depth` and `in_normal`, described
// there).
// The derivations sit beside the functions that compute them; sources: technique/horizon/mod.rs.

// What one invocation of a slice march (search.wgsl's `horizon`, vbgi's `bitmask`) works on:
// the pixel it searches, where its results go, its layer texel and layer, and the position that
// picks its slice angles and step jitter. The layers are stacked vertically in one 2D dispatch
// (rows of workgroups [l·G, (l+1)·G) with G = ⌈layer height / 8⌉ serve layer l; without
// interleaving there is one full-size layer). With HALF (`resolution=half`, half.wgsl, which the
// kernel includes too) there is one invocation per 2×2 block, at its pixel of this frame, read
// from the full-resolution G-buffer; the results go to the block's texel, and the angles follow
// the block grid so that neighbouring blocks take different ones. `valid` is false for an
// invocation past the image.
struct MarchAt {
    pixel: vec2<u32>,
    store_at: vec2<u32>,
    texel: vec2<u32>,
    layer: u32,
    pattern: vec2<u32>,
    valid: bool,
}

fn march_at(cam: View, p: HorizonParams, id: vec2<u32>) -> MarchAt {
    var m: MarchAt;
    if HALF {
        m.store_at = id;
        m.pixel = half_pixel(cam, min(id, half_size(cam) - 1u));
        m.texel = m.pixel;
        m.pattern = id;
        m.valid = all(id < half_size(cam));
        return m;
    }
    let rows = ((p.layer_height + 7u) / 8u) * 8u;
    m.texel = vec2<u32>(id.x, id.y % rows);
    m.layer = id.y / rows;
    m.pixel = layer_pixel(p, m.texel, m.layer);
    m.store_at = m.pixel;
    m.pattern = m.pixel;
    m.valid = m.texel.x < p.layer_width && m.texel.y < p.layer_height && in_bounds(cam, m.pixel);
    return m;
}

// Normal (xyz) and view depth (w) of a layer texel.
fn geometry(depth_layers: texture_2d_array<f32>, normal_layers: texture_2d_array<f32>, p: HorizonParams, q: vec2<i32>, layer: u32) -> vec4<f32> {
    let g = textureLoad(normal_layers, q, layer, 0);
    if p.scale == 1u {
        return vec4<f32>(g.xyz, select(0.0, textureLoad(depth_layers, q, layer, 0).r, g.w != 0.0));
    }
    return g;
}

fn layer_pixel(p: HorizonParams, texel: vec2<u32>, layer: u32) -> vec2<u32> {
    return texel * p.scale + vec2<u32>(layer % p.scale, layer / p.scale);
}

// The surface point seen through layer position `pos` (continuous texel coordinates), taken on
// the tangent plane (point `centre`, normal `n`) of the texel it falls in;
// w = 0 when the ray through `pos` misses that plane (it passes above a horizon line: the texel
// centre is not what the slice sees there, and the sample is skipped).
fn on_slice_line(cam: View, p: HorizonParams, pos: vec2<f32>, layer: u32, centre: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let r = to_world(cam, view_dir(cam, layer_to_full(p, pos, layer)));
    let eye = cam.camera_position.xyz;
    let denom = dot(n, r);
    let along = dot(n, centre - eye) / denom;
    if abs(denom) < 1e-4 * length(r) || along <= 0.0 {
        return vec4<f32>(centre, 0.0);
    }
    return vec4<f32>(eye + r * along, 1.0);
}

// The projected normal n′ = (n·d, n·ω_o) of slice direction `d`, in world or view space alike.
// Horizons are initialised from the normal (Sec. 2.1): with the projected normal
// n′ = (n·D, n·ω_o) at slice angle γ = atan2(n′x, n′y), θ_front = γ + π/2 and θ_back = γ − π/2,
// so they never fall below the tangent plane. A shading normal may face away from the eye (a
// normal map's, or one interpolated across a silhouette: n·ω_o < 0). Its hemisphere then
// reaches past the slice's half circle θ ∈ [−π, π]: the initial horizons cross (θ_back > 0),
// the open hemisphere's weight U (below) can vanish or turn negative while the visible arcs'
// weights do not, and the ratio estimators blow up (hbil with one slice wrote irradiance of
// 8000 on Crytek Sponza's normal-mapped arcade). Such a normal is taken at the eye's horizon,
// n′y = max(n·ω_o, 0) in every slice, which is the normal with its ω_o part removed (the
// common length cancels in every ratio below): γ ∈ [−π/2, π/2], both horizons stay on their
// sides, and every weight is ≥ 0. XeGTAO clamps the projected normal's angle the same way.
fn projected_normal(n: vec3<f32>, d: vec3<f32>, omega_o: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(dot(n, d), max(dot(n, omega_o), 0.0));
}

// Slice integrals. For one slice with horizons θ0 ≤ 0 ≤ θ1 and n′ = (nx, ny) (unnormalised, so
// that slices weigh by the projected normal's length as in GTAO), every quantity is an integral
// ∫ f(θ) |sin θ| dθ over [θ0, θ1], and with
//     G(θ) = ½ nx (θ − sin θ cos θ) + ½ ny sin² θ
// (one antiderivative serves both sides because θ − sin θ cos θ is odd and sin² θ even):
//   AO_i   = G(θ1) + G(θ0)                                            (HBIL Eq. 10–11)
//   ñ′     = (Gx(θ1) + Gx(θ0), Gy(θ1) + Gy(θ0)),  Gx: n′ = (1, 0), Gy: n′ = (0, 1)   (Eq. 4–6)
//   ΔE     = L_d(x′) (G(θ_old) − G(θ_new)) when a sample raises a horizon from θ_old to θ_new
//                                                                       (Eq. 18, both sides)
// Deviation: the paper prints Eq. 6 and Eq. 11 as ½ nx [θ1 − θ0 + sin θ0 cos θ0 − sin θ1 cos θ1];
// with θ0 ≤ 0 that is not the integral of sin θ |sin θ| (it gives ñx = π/2 for the symmetric
// horizons ±π/2, where the true value is 0); the G form above is the exact integral and agrees
// with Jimenez et al.'s per-side â(h).
fn slice_g(theta: f32, n: vec2<f32>) -> f32 {
    return slice_g_at(theta, vec2<f32>(cos(theta), sin(theta)), n);
}

// slice_g with cs = (cos θ, sin θ) already known (a march that steps θ by rotation).
fn slice_g_at(theta: f32, cs: vec2<f32>, n: vec2<f32>) -> f32 {
    return 0.5 * n.x * (theta - cs.y * cs.x) + 0.5 * n.y * cs.y * cs.y;
}

// (cos, sin) of α + β from c = (cos α, sin α) and r = (cos β, sin β).
fn rotate_angle(c: vec2<f32>, r: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(c.x * r.x - c.y * r.y, c.y * r.x + c.x * r.y);
}

// Horizon search (HBIL Sec. 1.1–1.3, 2.1). At the surface point x (normal n) the local camera
// frame is ω_o = normalize(eye − x), ω_x = normalize(Y × ω_o) with Y the camera's up vector,
// ω_y = ω_o × ω_x. Slice φ has the tangent direction D(φ) = cos φ ω_x + sin φ ω_y; the plane
// spanned by ω_o and D contains the eye, so it projects to a straight screen line through x,
// which is marched both ways. A sample s on it lies in the slice (up to the snap to a texel
// centre, removed by projecting s − x onto the slice plane), and its angle from ω_o is
// exactly cos θ = (s − x)·ω_o / |s − x| — the local-camera horizon angle that Sec. 1.3 obtains
// from the camera-space angle β by cos θ = (cos α z + sin α r)/√(r² + z²); computing it from the
// vector in the local frame is the same correction without the intermediate angles.
struct LocalFrame {
    o: vec3<f32>,
    x: vec3<f32>,
    y: vec3<f32>,
}

fn local_frame(cam: View, x: vec3<f32>) -> LocalFrame {
    var f: LocalFrame;
    f.o = normalize(cam.camera_position.xyz - x);
    let up = normalize(cam.world_from_view[1].xyz);
    var ox = cross(up, f.o);
    if dot(ox, ox) < 1e-8 {
        ox = normalize(cam.world_from_view[0].xyz);
    }
    f.x = normalize(ox);
    f.y = cross(f.o, f.x);
    return f;
}

// Screen length of R at view depth `depth` in layer texels, as if the occluder were up to R
// nearer the camera (capped by `max_pixels` at full resolution).
fn march_reach(cam: View, p: HorizonParams, depth: f32) -> f32 {
    let focal = 0.5 * cam.size.y / cam.tan_half_fov;
    let r_px = min(p.max_pixels, p.radius * focal / max(depth - p.radius, 0.2 * depth));
    return r_px / f32(p.scale);
}

// Unit screen direction (pixels) of slice direction `d` at x (x_screen: x on screen).
fn slice_screen_dir(cam: View, x: vec3<f32>, x_screen: vec2<f32>, d: vec3<f32>, depth: f32) -> vec2<f32> {
    var dir = to_screen(cam, cam.clip_from_world, x + d * (0.01 * depth)) - x_screen;
    if dot(dir, dir) < 1e-12 {
        dir = vec2<f32>(1.0, 0.0);
    }
    return normalize(dir);
}

// View-space forms of the above (the horizon search works in view space: the eye at the origin,
// looking down −Z, +Y up; positions from depth and directions through pixels need no matrix).

// A world direction in view space, and back.
fn to_view(cam: View, v: vec3<f32>) -> vec3<f32> {
    return (cam.view_from_world * vec4<f32>(v, 0.0)).xyz;
}

fn to_world(cam: View, v: vec3<f32>) -> vec3<f32> {
    return (cam.world_from_view * vec4<f32>(v, 0.0)).xyz;
}

// The view-space direction (z = −1) through full-resolution position `full` (pixel units).
fn view_dir(cam: View, full: vec2<f32>) -> vec3<f32> {
    let uv = full * cam.inv_size;
    let t = cam.tan_half_fov;
    return vec3<f32>((2.0 * uv.x - 1.0) * t * cam.aspect, (1.0 - 2.0 * uv.y) * t, -1.0);
}

// Full-resolution position of layer position `pos` (continuous texel coordinates).
fn layer_to_full(p: HorizonParams, pos: vec2<f32>, layer: u32) -> vec2<f32> {
    let scale = f32(p.scale);
    return (pos - 0.5) * scale + vec2<f32>(f32(layer % p.scale), f32(layer / p.scale)) + 0.5;
}

// on_slice_line in view space: the point seen through layer position `pos` on the tangent plane
// (point `centre`, normal `n`, both view space) of the texel it falls in; w = 0 on a miss.
fn view_on_slice_line(cam: View, p: HorizonParams, pos: vec2<f32>, layer: u32, centre: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let r = view_dir(cam, layer_to_full(p, pos, layer));
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

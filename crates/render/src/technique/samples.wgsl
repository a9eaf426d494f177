// samples.wgsl — hemisphere samples and the screen-space visibility test shared by the
// sampling techniques (ssao, ssdo, s3ho, ssbn), so that they differ only in what they do with the
// samples, a library (after common.wgsl and shaders/surface.wgsl). Sources and deviations: see
// technique/ssdo/mod.rs, whose header documents the test. The interleaved sample sets come from
// samples.rs beside this file.
//
// It declares no bindings: its functions take the view (`cam: View`), the textures and the
// elements of the storage arrays they read. A pass that uses them declares, in its group 1:
//   sample_sets: array<vec4<f32>> (storage, read) — the interleaved pattern: 16 sets × N samples
//     (xyz unit direction in the tangent frame, z up; w: λ/R in (0, 1]); sample_local takes the
//     entry sample_sets[sample_set_index(i, pixel, cfg)];
//   gb_normal, gb_view_depth (as shaders/surface.wgsl);
//   layer_views: array<LayerView> (storage, read) — extra layers (passes/layers/): views 0..2 =
//     peeled layers 2..4 of the main camera, views 3..6 = additional cameras; camera_verdict
//     takes camera c's, layer_views[CAMERA_VIEW_BASE + c];
//   peel_normal, peel_depth, cam_normal, cam_depth: texture_2d_array<f32> — their normals
//     (oriented: see layers.rs) and view depths (unfilterable).
// The blocker test over all views (`occlusion`: the main view's verdict, then each additional
// camera's) and its march along a direction (`march_occlusion`) loop over layer_views, a
// storage array no function can take: they are glue in each pass that runs the test (ssdo
// `direct` and `bounce`, s3ho `sample`), written the same in each; their rules are documented
// here, beside the pieces they call.

const CAMERA_VIEW_BASE: u32 = 3u;
// `Occlusion.source` of a blocker seen by additional camera c: CAMERA_SOURCE + c (peeled layer
// k ≥ 2 of the main view: k − 1; the G-buffer: 0).
const CAMERA_SOURCE: u32 = 8u;

// What the sampling needs from a technique's parameters.
struct SampleConfig {
    samples: u32,
    // 0 chapter pattern, 1 interleaved 4×4 sets.
    pattern: u32,
    // Hemisphere radius R (m).
    radius: f32,
    // Fraction of R where the blocker fade starts.
    fade: f32,
    // Depth layers of the main view (1..=4) and additional cameras (0..=4) in the blocker test.
    layers: u32,
    cameras: u32,
}

// Interleaved gradient noise (Jimenez 2014), as the chapter uses it: a rotation in [0, π).
fn interleaved_gradient_noise(pixel: vec2<u32>) -> f32 {
    let c = vec2<f32>(pixel) + 0.5;
    return fract(52.9829189 * fract(0.06711056 * c.x + 0.00583715 * c.y));
}

fn hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Index in the interleaved pattern (sample_sets) of sample i of pixel `pixel`.
fn sample_set_index(i: u32, pixel: vec2<u32>, cfg: SampleConfig) -> u32 {
    let n = cfg.samples;
    let set_index = (pixel.x % 4u) + 4u * (pixel.y % 4u);
    return set_index * n + i;
}

// Sample i of pixel `pixel`: xyz unit direction in the tangent frame (z = normal), w = λ/R.
// `seed` is the frame's noise seed (View::seed); `set_sample` the interleaved pattern's entry,
// sample_sets[sample_set_index(i, pixel, cfg)], returned for pattern 1.
fn sample_local(seed: u32, set_sample: vec4<f32>, i: u32, pixel: vec2<u32>, cfg: SampleConfig) -> vec4<f32> {
    let n = cfg.samples;
    if cfg.pattern == 1u {
        return set_sample;
    }
    // Chapter: stratified elevation cos = 1 − α, golden-ratio azimuth, IGN rotation.
    let alpha = (f32(i) + 0.5) / f32(n);
    let cos_e = 1.0 - alpha;
    let sin_e = sqrt(max(0.0, 1.0 - cos_e * cos_e));
    // Seed 0 gives the chapter's rotation exactly; other seeds turn it further.
    let phi = PI * fract(interleaved_gradient_noise(pixel) + f32(hash(seed) >> 8u) / 16777216.0 * f32(min(seed, 1u)));
    let theta = 2.0 * PI * alpha * (7.0 * f32(n) / 9.0) + phi;
    // Random length λ ∈ (0, 1] per pixel and sample (with the frame seed), λ = u^(1/3): the
    // sampling points are uniform in the hemisphere's volume.
    let h = hash(pixel.x * 1973u + pixel.y * 9277u + i * 26699u + seed * 103u);
    let lambda = pow((f32(h >> 8u) + 1.0) / 16777216.0, 1.0 / 3.0);
    return vec4<f32>(sin_e * cos(theta), sin_e * sin(theta), cos_e, lambda);
}

struct Frame3 {
    t: vec3<f32>,
    b: vec3<f32>,
}

// The chapter's tangent frame: an up vector never collinear with n.
fn tangent_frame(n: vec3<f32>) -> Frame3 {
    let up = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.y) < 0.999);
    let t = normalize(cross(up, n));
    return Frame3(t, cross(n, t));
}

// How much the point s = p + λω, seen from p, is occluded: 0 visible, up to 1 occluded; the
// blocker (sender patch for the bounce) in `.sender`, where it was seen in `.source` (0 G-buffer,
// 1..3 peeled layer 2..4, CAMERA_SOURCE + c additional camera c) at `.pixel` of that view.
struct Occlusion {
    amount: f32,
    pixel: vec2<u32>,
    distance: f32,
    source: u32,
    sender: Surface,
}

// The fade of a blocker whose entry face (the face towards the viewer that s is behind) is
// `surf`: its distance from p where the segment p → s crosses the face's tangent plane when p is
// in front of it, else (the plane seen is not the blocking face, e.g. the far side of a box) the
// distance to the surface point seen; amount = 1 − smoothstep(fade·R, R, d).
fn blocker_fade(p: vec3<f32>, s: vec3<f32>, lambda: f32, surf: Surface, cfg: SampleConfig) -> vec2<f32> {
    let above_s = dot(s - surf.p, surf.n);
    let above_p = dot(p - surf.p, surf.n);
    var d = distance(surf.p, p);
    if above_p >= 0.0 {
        d = above_p / max(above_p - above_s, 1e-12) * lambda;
    }
    return vec2<f32>(1.0 - smoothstep(cfg.fade * cfg.radius, cfg.radius, d), d);
}

// The surface of peeled layer k + 2 of the main view (`cam`) at `pixel`: `normals`/`depths` the
// peeled layers' normals and view depths (peel_normal, peel_depth).
fn peel_surface(cam: View, normals: texture_2d_array<f32>, depths: texture_2d_array<f32>, pixel: vec2<u32>, k: u32) -> Surface {
    var s: Surface;
    let nw = textureLoad(normals, pixel, k, 0);
    let depth = textureLoad(depths, pixel, k, 0).r;
    s.valid = nw.w != 0.0 && depth > 0.0;
    s.n = normalize(nw.xyz);
    s.p = world_position(cam, pixel, depth);
    return s;
}

// The surface additional camera c (its view `camera`, layer_views[CAMERA_VIEW_BASE + c]) sees at
// `pixel`: `normals`/`depths` the cameras' normals and view depths (cam_normal, cam_depth).
fn camera_surface(camera: LayerView, normals: texture_2d_array<f32>, depths: texture_2d_array<f32>, pixel: vec2<u32>, c: u32) -> Surface {
    var s: Surface;
    let nw = textureLoad(normals, pixel, c, 0);
    let depth = textureLoad(depths, pixel, c, 0).r;
    s.valid = nw.w != 0.0 && depth > 0.0;
    s.n = normalize(nw.xyz);
    s.p = layer_position(camera, pixel, depth);
    return s;
}

// What one view says about s: `informed` (s projects inside it), `free` (s is in front of what
// it sees there, or it sees background) or occluded by `o`.
struct ViewVerdict {
    informed: bool,
    free: bool,
    o: Occlusion,
}

// The main view: the paper's test against the first layer (against its tangent plane, see
// technique/ssdo/mod.rs), and with depth peeling (paper Sec. 4) s is inside a solid only between
// an entry layer (1, 3) and the exit layer after it (2, 4): behind an exit face it lies in a gap
// and is free (Fig. 5, sample A). Peeled normals face outwards (entry layers towards the camera,
// exit layers away from it), so "inside" is "behind both faces' planes". A missing exit keeps
// the single-layer verdict. `cam` is the main view; `gb_normal`/`gb_depth` its G-buffer normal and
// view depth, `peel_normal`/`peel_depth` its peeled layers'.
fn main_view_verdict(cam: View, gb_normal: texture_2d<f32>, gb_depth: texture_2d<f32>, peel_normal: texture_2d_array<f32>, peel_depth: texture_2d_array<f32>, p: vec3<f32>, s: vec3<f32>, lambda: f32, cfg: SampleConfig) -> ViewVerdict {
    var v: ViewVerdict;
    v.informed = false;
    v.free = true;
    v.o.amount = 0.0;
    let c = cam.clip_from_world * vec4<f32>(s, 1.0);
    // Chapter condition 1: outside the screen (or behind the camera) — no information.
    if c.w <= 0.0 {
        return v;
    }
    let ndc = c.xy / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return v;
    }
    v.informed = true;
    let q = vec2<u32>(uv * cam.size);
    let surf = surface_at(cam, gb_normal, gb_depth, q);
    // Chapter condition 2: background — open.
    if !surf.valid {
        return v;
    }
    // Chapter condition 3 / the paper's rule against the tangent plane at q.
    let tolerance = 1e-4 * c.w;
    if dot(s - surf.p, surf.n) >= -tolerance {
        return v;
    }
    var entry = surf;
    var sender = surf;
    var source = 0u;
    var inside = true;
    for (var k = 0u; k + 1u < cfg.layers; k++) {
        let layer = peel_surface(cam, peel_normal, peel_depth, q, k);
        if !layer.valid {
            break;
        }
        let behind = dot(s - layer.p, layer.n) < -tolerance;
        if k % 2u == 0u {
            // Exit face (layer 2 or 4).
            if behind {
                if abs(dot(s - layer.p, layer.n)) < abs(dot(s - entry.p, entry.n)) {
                    sender = layer;
                    source = k + 1u;
                }
                break;
            }
            inside = false;
        } else {
            // Entry face (layer 3).
            if !behind {
                break;
            }
            inside = true;
            entry = layer;
            sender = layer;
            source = k + 1u;
        }
    }
    if !inside {
        return v;
    }
    let f = blocker_fade(p, s, lambda, entry, cfg);
    v.free = false;
    v.o.amount = f.x;
    v.o.distance = f.y;
    v.o.pixel = q;
    v.o.source = source;
    v.o.sender = sender;
    return v;
}

// Additional camera c (paper Sec. 4): the single-layer test in that view, `camera`
// (layer_views[CAMERA_VIEW_BASE + c]); `cam_normal`/`cam_depth` the cameras' normals and depths.
fn camera_verdict(camera: LayerView, cam_normal: texture_2d_array<f32>, cam_depth: texture_2d_array<f32>, p: vec3<f32>, s: vec3<f32>, lambda: f32, c: u32, cfg: SampleConfig) -> ViewVerdict {
    var v: ViewVerdict;
    v.informed = false;
    v.free = true;
    v.o.amount = 0.0;
    let h = camera.clip_from_world * vec4<f32>(s, 1.0);
    if h.w <= 0.0 {
        return v;
    }
    let ndc = h.xyz / h.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) || ndc.z < 0.0 {
        return v;
    }
    v.informed = true;
    let q = vec2<u32>(uv * camera.size);
    let surf = camera_surface(camera, cam_normal, cam_depth, q, c);
    if !surf.valid || dot(s - surf.p, surf.n) >= -1e-4 * h.w {
        return v;
    }
    let f = blocker_fade(p, s, lambda, surf, cfg);
    v.free = false;
    v.o.amount = f.x;
    v.o.distance = f.y;
    v.o.pixel = q;
    v.o.source = CAMERA_SOURCE + c;
    v.o.sender = surf;
    return v;
}

// The blocker test of every technique that samples the hemisphere, `occlusion(p, omega, lambda,
// cfg) -> Occlusion` (glue in each pass, see the header): s = p + λω; the main view's verdict,
// then each additional camera's. A sample is free as soon as one view that sees it finds it in
// front of the surface there (free space seen from any viewpoint is free), else occluded by the
// strongest blocker any view found; off-screen in every view, it is free (chapter condition 1).

// Points per direction of the march a bounce takes its sender from. The bounce's patch estimator
// (area πR²/N at the sample's distance, SSDO Sec. 3) assumes the senders of points spread
// through the hemisphere's volume; a marched ray's first blocker is nearer, and 1/d²
// over-weights it (ssdo `diffuse` on cornell 0.045 → 0.067 with two layers and 16 steps). With
// two or four layers (where 16 marched points are the default for visibility) the sender
// therefore comes from at most the technique's paper count (`paper_steps`: ssdo 1, the single
// point at λ; s3ho 2); with one layer from the march itself, as before.
fn bounce_steps(steps: u32, paper_steps: u32, cfg: SampleConfig) -> u32 {
    if cfg.layers > 1u {
        return min(steps, paper_steps);
    }
    return steps;
}

// Where a world point falls on the main view `cam`, in pixels.
fn screen_pixel(cam: View, x: vec3<f32>) -> vec2<f32> {
    let c = cam.clip_from_world * vec4<f32>(x, 1.0);
    let ndc = c.xy / max(c.w, 1e-12);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * cam.size;
}

// The blocker test along a direction (ray marching), `march_occlusion(p, omega, lambda, steps,
// cfg) -> Occlusion` (glue in each pass, see the header): `steps` points at λ·k/steps,
// k = 1..steps; the first occluded one decides (steps = 1: the paper's single point at λ).
// Points before the last that land within MARCH_MIN_PIXELS of p on screen (screen_pixel) are
// skipped: the depth buffer cannot resolve them (they read p's own pixel or its neighbours, whose
// faces at a corner would count as blockers), so a sub-pixel radius gets the single-point test.
const MARCH_MIN_PIXELS: f32 = 1.5;

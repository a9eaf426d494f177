// screen_samples.wgsl — hemisphere samples and the screen-space visibility test shared by the
// sampling techniques (ssao, ssdo, s3ho, ssbn), so that they differ only in what they do with the
// samples. Prepended after common.wgsl (and env/lights where needed). Sources and deviations: see
// technique/ssdo.wgsl, whose header documents the test.

// Interleaved pattern: 16 sets × N samples (xyz: unit direction in the tangent frame, z up;
// w: λ/R in (0, 1]).
@group(0) @binding(6) var<storage, read> sample_sets: array<vec4<f32>>;
@group(0) @binding(8) var gb_normal: texture_2d<f32>;
@group(0) @binding(9) var gb_view_depth: texture_2d<f32>;

// What the sampling needs from a technique's parameters.
struct SampleConfig {
    samples: u32,
    // 0 chapter pattern, 1 interleaved 4×4 sets.
    pattern: u32,
    // Hemisphere radius R (m).
    radius: f32,
    // Fraction of R where the blocker fade starts.
    fade: f32,
}

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

// Sample i of pixel `pixel`: xyz unit direction in the tangent frame (z = normal), w = λ/R.
fn sample_local(i: u32, pixel: vec2<u32>, cfg: SampleConfig) -> vec4<f32> {
    let n = cfg.samples;
    if cfg.pattern == 1u {
        let set_index = (pixel.x % 4u) + 4u * (pixel.y % 4u);
        return sample_sets[set_index * n + i];
    }
    // Chapter: stratified elevation cos = 1 − α, golden-ratio azimuth, IGN rotation.
    let alpha = (f32(i) + 0.5) / f32(n);
    let cos_e = 1.0 - alpha;
    let sin_e = sqrt(max(0.0, 1.0 - cos_e * cos_e));
    // Seed 0 gives the chapter's rotation exactly; other seeds turn it further.
    let phi = PI * fract(interleaved_gradient_noise(pixel) + f32(hash(frame.counts.z) >> 8u) / 16777216.0 * f32(min(frame.counts.z, 1u)));
    let theta = 2.0 * PI * alpha * (7.0 * f32(n) / 9.0) + phi;
    // Random length λ ∈ (0, 1] per pixel and sample (with the frame seed), λ = u^(1/3): the
    // sampling points are uniform in the hemisphere's volume.
    let h = hash(pixel.x * 1973u + pixel.y * 9277u + i * 26699u + frame.counts.z * 103u);
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

// How much the point s = p + λω, seen from p, is occluded: 0 visible, up to 1 occluded.
// Returns the occluder's pixel in `.pixel` for the bounce.
struct Occlusion {
    amount: f32,
    pixel: vec2<u32>,
    distance: f32,
}

fn occlusion(p: vec3<f32>, omega: vec3<f32>, lambda: f32, cfg: SampleConfig) -> Occlusion {
    var o: Occlusion;
    o.amount = 0.0;
    let s = p + omega * lambda;
    let c = frame.clip_from_world * vec4<f32>(s, 1.0);
    // Chapter condition 1: outside the screen (or behind the camera) — open.
    if c.w <= 0.0 {
        return o;
    }
    let ndc = c.xy / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return o;
    }
    let q = vec2<u32>(uv * frame.size.xy);
    let surf = surface_at(q);
    // Chapter condition 2: background — open.
    if !surf.valid {
        return o;
    }
    // Chapter condition 3 / the paper's rule against the tangent plane at q: the sample is
    // behind the surface seen there.
    let above_s = dot(s - surf.p, surf.n);
    if above_s >= -1e-4 * c.w {
        return o;
    }
    // Blocker distance for the fade: where the segment p → s crosses the tangent plane when p is
    // in front of it, else (the plane seen is not the blocking face, e.g. the far side of a box)
    // the distance to the surface point seen.
    let above_p = dot(p - surf.p, surf.n);
    var d = distance(surf.p, p);
    if above_p >= 0.0 {
        d = above_p / max(above_p - above_s, 1e-12) * lambda;
    }
    o.amount = 1.0 - smoothstep(cfg.fade * cfg.radius, cfg.radius, d);
    o.pixel = q;
    o.distance = d;
    return o;
}


// Transfer from a sender patch (a pixel that occludes a sample, SSDO Sec. 3) to the receiver,
// per unit sender radiance, in irradiance/π units: area · cos θ_s · cos θ_r · falloff /
// (π · max(d, distance_clamp)²) with falloff 1 − d/R; 0 when either surface faces away.
fn sender_transfer(receiver: Surface, sender: Surface, area: f32, radius: f32, distance_clamp: f32) -> f32 {
    let to_sender = sender.p - receiver.p;
    let d = length(to_sender);
    if d <= 0.0 {
        return 0.0;
    }
    let dir = to_sender / d;
    let cos_s = max(0.0, dot(sender.n, -dir));
    let cos_r = max(0.0, dot(receiver.n, dir));
    let falloff = max(0.0, 1.0 - d / radius);
    let dc = max(distance_clamp, d);
    return area * cos_s * cos_r * falloff / (PI * dc * dc);
}

// half.wgsl — `resolution=half` (gtao, hbil, vbgi): the pixel of each 2×2 block that the search
// takes, and the edge-aware upsample that brings its results to every pixel. A library (after
// common.wgsl, env.wgsl, far.wgsl and params.wgsl): it declares no bindings; its functions take
// the view (`cam`), the environment's uniforms (`e`), the G-buffer images they read (`normals`:
// world normal, `depths`: view depth), the search's results (`cones`, `nears`, `fars`:
// search.wgsl's `out_cone`, `out_near`, `out_far`, one texel per 2×2 block) and the far field's
// probes (`probes`, `visibility`, `atlas`, `smp`: far.wgsl's far_irradiance_here). accumulate.wgsl upsamples on its
// way in; upsample.wgsl writes full-resolution images where the bilateral blur comes first.
//
// Half resolution (`resolution=half`, gtao, hbil and vbgi, half.wgsl): the search runs at one pixel
// of each 2×2 block, the block's four in turn over frames ((0,0), (1,1), (1,0), (0,1)), reading
// the full-resolution G-buffer; slice angles and step jitter follow the block grid, so that the
// blocks around a pixel bring different directions. Every pixel then takes the four searched
// pixels around it with the bilinear weights of its position, each times
// (n·n_s)⁸ / (1 + (d/(0.01 depth))²), d the searched point's distance from the pixel's tangent
// plane: a tap on another surface (across a silhouette or a crease) hardly counts, and a pixel
// whose nearest taps all lie on other surfaces takes the likeliest of them. The bilinear weights
// carry a floor of 10⁻³ for that case, the normals' term one of 10⁻¹² for a pixel whose every
// tap faces 90° or more away (a roof's edge over a wall, one pixel wide). A pixel none of whose
// taps sees a surface (a ledge one pixel wide against the sky, on the three frames of four whose
// searched rows or columns miss it) is taken as open: ao 1, its own normal as the bent normal,
// no near field, and the far field of an open hemisphere (the probe volume's irradiance, or the
// sky's). Left dark, such pixels read a quarter of their light in the running mean. The far field (the environment through the visible arcs
// or sectors) is a cosine-weighted integral at the searched pixel's normal n_s; each tap's is
// carried to the pixel's normal n by E_sky(n)/E_sky(n_s), the open sky's SH irradiance at the two
// (per channel; not where E_sky(n_s) is below 5 % of E_sky(n)): the visibility is shared by
// neighbours, the normal is not where a normal map varies it. Accumulate upsamples on its way in;
// with the bilateral blur the `upsample` pass writes full-resolution images first, which the blur
// reads.

// The upsample's tolerance: a tap counts half when its surface point lies this far (relative to
// the pixel's view depth) from the pixel's tangent plane.
const HALF_PLANE: f32 = 0.01;

// The pixel of its 2×2 block that frame `frame`'s search takes: (0,0), (1,1), (1,0), (0,1) in
// turn, so that a running mean sees all four.
fn half_offset(frame: u32) -> vec2<u32> {
    let k = frame % 4u;
    return vec2<u32>(((k + 1u) >> 1u) & 1u, k & 1u);
}

// The size of the searched grid: one texel per 2×2 block.
fn half_size(cam: View) -> vec2<u32> {
    return (vec2<u32>(cam.size) + 1u) / 2u;
}

// The full-resolution pixel that half-resolution `texel` searches this frame.
fn half_pixel(cam: View, texel: vec2<u32>) -> vec2<u32> {
    return min(texel * 2u + half_offset(cam.frame_index), vec2<u32>(cam.size) - 1u);
}

// The four searched texels around a pixel (tap i at `base` + (i & 1, i >> 1)) and their
// weights, which sum to 1 (all 0 where no tap sees a surface).
struct HalfTaps {
    base: vec2<i32>,
    weight: vec4<f32>,
    // The searched pixels' unit normals (where their weight is not 0).
    normal: array<vec3<f32>, 4>,
}

fn half_tap(h: HalfTaps, i: u32) -> vec2<i32> {
    return h.base + vec2<i32>(i32(i & 1u), i32(i >> 1u));
}

// The upsample's taps of full-resolution `pixel` (world point x, unit normal n, view depth
// `depth`): the bilinear weights of the four searched pixels around it, each times
// (n·n_s)⁸ / (1 + (d/(HALF_PLANE depth))²), d the searched point's distance from x's tangent
// plane, so that a tap on another surface hardly counts. A small floor under the bilinear weight
// lets a pixel whose nearest taps lie on other surfaces take the farther one on its own; a tiny
// one under the normals' term lets a pixel whose every tap faces 90° or more away (a roof's edge
// over a wall) take them rather than nothing.
fn half_taps(normals: texture_2d<f32>, depths: texture_2d<f32>, cam: View, pixel: vec2<u32>, x: vec3<f32>, n: vec3<f32>, depth: f32) -> HalfTaps {
    let off = half_offset(cam.frame_index);
    let rel = vec2<i32>(pixel) - vec2<i32>(off);
    var h: HalfTaps;
    h.base = vec2<i32>(floor(vec2<f32>(rel) * 0.5));
    // 0 on a searched row or column, ½ between two.
    let f = vec2<f32>(rel - 2 * h.base) * 0.5;
    let grid = vec2<i32>(half_size(cam));
    let last = vec2<u32>(cam.size) - 1u;
    let tol = HALF_PLANE * depth;
    var sum = 0.0;
    for (var i = 0u; i < 4u; i++) {
        let t = half_tap(h, i);
        if any(t < vec2<i32>(0)) || any(t >= grid) {
            continue;
        }
        let s = min(vec2<u32>(t) * 2u + off, last);
        let ds = textureLoad(depths, s, 0).r;
        let ns = textureLoad(normals, s, 0);
        if ds <= 0.0 || ns.w == 0.0 {
            continue;
        }
        let bx = select(1.0 - f.x, f.x, (i & 1u) == 1u);
        let by = select(1.0 - f.y, f.y, (i >> 1u) == 1u);
        let plane = dot(n, world_position(cam, s, ds) - x) / tol;
        h.normal[i] = normalize(ns.xyz);
        let c = max(dot(n, h.normal[i]), 0.0);
        let c2 = c * c;
        let c4 = c2 * c2;
        let w = (bx * by + 1e-3) * (c4 * c4 + 1e-12) / (1.0 + plane * plane);
        h.weight[i] = w;
        sum += w;
    }
    if sum > 0.0 {
        h.weight /= sum;
    }
    return h;
}

// This frame's search results at full-resolution `pixel` (its G-buffer normal `nw`, w = 0
// without a surface, and view depth `depth`, which the caller has read): bent cone, near field
// (NEAR) and far field (FAR), the searched texels' weighted by half_taps. A pixel without a
// surface gets the open cone (0, 0, 0, 1) and no light; one whose taps all lack a surface is
// taken as open (below).
struct HalfResults {
    cone: vec4<f32>,
    near: vec3<f32>,
    far: vec4<f32>,
}

fn half_upsample(normals: texture_2d<f32>, depths: texture_2d<f32>, cones: texture_2d<f32>, nears: texture_2d<f32>, fars: texture_2d<f32>, probes: texture_2d<f32>, visibility: texture_2d<f32>, atlas: texture_2d<f32>, smp: sampler, cam: View, e: EnvUniforms, pixel: vec2<u32>, nw: vec4<f32>, depth: f32) -> HalfResults {
    var r: HalfResults;
    r.cone = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if nw.w == 0.0 || depth <= 0.0 {
        return r;
    }
    let n = normalize(nw.xyz);
    let x = world_position(cam, pixel, depth);
    let h = half_taps(normals, depths, cam, pixel, x, n, depth);
    if dot(h.weight, vec4<f32>(1.0)) == 0.0 {
        // Every searched pixel around is sky (a surface one pixel wide, whose row or column
        // this frame's search skips): the pixel is taken as open, its far field as what an
        // unoccluded hemisphere receives, the probe volume's irradiance or the sky's.
        r.cone = vec4<f32>(n, 1.0);
        if FAR {
            var open = env_irradiance_sh(e, n);
            if far_volume(probes) {
                open = far_irradiance_here(probes, visibility, atlas, smp, cam, x, n);
            }
            r.far = vec4<f32>(open, 1.0);
        }
        return r;
    }
    r.cone = vec4<f32>(0.0);
    // The open sky's irradiance at this pixel's normal (FAR below).
    var e_p = vec3<f32>(0.0);
    if FAR {
        e_p = env_irradiance_sh(e, n);
    }
    for (var i = 0u; i < 4u; i++) {
        let w = h.weight[i];
        if w == 0.0 {
            continue;
        }
        let t = half_tap(h, i);
        r.cone += w * textureLoad(cones, t, 0);
        if NEAR {
            r.near += w * textureLoad(nears, t, 0).rgb;
        }
        if FAR {
            // The far field is a cosine-weighted integral at the searched pixel's normal: it is
            // carried to this pixel's normal by the ratio of the open sky's irradiance at the two
            // (what a normal map changes between neighbours), where the searched one's is not dark.
            let e_s = env_irradiance_sh(e, h.normal[i]);
            let ratio = select(vec3<f32>(1.0), e_p / max(e_s, vec3<f32>(1e-8)), e_s > 0.05 * max(e_p, vec3<f32>(1e-8)));
            let f = textureLoad(fars, t, 0);
            r.far += w * vec4<f32>(f.rgb * ratio, f.w);
        }
    }
    return r;
}

// reproject.wgsl — last frame's radiance in this frame's view (HBIL Sec. 3.2), then hole filling.
//
// Scatter (the paper's default): every pixel of last frame is moved to where its surface point
// lands now (last frame's depth and camera → world → this camera). A point lands only if it lies
// on the surface this frame sees there (`same_surface` in common.wgsl: near its tangent plane,
// similar normal, within a few pixel footprints); several landing on one pixel are resolved by a
// depth test on an atomic buffer (the nearest wins). Three passes: scatter_depth (atomicMin of
// the depth bits: positive floats order like their bit patterns), scatter_color (the winner
// writes its radiance), scatter_resolve (one pass over this frame's pixels: winner → alpha 1,
// no winner → hole, alpha 0; and the depth buffer is reset for the next frame).
// Gather (selectable): every pixel of this frame follows its motion vector into last frame and
// takes the bilinear mean of the taps that pass the same surface test; none → hole.
// Push/pull (Kraus 2009, "The Pull-Push Algorithm Revisited"): `push` builds coarser levels,
// each texel the alpha-weighted mean of its 2×2 children with alpha min(1, Σ alpha); `pull`
// goes back down, keeping every valid texel and filling the rest from the bilinearly
// interpolated coarser level: out = a · fine + (1 − a) · coarse. A filled value is thus a convex
// combination of valid values around the hole.

struct ReprojectParams {
    reject_depth: f32,
    reject_normal: f32,
    _pad0: f32,
    _pad1: f32,
}

@group(1) @binding(0) var<uniform> params: ReprojectParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var gb_view_depth: texture_2d<f32>;
@group(1) @binding(4) var prev_geometry: texture_2d<f32>;
@group(1) @binding(5) var prev_radiance: texture_2d<f32>;
@group(1) @binding(6) var<storage, read_write> zbuffer: array<atomic<u32>>;
@group(1) @binding(7) var<storage, read_write> colors: array<vec4<f32>>;
@group(1) @binding(8) var out_reprojected: texture_storage_2d<rgba16float, write>;
@group(1) @binding(3) var gb_motion: texture_2d<f32>;

const EMPTY: u32 = 0xffffffffu;

struct Landing {
    index: u32,
    depth_bits: u32,
    ok: bool,
}

// Where last frame's pixel `pixel` lands in this frame, if it lands on the surface seen there.
fn land(pixel: vec2<u32>) -> Landing {
    var l: Landing;
    l.ok = false;
    let g = textureLoad(prev_geometry, pixel, 0);
    if g.w <= 0.0 {
        return l;
    }
    let world = (view.prev_world_from_view * vec4<f32>(prev_view_position(view, pixel, g.w), 1.0)).xyz;
    let d = -(view.view_from_world * vec4<f32>(world, 1.0)).z;
    if d <= 0.0 {
        return l;
    }
    let s = floor(to_screen(view, view.clip_from_world, world));
    if any(s < vec2<f32>(0.0)) || any(s >= view.size) {
        return l;
    }
    let q = vec2<u32>(s);
    let nw = textureLoad(gb_normal, q, 0);
    let qd = textureLoad(gb_view_depth, q, 0).r;
    if nw.w == 0.0 || qd <= 0.0 {
        return l;
    }
    if !same_surface(view, world_position(view, q, qd), normalize(nw.xyz), qd, world, g.xyz, params.reject_depth, params.reject_normal) {
        return l;
    }
    l.index = q.y * u32(view.size.x) + q.x;
    l.depth_bits = bitcast<u32>(d);
    l.ok = true;
    return l;
}

@compute @workgroup_size(8, 8, 1)
fn scatter_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if !in_bounds(view, id.xy) {
        return;
    }
    let l = land(id.xy);
    if l.ok {
        atomicMin(&zbuffer[l.index], l.depth_bits);
    }
}

@compute @workgroup_size(8, 8, 1)
fn scatter_color(@builtin(global_invocation_id) id: vec3<u32>) {
    if !in_bounds(view, id.xy) {
        return;
    }
    let l = land(id.xy);
    if l.ok && atomicLoad(&zbuffer[l.index]) == l.depth_bits {
        colors[l.index] = vec4<f32>(textureLoad(prev_radiance, id.xy, 0).rgb, 1.0);
    }
}

@compute @workgroup_size(8, 8, 1)
fn scatter_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let i = pixel.y * u32(view.size.x) + pixel.x;
    var out = vec4<f32>(0.0);
    if atomicLoad(&zbuffer[i]) != EMPTY {
        out = colors[i];
    }
    atomicStore(&zbuffer[i], EMPTY);
    textureStore(out_reprojected, pixel, out);
}

@compute @workgroup_size(8, 8, 1)
fn gather(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    let nw = textureLoad(gb_normal, pixel, 0);
    let depth = textureLoad(gb_view_depth, pixel, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(out_reprojected, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let x = world_position(view, pixel, depth);
    // Motion = last − this frame's pixel position of the point.
    let prev = vec2<f32>(pixel) + 0.5 + textureLoad(gb_motion, pixel, 0).rg;
    let taps = history_taps(view, prev_geometry, prev, x, n, depth, params.reject_depth, params.reject_normal);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        if taps.weights[k] > 0.0 {
            sum += taps.weights[k] * textureLoad(prev_radiance, taps.base + tap_offset(k), 0).rgb;
        }
    }
    let weight = taps.total;
    var out = vec4<f32>(0.0);
    if weight > 1e-3 {
        out = vec4<f32>(sum / weight, 1.0);
    }
    textureStore(out_reprojected, pixel, out);
}

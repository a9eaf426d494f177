// far.wgsl — the far field, a library (after env.wgsl) for passes that light what lies beyond R.
// It declares no bindings: its functions take the three far-field textures and the sampler
// (nearfield binds them in group 0, shaders/frame_bindings.wgsl; crate::far uploads them).
//
// With `--far sky` (far_volume() false) passes keep their own environment terms. With a probe
// volume (nearfield_scene::probes, the book's "The far field") a point P with normal n seen from
// v reads the 8 probes of its cell with DDGI's weights (McGuire et al. 2019): trilinear at
// P' = P + bias (0.3 n + 0.7 v), a wrap-around backface term ((dir·n + 1)/2)² + 0.2, Chebyshev's
// bound on the probe seeing P' cubed, weights below 0.2 crushed, switched-off probes skipped; the
// normalised sum of their order-2 SH radiance is the far field at P. ProbeVolume::weights is the
// same arithmetic on the CPU (a GPU test compares the two).

// The textures the functions take:
// `probes`, rgba32float. Row 0, texels 0..3: the grid (FarGrid below; counts as exact floats); texel 4:
// 1 / the irradiance atlas's size. From row 1:
// FAR_TEXELS texels per probe, `counts.w` probes per row: (offset xyz, active), then 9 SH rgb.
// (The grid rides in the texture rather than a uniform: one more uniform buffer in group 0
// crashes lavapipe 22.3's pipelines with many bindings.)
// `visibility`, rg16float, a FAR_TILE² tile per probe (`counts.w` per row): (mean, mean²) of the distance /
// max distance over an octahedral map with a one-texel border.
// `atlas`, rgba16float, a FAR_IRR_TILE² tile per probe (`counts.w` per row): E(n)/π over an octahedral
// map of n with a one-texel border; 1 / its size in row 0's texel 4 of `probes`.
// `smp`: linear filtering (the environment's sampler).

struct FarGrid {
    // xyz: position of probe (0, 0, 0) (m); w: 1 with a volume, 0 for the sky.
    origin: vec4<f32>,
    // xyz: spacing (m); w: the lookup's bias (m).
    spacing: vec4<f32>,
    // Probes per axis; w: probes per row of the probe texture and the visibility atlas.
    counts: vec4<u32>,
    // x: largest recorded distance (m); yz: 1 / atlas size; w: unused.
    vis: vec4<f32>,
}

fn far_grid(probes: texture_2d<f32>) -> FarGrid {
    var g: FarGrid;
    g.origin = textureLoad(probes, vec2<u32>(0u, 0u), 0);
    g.spacing = textureLoad(probes, vec2<u32>(1u, 0u), 0);
    g.counts = vec4<u32>(textureLoad(probes, vec2<u32>(2u, 0u), 0));
    g.vis = textureLoad(probes, vec2<u32>(3u, 0u), 0);
    return g;
}

const FAR_TEXELS: u32 = 13u;
const FAR_VIS_RES: f32 = 16.0;
const FAR_TILE: u32 = 18u;
const FAR_IRR_RES: f32 = 12.0;
const FAR_IRR_TILE: u32 = 14u;

// 1 / the irradiance atlas's size.
fn far_irr_texel(probes: texture_2d<f32>) -> vec2<f32> {
    return textureLoad(probes, vec2<u32>(4u, 0u), 0).xy;
}

// The radiance arriving at a point: order-2 SH (nearfield_scene::sh's basis), rgb.
struct FarSh {
    c: array<vec4<f32>, 9>,
}

// The far field a pipeline is made for: FAR_FIELD_SKY, FAR_FIELD_VOLUME, or FAR_FIELD_BOUND
// (the default: far_volume() reads it from the bound probe texture). nearfield's passes set it
// from the frame group they are built with (FrameGroup::far_field_constant), so that the side
// of every `far_volume()` branch the frame does not take is left out of the kernel: a SIMD
// backend (lavapipe) would run it for every pixel (docs/src/architecture.md, "Specialised
// kernels").
const FAR_FIELD_SKY: u32 = 0u;
const FAR_FIELD_VOLUME: u32 = 1u;
const FAR_FIELD_BOUND: u32 = 2u;
override FAR_FIELD: u32 = 2u;

fn far_volume(probes: texture_2d<f32>) -> bool {
    if FAR_FIELD == FAR_FIELD_BOUND {
        return textureLoad(probes, vec2<u32>(0u, 0u), 0).w > 0.5;
    }
    return FAR_FIELD == FAR_FIELD_VOLUME;
}

fn far_sign(v: vec2<f32>) -> vec2<f32> {
    return select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

// Octahedral coordinates in [−1, 1]² of a unit direction (nearfield_scene::probes::oct_encode).
fn far_oct_encode(d: vec3<f32>) -> vec2<f32> {
    let p = d.xy / max(abs(d.x) + abs(d.y) + abs(d.z), 1e-20);
    if d.z >= 0.0 {
        return p;
    }
    return (vec2<f32>(1.0) - abs(p.yx)) * far_sign(p);
}

fn far_texel(probes: texture_2d<f32>, g: FarGrid, index: u32, k: u32) -> vec4<f32> {
    let row = g.counts.w;
    return textureLoad(probes, vec2<u32>((index % row) * FAR_TEXELS + k, 1u + index / row), 0);
}

// (mean, mean²) of probe `index`'s distances towards unit `d`, in metres and metres².
fn far_moments(visibility: texture_2d<f32>, smp: sampler, g: FarGrid, index: u32, d: vec3<f32>) -> vec2<f32> {
    let row = g.counts.w;
    let tile = vec2<f32>(f32((index % row) * FAR_TILE), f32((index / row) * FAR_TILE));
    let t = tile + (far_oct_encode(d) * 0.5 + 0.5) * FAR_VIS_RES + 1.0;
    let m = textureSampleLevel(visibility, smp, t * g.vis.yz, 0.0).xy;
    let maxd = g.vis.x;
    return vec2<f32>(m.x * maxd, m.y * maxd * maxd);
}

// One of the 8 probes around a lookup: its index and DDGI weight (0 when switched off).
struct FarCorner {
    index: u32,
    w: f32,
}

// The cell of a lookup at world `p`, unit normal `n`, seen from unit `v`.
struct FarCell {
    grid: FarGrid,
    p: vec3<f32>,
    n: vec3<f32>,
    biased: vec3<f32>,
    base: vec3<f32>,
    alpha: vec3<f32>,
}

fn far_cell(probes: texture_2d<f32>, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> FarCell {
    var cell: FarCell;
    cell.grid = far_grid(probes);
    cell.p = p;
    cell.n = n;
    let counts = vec3<f32>(cell.grid.counts.xyz);
    cell.biased = p + cell.grid.spacing.w * (0.3 * n + 0.7 * v);
    let last = counts - 1.0;
    let rel = clamp((cell.biased - cell.grid.origin.xyz) / cell.grid.spacing.xyz, vec3<f32>(0.0), last);
    cell.base = min(floor(rel), max(last - 1.0, vec3<f32>(0.0)));
    cell.alpha = clamp(rel - cell.base, vec3<f32>(0.0), vec3<f32>(1.0));
    return cell;
}

// Corner `c` (bit 0: +x, 1: +y, 2: +z) of the cell with its unnormalised weight.
fn far_corner(probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, cell: FarCell, c: u32) -> FarCorner {
    let g = cell.grid;
    let o = vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
    let coords = min(vec3<u32>(cell.base) + o, g.counts.xyz - 1u);
    var out: FarCorner;
    out.index = coords.x + g.counts.x * (coords.y + g.counts.y * coords.z);
    out.w = 0.0;
    let state = far_texel(probes, g, out.index, 0u);
    if state.w < 0.5 {
        return out;
    }
    let tri = mix(1.0 - cell.alpha, cell.alpha, vec3<f32>(o));
    let trilinear = tri.x * tri.y * tri.z;
    let pos = g.origin.xyz + g.spacing.xyz * vec3<f32>(coords) + state.xyz;
    let to_probe_v = pos - cell.p;
    let to_probe = select(vec3<f32>(0.0), normalize(to_probe_v), dot(to_probe_v, to_probe_v) > 0.0);
    let wrap = 0.5 * (dot(to_probe, cell.n) + 1.0);
    var w = wrap * wrap + 0.2;
    let from_probe = cell.biased - pos;
    let dist = length(from_probe);
    let m = far_moments(visibility, smp, g, out.index, from_probe / max(dist, 1e-12));
    if dist > m.x {
        let variance = max(abs(m.y - m.x * m.x), 1e-6 * g.vis.x);
        let cheb = variance / (variance + (dist - m.x) * (dist - m.x));
        w *= cheb * cheb * cheb;
    }
    w = max(w, 1e-6);
    if w < 0.2 {
        w *= w * w / (0.2 * 0.2);
    }
    out.w = w * trilinear;
    return out;
}

// The far field's radiance SH at world point `p` with unit normal `n`, seen from unit `v`.
fn far_sh_at(probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> FarSh {
    var out: FarSh;
    for (var k = 0u; k < 9u; k++) {
        out.c[k] = vec4<f32>(0.0);
    }
    let cell = far_cell(probes, p, n, v);
    var total = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let corner = far_corner(probes, visibility, smp, cell, c);
        if corner.w <= 0.0 {
            continue;
        }
        for (var k = 0u; k < 9u; k++) {
            out.c[k] += corner.w * far_texel(probes, cell.grid, corner.index, 1u + k);
        }
        total += corner.w;
    }
    if total > 0.0 {
        for (var k = 0u; k < 9u; k++) {
            out.c[k] /= total;
        }
    }
    return out;
}

// The far field's own visibility within R about unit normal `n` at world `p` (seen from unit
// `v`): the cosine-weighted share of the hemisphere in which the probes around p meet nothing
// within R (each probe's visibility SH, ProbeVolume::visibility_sh, with the lookup's weights),
// in [0, 1]. 1 where the probes see nothing within R.
fn far_ao_at(probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> f32 {
    let cell = far_cell(probes, p, n, v);
    let b = sh_basis(n);
    var a = 0.0;
    var total = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let corner = far_corner(probes, visibility, smp, cell, c);
        if corner.w <= 0.0 {
            continue;
        }
        let t0 = far_texel(probes, cell.grid, corner.index, 10u);
        let t1 = far_texel(probes, cell.grid, corner.index, 11u);
        let t2 = far_texel(probes, cell.grid, corner.index, 12u);
        let band1 = t0.y * b[1] + t0.z * b[2] + t1.x * b[3];
        let band2 = t1.y * b[4] + t1.z * b[5] + t2.x * b[6] + t2.y * b[7] + t2.z * b[8];
        a += corner.w * (t0.x * b[0] + (2.0 / 3.0) * band1 + 0.25 * band2);
        total += corner.w;
    }
    if total <= 0.0 {
        return 1.0;
    }
    return clamp(a / total, 0.0, 1.0);
}

fn far_ao_here(probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, cam: View, p: vec3<f32>, n: vec3<f32>) -> f32 {
    return far_ao_at(probes, visibility, smp, p, n, normalize(cam.camera_position.xyz - p));
}

// E(n)/π of the far field at world `p` with unit normal `n` seen from unit `v`: the same weights
// as far_sh_at over each probe's pre-convolved octahedral irradiance (one bilinear fetch a probe
// instead of 9 SH texels; ProbeVolume::irradiance_tile, within IRRADIANCE_TILE_ERROR of the SH).
fn far_irradiance_at(probes: texture_2d<f32>, visibility: texture_2d<f32>, atlas: texture_2d<f32>, smp: sampler, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let cell = far_cell(probes, p, n, v);
    let row = cell.grid.counts.w;
    let within = (far_oct_encode(n) * 0.5 + 0.5) * FAR_IRR_RES + 1.0;
    let texel = far_irr_texel(probes);
    var e = vec3<f32>(0.0);
    var total = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let corner = far_corner(probes, visibility, smp, cell, c);
        if corner.w <= 0.0 {
            continue;
        }
        let tile = vec2<f32>(f32((corner.index % row) * FAR_IRR_TILE), f32((corner.index / row) * FAR_IRR_TILE));
        let uv = (tile + within) * texel;
        e += corner.w * textureSampleLevel(atlas, smp, uv, 0.0).rgb;
        total += corner.w;
    }
    return max(e / max(total, 1e-20), vec3<f32>(0.0));
}

// far_irradiance_at at a surface point of the frame, seen from the camera of `cam`.
fn far_irradiance_here(probes: texture_2d<f32>, visibility: texture_2d<f32>, atlas: texture_2d<f32>, smp: sampler, cam: View, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return far_irradiance_at(probes, visibility, atlas, smp, p, n, normalize(cam.camera_position.xyz - p));
}

// The far field at a surface point of the frame: world `p`, unit normal `n`, seen from the
// camera of `cam`.
fn far_sh_here(probes: texture_2d<f32>, visibility: texture_2d<f32>, smp: sampler, cam: View, p: vec3<f32>, n: vec3<f32>) -> FarSh {
    return far_sh_at(probes, visibility, smp, p, n, normalize(cam.camera_position.xyz - p));
}

// E(n)/π of the far field (Ramamoorthi & Hanrahan 2001, as env_irradiance_sh).
fn far_irradiance(f: FarSh, n: vec3<f32>) -> vec3<f32> {
    let b = sh_basis(n);
    var e = f.c[0].rgb * b[0];
    for (var i = 1u; i < 4u; i++) {
        e += f.c[i].rgb * (b[i] * (2.0 / 3.0));
    }
    for (var i = 4u; i < 9u; i++) {
        e += f.c[i].rgb * (b[i] * 0.25);
    }
    return max(e, vec3<f32>(0.0));
}

// Irradiance over π through the cone of half-angle acos(t) about unit `a` (env_irradiance_cone's
// factors; the volume has no band 3).
fn far_irradiance_cone(f: FarSh, a: vec3<f32>, t: f32) -> vec3<f32> {
    let b = sh_basis(a);
    let t2 = t * t;
    let k = vec3<f32>(1.0 - t2, (2.0 / 3.0) * (1.0 - t2 * t), 0.25 * (1.0 + 2.0 * t2 - 3.0 * t2 * t2));
    var e = f.c[0].rgb * (b[0] * k.x);
    for (var i = 1u; i < 4u; i++) {
        e += f.c[i].rgb * (b[i] * k.y);
    }
    for (var i = 4u; i < 9u; i++) {
        e += f.c[i].rgb * (b[i] * k.z);
    }
    return max(e, vec3<f32>(0.0));
}

// Radiance from direction `d`, unclamped: order 2 rings (negative lobes beside a bright sky
// opening), and a sum of weighted directions is only the SH's own integral when the negative
// parts stay in it. Clamping each direction at 0 made hbil's and vbgi's Sponza images 26–28 %
// too bright; callers clamp their sums.
fn far_radiance(f: FarSh, d: vec3<f32>) -> vec3<f32> {
    let b = sh_basis(d);
    var l = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        l += f.c[i].rgb * b[i];
    }
    return l;
}

// Σ w·Y_i(ω) over weighted directions ω (the first 9 of sh_basis). The radiance is linear in
// the basis, so Σ w·far_radiance(f, ω) = far_apply(f, Σ w·Y(ω)): a kernel that integrates the far
// field over many directions sums 9 numbers a direction and reads the volume's SH once, after
// its loops, instead of keeping 9 rgb coefficients live through them.
struct FarMoments {
    m: array<f32, 9>,
}

fn far_moments_add(acc: ptr<function, FarMoments>, d: vec3<f32>, w: f32) {
    let b = sh_basis(d);
    for (var i = 0u; i < 9u; i++) {
        (*acc).m[i] += b[i] * w;
    }
}

// Σ c_i·moments_i: the weighted sum of the radiance over the directions the moments were taken
// from (unclamped, as far_radiance).
fn far_apply(f: FarSh, acc: FarMoments) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        l += f.c[i].rgb * acc.m[i];
    }
    return l;
}

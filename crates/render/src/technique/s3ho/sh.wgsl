// sh.wgsl — `S3hoParams` and the SH helpers shared by the s3ho passes: clamped-cosine lobes,
// half-float packing of the 16 coefficients (technique/s3ho/mod.rs has the overview). A
// library (after env.wgsl): it declares no bindings; the passes bind `params: S3hoParams`.
//
// SH: real basis of nearfield_scene::sh (Sloan's "Stupid SH Tricks" polynomials without the
// Condon–Shortley phase, polar axis world z, index l(l+1)+m, orthonormality tested there), 4
// bands = 16 coefficients.

struct S3hoParams {
    radius: f32,
    // (Directions per pixel: the override SAMPLES.)
    _pad0: u32,
    pattern: u32,
    fade: f32,
    // (Ray-marching points per direction: the override STEPS.)
    _pad1: u32,
    // Smooth visibility weight (0: off).
    lambda: f32,
    // 0 s3ho, 1 ssbn.
    technique: u32,
    // Indirect extension on/off.
    indirect: u32,
    strength: f32,
    distance_clamp: f32,
    // Depth layers of the main view and additional cameras in the blocker test (passes/layers/).
    layers: u32,
    cameras: u32,
}

// Counts, fixed per pipeline (WGSL override constants; technique/s3ho/mod.rs sets them).
// Directions per pixel N.
override SAMPLES: u32 = 16u;
// Ray-marching points per direction.
override STEPS: u32 = 2u;

// Clamped-cosine band factors A_l (Funk–Hecke), bands 0..3.
fn cosine_band(l: u32) -> f32 {
    switch l {
        case 0u: { return PI; }
        case 1u: { return 2.0 * PI / 3.0; }
        case 2u: { return PI / 4.0; }
        default: { return 0.0; }
    }
}

fn band(i: u32) -> u32 {
    return select(select(select(3u, 2u, i < 9u), 1u, i < 4u), 0u, i < 1u);
}

// SH of the clamped cosine lobe about n.
fn sh_cosine(n: vec3<f32>) -> array<f32, 16> {
    var c = sh_basis(n);
    for (var i = 0u; i < 16u; i++) {
        c[i] *= cosine_band(band(i));
    }
    return c;
}

fn pack16(c: array<f32, 16>) -> array<vec4<u32>, 2> {
    var out: array<vec4<u32>, 2>;
    for (var k = 0u; k < 2u; k++) {
        let b = 8u * k;
        out[k] = vec4<u32>(
            pack2x16float(vec2<f32>(c[b], c[b + 1u])),
            pack2x16float(vec2<f32>(c[b + 2u], c[b + 3u])),
            pack2x16float(vec2<f32>(c[b + 4u], c[b + 5u])),
            pack2x16float(vec2<f32>(c[b + 6u], c[b + 7u])));
    }
    return out;
}

fn unpack16(a: vec4<u32>, b: vec4<u32>) -> array<f32, 16> {
    var c: array<f32, 16>;
    let words = array<u32, 8>(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w);
    for (var k = 0u; k < 8u; k++) {
        let v = unpack2x16float(words[k]);
        c[2u * k] = v.x;
        c[2u * k + 1u] = v.y;
    }
    return c;
}

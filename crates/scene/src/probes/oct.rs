//! The octahedral map of directions the probes' visibility and irradiance tiles are stored in,
//! with its one-texel border for bilinear filtering across the octahedron's edges.

use super::{VIS_RES, VIS_TILE};
use glam::{Vec2, Vec3};

/// Octahedral encoding of a unit direction into [−1, 1]² (z-up octahedron).
pub fn oct_encode(d: Vec3) -> Vec2 {
    let l1 = d.x.abs() + d.y.abs() + d.z.abs();
    let p = Vec2::new(d.x, d.y) / l1.max(1e-20);
    if d.z >= 0.0 {
        p
    } else {
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign_not_zero(p)
    }
}

/// The unit direction of an octahedral coordinate in [−1, 1]².
pub fn oct_decode(e: Vec2) -> Vec3 {
    let z = 1.0 - e.x.abs() - e.y.abs();
    let xy = if z < 0.0 {
        (Vec2::ONE - Vec2::new(e.y.abs(), e.x.abs())) * sign_not_zero(e)
    } else {
        e
    };
    Vec3::new(xy.x, xy.y, z).normalize()
}

fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

/// Solid angle (sr) of texel (x, y) of a `res`² octahedral map: its two spherical triangles.
pub fn oct_texel_solid_angle(x: u32, y: u32, res: u32) -> f32 {
    let r = res as f32;
    let corner = |i: u32, j: u32| {
        oct_decode(Vec2::new(
            i as f32 / r * 2.0 - 1.0,
            j as f32 / r * 2.0 - 1.0,
        ))
    };
    let (a, b, c, d) = (
        corner(x, y),
        corner(x + 1, y),
        corner(x + 1, y + 1),
        corner(x, y + 1),
    );
    let triangle = |a: Vec3, b: Vec3, c: Vec3| {
        2.0 * a
            .dot(b.cross(c))
            .abs()
            .atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
    };
    triangle(a, b, c) + triangle(a, c, d)
}

/// Direction of texel (x, y) of a [`VIS_RES`]² octahedral map (texel centres).
pub fn texel_direction(x: u32, y: u32) -> Vec3 {
    oct_texel_direction(x, y, VIS_RES)
}

/// Direction of texel (x, y) of a `res`² octahedral map (texel centres).
pub fn oct_texel_direction(x: u32, y: u32, res: u32) -> Vec3 {
    let r = res as f32;
    oct_decode(Vec2::new(
        (x as f32 + 0.5) / r * 2.0 - 1.0,
        (y as f32 + 0.5) / r * 2.0 - 1.0,
    ))
}

/// The interior texel a border texel (x, y) of a tile repeats (tile coordinates, 0 and
/// `VIS_TILE − 1` are the border): the octahedron folds each edge onto itself mirrored.
pub fn border_source(x: u32, y: u32) -> (u32, u32) {
    oct_border_source(x, y, VIS_RES)
}

/// [`border_source`] for a `res`² map with its border (`res + 2` texels a side).
pub fn oct_border_source(x: u32, y: u32, res: u32) -> (u32, u32) {
    let last = res + 1;
    let n = res;
    let ix = x.clamp(1, n) - 1;
    let iy = y.clamp(1, n) - 1;
    match (x == 0 || x == last, y == 0 || y == last) {
        // Corners: the diagonally opposite interior corner.
        (true, true) => (n - 1 - ix, n - 1 - iy),
        (true, false) => (ix, n - 1 - iy),
        (false, true) => (n - 1 - ix, iy),
        (false, false) => (ix, iy),
    }
}

/// Builds a bordered tile from the [`VIS_RES`]² interior moments (row-major).
pub fn bordered_tile(interior: &[[f32; 2]]) -> Vec<[f32; 2]> {
    let mut tile = Vec::with_capacity((VIS_TILE * VIS_TILE) as usize);
    for y in 0..VIS_TILE {
        for x in 0..VIS_TILE {
            let (sx, sy) = border_source(x, y);
            tile.push(interior[(sy * VIS_RES + sx) as usize]);
        }
    }
    tile
}

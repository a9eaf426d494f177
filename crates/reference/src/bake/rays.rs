//! The probes' rays: a spherical Fibonacci lattice turned by a per-probe random rotation, and
//! the 16-bit octahedral normals the bounce hits keep.

use crate::sampling::hash;
use glam::{Mat3, Quat, Vec2, Vec3};
use nearfield_scene::probes;
use std::f32::consts::PI;

pub(super) fn pack_normal(n: Vec3) -> [u16; 2] {
    let e = probes::oct_encode(n) * 0.5 + 0.5;
    [
        (e.x.clamp(0.0, 1.0) * 65535.0).round() as u16,
        (e.y.clamp(0.0, 1.0) * 65535.0).round() as u16,
    ]
}

pub(super) fn unpack_normal(p: [u16; 2]) -> Vec3 {
    probes::oct_decode(Vec2::new(p[0] as f32, p[1] as f32) / 65535.0 * 2.0 - 1.0)
}

/// The i-th of n directions on a spherical Fibonacci lattice.
pub(super) fn fibonacci(i: u32, n: u32) -> Vec3 {
    let golden = (5f32.sqrt() - 1.0) * 0.5;
    let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * (i as f32 * golden).fract();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The rotation probe `index`'s rays are turned by.
pub(super) fn probe_rotation(index: usize) -> Mat3 {
    let h = |k: u32| (hash(index as u32 ^ hash(k)) >> 8) as f32 / (1u32 << 24) as f32;
    // A uniform random rotation (Shoemake 1992).
    let (u1, u2, u3) = (h(1), h(2), h(3));
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let q = Quat::from_xyzw(
        a * (2.0 * PI * u2).sin(),
        a * (2.0 * PI * u2).cos(),
        b * (2.0 * PI * u3).sin(),
        b * (2.0 * PI * u3).cos(),
    );
    Mat3::from_quat(q.normalize())
}

/// The directions of probe `index`'s rays.
pub(super) fn directions(index: usize, rays: u32) -> Vec<Vec3> {
    let r = probe_rotation(index);
    (0..rays).map(|j| r * fibonacci(j, rays)).collect()
}

//! Deterministic per-pixel sample sequences: a 2D R2 low-discrepancy sequence (Roberts 2018)
//! with a per-pixel Cranley–Patterson rotation from a hash of (pixel, seed) for hemisphere
//! directions, and a PCG32 stream per pixel for path tracing's extra dimensions. Every pixel's
//! samples depend on its coordinates and the seed only, so results do not depend on the thread
//! count or the order of work.

use glam::{Vec2, Vec3};

/// PCG-style integer hash (Jarzynski & Olano 2020, "pcg" hash).
pub fn hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

pub fn pixel_seed(x: u32, y: u32, seed: u32) -> u32 {
    hash(x ^ hash(y ^ hash(seed)))
}

fn unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The i-th point of the R2 sequence rotated by `offset` (toroidally).
pub fn r2(i: u32, offset: Vec2) -> Vec2 {
    const G: f64 = 1.324_717_957_244_746;
    const A1: f64 = 1.0 / G;
    const A2: f64 = 1.0 / (G * G);
    let x = (offset.x as f64 + A1 * i as f64).fract();
    let y = (offset.y as f64 + A2 * i as f64).fract();
    Vec2::new(x as f32, y as f32)
}

/// Per-pixel rotation of the R2 sequence.
pub fn r2_offset(pixel_seed: u32) -> Vec2 {
    Vec2::new(unit(hash(pixel_seed)), unit(hash(pixel_seed ^ 0x9e37_79b9)))
}

/// Cosine-weighted direction on the hemisphere around unit `n` (pdf cos θ / π).
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = std::f32::consts::TAU * u.y;
    let (t, b) = orthonormal_basis(n);
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u.x).max(0.0).sqrt()).normalize()
}

/// Tangent and bitangent completing unit `n` (Duff et al. 2017).
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// PCG32 (O'Neill 2014).
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    pub fn next_f32(&mut self) -> f32 {
        unit(self.next_u32())
    }

    pub fn next_vec2(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cosine_samples_have_mean_cosine_two_thirds() {
        // E[cos θ] under pdf cos θ / π is 2/3.
        let n = Vec3::new(0.3, 0.5, -0.8).normalize();
        let off = r2_offset(7);
        let m: f32 = (0..4096)
            .map(|i| cosine_hemisphere(n, r2(i, off)).dot(n))
            .sum::<f32>()
            / 4096.0;
        assert!((m - 2.0 / 3.0).abs() < 2e-3, "{m}");
        let (t, b) = orthonormal_basis(n);
        assert!(t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6 && t.dot(b).abs() < 1e-6);
    }
}

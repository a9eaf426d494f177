//! Where the probes of a volume stand: a regular grid over the scene's bounds.
//!
//! Placement (the book, "The far field"): the bounds are cut into `counts` equal cells per axis
//! and one probe stands at the centre of each cell, so that no probe sits on a bounding plane
//! (where floors and walls usually are). `--spacing M` asks for cells of at most M metres;
//! `--probes X,Y,Z` asks for the counts. The default (`nearfield_reference::bake::default_grid`)
//! asks for about [`DEFAULT_PROBES`] probes, more for detailed scenes, with every axis at least
//! 1/16 of the longest one so that a flat scene (a plane) still gets a layer. Probes that land inside geometry are moved or switched off
//! by the bake (`nearfield_reference::bake`).

use crate::Aabb;
use glam::Vec3;

/// Probes in one volume, at most (the documented probe budget).
pub const MAX_PROBES: usize = 65_536;
/// Most probes of the default grid (its spacing grows beyond [`DEFAULT_SPACING`] to stay
/// within): about 50 MB of volume on the GPU.
pub const DEFAULT_PROBES: f32 = 16384.0;
/// The default distance between probes (m): one probe per metre, the scale at which engines
/// keep irradiance volumes for interiors.
pub const DEFAULT_SPACING: f32 = 1.0;

/// A regular grid of probes: probe (i, j, k) stands at `origin + (i, j, k) · spacing`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeGrid {
    /// Position of probe (0, 0, 0) (m).
    pub origin: Vec3,
    /// Distance between neighbouring probes per axis (m, > 0).
    pub spacing: Vec3,
    /// Probes per axis (≥ 1 each).
    pub counts: [u32; 3],
}

/// Why a grid cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GridError {
    #[error("--spacing {0}: must be a finite number of metres > 0")]
    Spacing(f32),
    #[error("--probes {},{},{}: each count must be at least 1", .0[0], .0[1], .0[2])]
    Counts([u32; 3]),
    #[error(
        "the grid has {count} probes ({}×{}×{}); the probe budget is {MAX_PROBES} (a larger --spacing or fewer --probes fit)",
        .counts[0], .counts[1], .counts[2]
    )]
    Budget { count: u64, counts: [u32; 3] },
    #[error("the scene is empty: a probe volume needs geometry")]
    Empty,
}

impl ProbeGrid {
    /// The spacing (m) that cuts `bounds` into about `probes` cells of equal sides (every axis
    /// counted at least 1/16 of the longest, so that a flat scene gets one layer), never finer
    /// than what the probe budget holds.
    pub fn default_spacing(bounds: Aabb, probes: f32) -> f32 {
        let e = bounds.extent().max(Vec3::splat(1e-6));
        let floor = e.max_element() / 16.0;
        let v = e.max(Vec3::splat(floor));
        let volume = v.x * v.y * v.z;
        let by_count = (volume / probes.max(1.0)).cbrt();
        // 0.8 of the budget: ceil() per axis adds up to a cell per axis.
        let by_budget = (volume / (0.8 * MAX_PROBES as f32)).cbrt();
        by_count.max(by_budget)
    }

    /// Cells of at most `spacing` metres over `bounds`, one probe at each cell's centre.
    pub fn with_spacing(bounds: Aabb, spacing: f32) -> Result<Self, GridError> {
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(GridError::Spacing(spacing));
        }
        if bounds.is_empty() {
            return Err(GridError::Empty);
        }
        let e = bounds.extent();
        let count = |x: f32| -> u64 { ((x / spacing).ceil() as u64).max(1) };
        let c = [count(e.x), count(e.y), count(e.z)];
        let total = c[0].saturating_mul(c[1]).saturating_mul(c[2]);
        let clamp = |x: u64| x.min(u32::MAX as u64) as u32;
        let counts = [clamp(c[0]), clamp(c[1]), clamp(c[2])];
        if total > MAX_PROBES as u64 {
            return Err(GridError::Budget {
                count: total,
                counts,
            });
        }
        Self::with_counts(bounds, counts)
    }

    /// `counts` cells over `bounds`, one probe at each cell's centre.
    pub fn with_counts(bounds: Aabb, counts: [u32; 3]) -> Result<Self, GridError> {
        if counts.contains(&0) {
            return Err(GridError::Counts(counts));
        }
        if bounds.is_empty() {
            return Err(GridError::Empty);
        }
        let total = counts.iter().map(|&c| c as u64).product::<u64>();
        if total > MAX_PROBES as u64 {
            return Err(GridError::Budget {
                count: total,
                counts,
            });
        }
        let e = bounds.extent();
        let n = Vec3::new(counts[0] as f32, counts[1] as f32, counts[2] as f32);
        // A flat axis (a plane) gets cells as deep as the other axes' finest, centred on it.
        let finest = (e / n).max_element().max(1e-4);
        let cell = Vec3::select((e / n).cmpgt(Vec3::splat(1e-6)), e / n, Vec3::splat(finest));
        let min = bounds.center() - 0.5 * cell * n;
        Ok(ProbeGrid {
            origin: min + 0.5 * cell,
            spacing: cell,
            counts,
        })
    }

    pub fn count(&self) -> usize {
        self.counts.iter().map(|&c| c as usize).product()
    }

    /// Linear index of probe (i, j, k): x fastest, then y, then z.
    pub fn index(&self, [i, j, k]: [u32; 3]) -> usize {
        let [nx, ny, _] = self.counts;
        (i + nx * (j + ny * k)) as usize
    }

    /// Grid coordinates of linear index `index`.
    pub fn coords(&self, index: usize) -> [u32; 3] {
        let [nx, ny, _] = self.counts;
        let i = index as u32;
        [i % nx, (i / nx) % ny, i / (nx * ny)]
    }

    /// Where probe `index` stands before any relocation.
    pub fn position(&self, index: usize) -> Vec3 {
        let [i, j, k] = self.coords(index);
        self.origin + self.spacing * Vec3::new(i as f32, j as f32, k as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(e: f32) -> Aabb {
        Aabb {
            min: Vec3::ZERO,
            max: Vec3::splat(e),
        }
    }

    #[test]
    fn cell_centred_within_the_bounds() {
        let g = ProbeGrid::with_spacing(cube(2.0), 0.5).unwrap();
        assert_eq!(g.counts, [4, 4, 4]);
        assert_eq!(g.position(0), Vec3::splat(0.25));
        assert_eq!(g.position(g.count() - 1), Vec3::splat(1.75));
        for i in 0..g.count() {
            assert_eq!(g.index(g.coords(i)), i);
        }
    }

    #[test]
    fn spacing_is_an_upper_bound() {
        let b = Aabb {
            min: Vec3::new(-1.0, 0.0, 0.0),
            max: Vec3::new(2.0, 1.0, 0.7),
        };
        let g = ProbeGrid::with_spacing(b, 0.4).unwrap();
        assert_eq!(g.counts, [8, 3, 2]);
        assert!(g.spacing.max_element() <= 0.4);
    }

    #[test]
    fn flat_scene_gets_one_layer() {
        let b = Aabb {
            min: Vec3::new(-5.0, 0.0, -5.0),
            max: Vec3::new(5.0, 0.0, 5.0),
        };
        let g = ProbeGrid::with_spacing(b, ProbeGrid::default_spacing(b, DEFAULT_PROBES)).unwrap();
        assert_eq!(g.counts[1], 1);
        assert!(g.spacing.y > 0.0);
        assert!((g.count() as f32) < 2.0 * DEFAULT_PROBES);
    }

    #[test]
    fn default_spacing_gives_about_the_target() {
        let g = ProbeGrid::with_spacing(
            cube(3.0),
            ProbeGrid::default_spacing(cube(3.0), DEFAULT_PROBES),
        )
        .unwrap();
        let n = g.count() as f32;
        assert!(
            (0.8 * DEFAULT_PROBES..=1.3 * DEFAULT_PROBES).contains(&n),
            "{n}"
        );
    }

    #[test]
    fn bad_grids_are_refused() {
        assert_eq!(
            ProbeGrid::with_spacing(cube(1.0), 0.0),
            Err(GridError::Spacing(0.0))
        );
        assert!(ProbeGrid::with_spacing(cube(1.0), -1.0).is_err());
        assert!(ProbeGrid::with_spacing(cube(1.0), f32::NAN).is_err());
        assert!(matches!(
            ProbeGrid::with_spacing(cube(100.0), 0.01),
            Err(GridError::Budget { .. })
        ));
        assert!(ProbeGrid::with_counts(cube(1.0), [0, 1, 1]).is_err());
        assert!(matches!(
            ProbeGrid::with_counts(cube(1.0), [100, 100, 100]),
            Err(GridError::Budget { .. })
        ));
        assert_eq!(
            ProbeGrid::with_spacing(Aabb::EMPTY, 1.0),
            Err(GridError::Empty)
        );
    }
}

//! A technique's frames as `compare` runs them: the camera still, turned (`--orbit`) or moved
//! along a path (`--path`, `--walk`), the history carried from frame to frame as an application
//! carries it. A still camera measures the convergence; a path measures every K-th frame
//! (`--every`) against the reference traced from that frame's camera.

use super::CompareArgs;
use super::judge::Judge;
use crate::options::{Loaded, Motion};
use anyhow::Result;
use nearfield_eval::metrics::{self, Mask};
use nearfield_eval::report::ConvergencePoint;
use nearfield_reference::{ReferenceImage, ReferenceSettings};
use nearfield_render::{Aov, AovImage, Renderer};
use nearfield_scene::Camera;

/// How many frames a technique renders and how its camera moves.
pub(super) struct Run {
    pub motion: Motion,
    pub frames: u32,
    /// The first frame's camera.
    first: Camera,
}

/// The references of the measured frames of a path: (frame index, reference).
pub(super) type Along = Vec<(u32, ReferenceImage)>;

/// A mask of a technique's image against one reference.
type MaskAgainst<'a> = &'a dyn Fn(&mut Renderer, &AovImage, &ReferenceImage) -> Mask;

impl Run {
    /// `frames` (`--frames`; default 1, or the path's) from `first`.
    pub fn new(motion: Motion, frames: Option<u32>, first: Camera) -> Self {
        let frames = frames.unwrap_or(match &motion {
            Motion::Path(p) => p.frames(),
            Motion::Orbit(_) => 1,
        });
        Run {
            motion,
            frames,
            first,
        }
    }

    /// The camera of frame `index`.
    pub fn camera(&self, index: u32) -> Camera {
        self.motion.camera(self.first, index)
    }

    /// The frames of a path that are measured: every `every`-th and the last.
    fn measured(&self, every: u32) -> Vec<u32> {
        if !matches!(self.motion, Motion::Path(_)) {
            return Vec::new();
        }
        (0..self.frames)
            .filter(|i| (i + 1) % every == 0 || i + 1 == self.frames)
            .collect()
    }

    /// Runs the frames of a technique; its last frame's AOV and mask, the convergence (a still
    /// camera with more than one frame) and the error of each measured frame of a path
    /// (against `along`'s references, each masked with `mask_against`).
    pub fn frames(
        &self,
        r: &mut Renderer,
        gpu_aov: Aov,
        judge: &Judge,
        mask_of: &dyn Fn(&mut Renderer, &AovImage) -> Mask,
        (along, mask_against): (&Along, MaskAgainst),
    ) -> Result<(AovImage, Mask, Vec<ConvergencePoint>, Vec<ConvergencePoint>)> {
        let still = self.motion.still() && self.frames > 1;
        let (mut convergence, mut path) = (Vec::new(), Vec::new());
        let mut mask = None;
        let mut next = along.iter().peekable();
        for i in 0..self.frames {
            self.motion.frame(r, i);
            if i % 8 == 7 {
                r.wait();
            }
            judge.progress.inc(1);
            let n = i + 1;
            if still && (self.frames <= 64 || n.is_power_of_two() || n == self.frames) {
                let value = r.read_aov(gpu_aov);
                let mask = mask.get_or_insert_with(|| mask_of(r, &value));
                let m = metrics::metrics(&value.pixels, &judge.reference.value, mask);
                convergence.push(ConvergencePoint {
                    frames: n,
                    rmse: m.rmse,
                    relative_error: m.relative_error,
                });
            }
            if let Some((_, truth)) = next.next_if(|(j, _)| *j == i) {
                let value = r.read_aov(gpu_aov);
                let m =
                    metrics::metrics(&value.pixels, &truth.value, &mask_against(r, &value, truth));
                path.push(ConvergencePoint {
                    frames: n,
                    rmse: m.rmse,
                    relative_error: m.relative_error,
                });
            }
        }
        let value = r.read_aov(gpu_aov);
        r.check_device()?;
        let mask = match mask {
            Some(m) => m,
            None => mask_of(r, &value),
        };
        Ok((value, mask, convergence, path))
    }
}

/// The references of a path's measured frames, each from its frame's camera (traced, or read from
/// the cache); none for a still or turning camera. `loaded`'s camera is the last frame's again
/// afterwards.
pub(super) fn path_truth(
    args: &CompareArgs,
    loaded: &mut Loaded,
    run: &Run,
    settings: &ReferenceSettings,
) -> Result<Along> {
    let measured = run.measured(args.every);
    let mut out = Vec::with_capacity(measured.len());
    for (k, i) in measured.iter().enumerate() {
        loaded.camera = run.camera(*i);
        eprintln!(
            "nearfield: reference of frame {} of {} ({} of {} measured)",
            i + 1,
            run.frames,
            k + 1,
            measured.len()
        );
        let (img, _) = crate::reference::compute(&args.scene, &args.reference, loaded, settings)?;
        out.push((*i, img));
    }
    loaded.camera = run.camera(run.frames - 1);
    Ok(out)
}

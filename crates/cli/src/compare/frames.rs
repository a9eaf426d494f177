//! A technique's frames as `compare` runs them: the camera still, turned (`--orbit`) or moved
//! along a path (`--path`, `--walk`), the history carried from frame to frame as an application
//! carries it. A still camera measures the convergence; a path measures every K-th frame
//! (`--every`) against the reference traced from that frame's camera.

use super::CompareArgs;
use super::judge::Judge;
use crate::options::{Loaded, Motion};
use anyhow::Result;
use nearfield_eval::metrics::{self, FrameChange, Mask};
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

/// What a technique's frames give: its last frame's AOV and mask, the convergence (a still
/// camera), and along a path the error of each measured frame and the motion-compensated change
/// of the technique and of the reference over consecutive measured frames.
pub(super) struct Frames {
    pub value: AovImage,
    pub mask: Mask,
    pub convergence: Vec<ConvergencePoint>,
    pub path: Vec<ConvergencePoint>,
    pub change: Option<(FrameChange, FrameChange)>,
}

/// The frames of a still camera's run at a view of the path, measured against its reference.
const STILL_FRAMES: u32 = 16;

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

    /// Runs the frames of a technique ([`Frames`]); along a path each measured frame is judged
    /// against `along`'s reference, masked with `mask_against`.
    pub fn frames(
        &self,
        r: &mut Renderer,
        gpu_aov: Aov,
        judge: &Judge,
        mask_of: &dyn Fn(&mut Renderer, &AovImage) -> Mask,
        (along, mask_against): (&Along, MaskAgainst),
    ) -> Result<Frames> {
        let still = self.motion.still() && self.frames > 1;
        let (mut convergence, mut path) = (Vec::new(), Vec::new());
        let mut mask = None;
        let mut next = along.iter().enumerate().peekable();
        // The last measured frame: its index in `along`, the technique's image and its mask.
        let mut prev: Option<(usize, AovImage, Mask)> = None;
        let mut change: Option<(FrameChange, FrameChange)> = None;
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
            if let Some((k, (_, truth))) = next.next_if(|(_, (j, _))| *j == i) {
                let value = r.read_aov(gpu_aov);
                let m_now = mask_against(r, &value, truth);
                let m = metrics::metrics(&value.pixels, &truth.value, &m_now);
                path.push(ConvergencePoint {
                    frames: n,
                    rmse: m.rmse,
                    relative_error: m.relative_error,
                });
                if let Some((pk, pv, pm)) = &prev
                    && along[*pk].0 + 1 == i
                {
                    let motion = r.read_aov(Aov::Motion).pixels;
                    let before = &along[*pk].1;
                    let t = metrics::frame_change(
                        (&value.pixels, &m_now),
                        (&pv.pixels, pm),
                        &motion,
                        None,
                    );
                    let stderr = (truth.stderr.as_slice(), before.stderr.as_slice());
                    let rc = metrics::frame_change(
                        (&truth.value, &m_now),
                        (&before.value, pm),
                        &motion,
                        Some(stderr),
                    );
                    let c = change.get_or_insert_default();
                    c.0 += t;
                    c.1 += rc;
                }
                prev = Some((k, value, m_now));
            }
        }
        let value = r.read_aov(gpu_aov);
        r.check_device()?;
        let mask = match mask {
            Some(m) => m,
            None => mask_of(r, &value),
        };
        Ok(Frames {
            value,
            mask,
            convergence,
            path,
            change,
        })
    }

    /// The mean error of a still camera after [`STILL_FRAMES`] frames at up to eight evenly
    /// spaced measured views of the path (`make`: a fresh renderer of the technique), each
    /// against its reference: the error the path's frames are held to.
    pub fn still_error(
        &self,
        make: &dyn Fn() -> Result<Renderer>,
        gpu_aov: Aov,
        (along, mask_against): (&Along, MaskAgainst),
    ) -> Result<Option<f64>> {
        if along.is_empty() {
            return Ok(None);
        }
        let step = along.len().div_ceil(8);
        let mut sum = 0.0;
        let mut n = 0;
        for (j, truth) in along.iter().step_by(step) {
            let mut r = make()?;
            r.set_camera(self.camera(*j));
            for _ in 0..STILL_FRAMES {
                r.render_frame();
            }
            let value = r.read_aov(gpu_aov);
            let mask = mask_against(&mut r, &value, truth);
            sum += metrics::metrics(&value.pixels, &truth.value, &mask).relative_error;
            n += 1;
        }
        Ok(Some(sum / n as f64))
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

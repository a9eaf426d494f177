//! A technique's frames as `compare` runs them: the camera still, turned (`--orbit`) or moved
//! along a path (`--path`, `--walk`), the history carried from frame to frame as an application
//! carries it. A still camera measures the convergence; a path measures every K-th frame
//! (`--every`) against the reference traced from that frame's camera.

use super::CompareArgs;
use super::judge::Judge;
use crate::options::{Loaded, Motion};
use anyhow::Result;
use nearfield_eval::metrics::{self, FrameChange, Mask};
use nearfield_eval::report::{ConvergencePoint, MethodReport};
use nearfield_reference::{ReferenceImage, ReferenceSettings};
use nearfield_render::{Aov, AovImage, Renderer};
use nearfield_scene::Camera;

/// How many frames a technique renders and how its camera moves.
pub(super) struct Run {
    pub motion: Motion,
    pub frames: u32,
    /// The first frame's camera.
    first: Camera,
    /// How the scene's objects move (empty: nothing moves).
    animation: nearfield_scene::Animation,
}

/// A measured frame of a path: its index, its reference, and (where the instability is measured,
/// [`Run::changes`]) the reference traced again with another seed, whose noise is independent
/// of the first's ([`metrics::FrameChange::cross`]).
pub(super) struct Measured {
    pub frame: u32,
    pub truth: ReferenceImage,
    pub twin: Option<ReferenceImage>,
}

/// The references of the measured frames of a path.
pub(super) type Along = Vec<Measured>;

/// A path's measured frames as the report shows them: (frame index, image).
pub(super) type Shown = Vec<(u32, image::RgbImage)>;

/// The motion-compensated change of the technique and of the reference over consecutive
/// measured frames.
pub(super) type Change = Option<(FrameChange, FrameChange)>;

/// What a technique's frames give: its last frame's AOV and mask, the convergence (a still
/// camera), and along a path the error of each measured frame and the motion-compensated change
/// of the technique and of the reference over consecutive measured frames.
pub(super) struct Frames {
    pub value: AovImage,
    pub mask: Mask,
    pub convergence: Vec<ConvergencePoint>,
    pub path: Vec<ConvergencePoint>,
    pub change: Change,
    /// Along a path: each measured frame as the report shows it, with its index.
    pub shown: Shown,
}

/// The frames of a still camera's run at a view of the path, measured against its reference.
const STILL_FRAMES: u32 = 16;

/// The frames after a cut (or after the objects stop) over which a technique's settling is
/// measured: the error of frames 17–32 after it is its settled value (frames 17 to the path's
/// end where it ends sooner, if that is at least [`SETTLE_TAIL`] frames).
const SETTLE_WINDOW: u32 = 32;
/// The fewest frames the settled value is the mean of.
const SETTLE_TAIL: u32 = 8;

impl Run {
    /// `frames` (`--frames`; default 1, or the path's) from `first` over `scene`.
    pub fn new(
        motion: Motion,
        frames: Option<u32>,
        first: Camera,
        scene: &nearfield_scene::Scene,
    ) -> Self {
        let frames = frames.unwrap_or(match &motion {
            Motion::Path(p) => p.frames(),
            Motion::Orbit { .. } => 1,
        });
        let animation = if scene.moves() {
            scene.animation.clone()
        } else {
            Default::default()
        };
        Run {
            motion,
            frames,
            first,
            animation,
        }
    }

    /// The camera of frame `index`.
    pub fn camera(&self, index: u32) -> Camera {
        self.motion.camera(self.first, index)
    }

    /// The scene's time at frame `index` (s).
    pub fn time(&self, index: u32) -> f32 {
        self.motion.time(index)
    }

    /// The frames of a path that are measured: every `every`-th, the last, and the
    /// [`SETTLE_WINDOW`] frames after each cut and after each time the objects stop.
    fn measured(&self, every: u32) -> Vec<u32> {
        if !matches!(self.motion, Motion::Path(_)) {
            return Vec::new();
        }
        let events = [self.cuts(), self.stops()].concat();
        (0..self.frames)
            .filter(|i| {
                (i + 1) % every == 0
                    || i + 1 == self.frames
                    || events.iter().any(|c| (*c..c + SETTLE_WINDOW).contains(i))
            })
            .collect()
    }

    /// Whether the camera of frame `i` is not that of frame `i − 1` (beyond rounding), or an
    /// object moved between them.
    fn moved(&self, i: u32) -> bool {
        let (a, b) = (self.camera(i - 1), self.camera(i));
        let scale = (a.target - a.eye).length().max(1e-6);
        (b.eye - a.eye).length() + (b.target - a.target).length() > 1e-5 * scale
            || (b.yfov - a.yfov).abs() > 1e-6
            || self.animation.moved_between(self.time(i - 1), self.time(i))
    }

    /// Whether measured frames `prev` and `i` are consecutive and something moved between them:
    /// the pairs whose change from frame to frame the instability figure sums.
    fn changes(&self, prev: u32, i: u32) -> bool {
        prev + 1 == i && self.moved(i)
    }

    /// The frames of a path whose camera jumps from the frame before's (a cut: the history is
    /// discarded).
    pub fn cuts(&self) -> Vec<u32> {
        if !matches!(self.motion, Motion::Path(_)) {
            return Vec::new();
        }
        (1..self.frames)
            .filter(|i| self.camera(i - 1).is_cut_to(&self.camera(*i)))
            .collect()
    }

    /// The frames at which the scene's moving objects come to rest: each frame that moved from
    /// the frame before while the next does not move from it. What they uncovered last changed
    /// there; from there on a technique's history settles (the disocclusion's ghost fades).
    pub fn stops(&self) -> Vec<u32> {
        let moved = |i: u32| self.animation.moved_between(self.time(i - 1), self.time(i));
        (1..self.frames.saturating_sub(1))
            .filter(|&s| moved(s) && !moved(s + 1))
            .collect()
    }

    /// The frames a technique takes to settle after each cut ([`Self::settle_after`]).
    pub fn settle(&self, path: &[ConvergencePoint]) -> Vec<u32> {
        self.settle_after(&self.cuts(), path)
    }

    /// The frames a technique takes to settle after each time the objects stop
    /// ([`Self::stops`], [`Self::settle_after`]).
    pub fn settle_stops(&self, path: &[ConvergencePoint]) -> Vec<u32> {
        self.settle_after(&self.stops(), path)
    }

    /// The frames a technique takes to settle after each of `events`: the first frame from the
    /// event on whose error is within 5 % of the settled value (the mean error of frames 17–32
    /// after it, [`SETTLE_WINDOW`]), counting the event's own frame as 1. An event too close to
    /// the path's end for [`SETTLE_TAIL`] settled frames is left out.
    fn settle_after(&self, events: &[u32], path: &[ConvergencePoint]) -> Vec<u32> {
        let error = |i: u32| {
            path.iter()
                .find(|p| p.frames == i + 1)
                .map(|p| p.relative_error)
        };
        let mut out = Vec::new();
        for &c in events {
            let (start, end) = (c + SETTLE_WINDOW / 2, (c + SETTLE_WINDOW).min(self.frames));
            if end < start + SETTLE_TAIL {
                continue;
            }
            let tail: Option<Vec<f64>> = (start..end).map(error).collect();
            let Some(tail) = tail else { continue };
            let settled = tail.iter().sum::<f64>() / tail.len() as f64;
            let k = (0..end - c)
                .find(|k| error(c + k).is_some_and(|e| e <= 1.05 * settled))
                .unwrap_or(end - c - 1);
            out.push(k + 1);
        }
        out
    }

    /// Runs the frames of a technique ([`Frames`]); along a path each measured frame is judged
    /// against `along`'s reference, masked with `mask_against`.
    pub fn frames(
        &self,
        (method, r): (&str, &mut Renderer),
        gpu_aov: Aov,
        judge: &Judge,
        along: &Along,
    ) -> Result<Frames> {
        let still = self.motion.still() && self.frames > 1;
        let (mut convergence, mut path) = (Vec::new(), Vec::new());
        let mut mask = None;
        let mut next = along.iter().enumerate().peekable();
        // The last measured frame: its index in `along`, the technique's image and its mask.
        let mut prev: Option<(usize, AovImage, Mask)> = None;
        let mut change: Option<(FrameChange, FrameChange)> = None;
        let mut shown = Vec::new();
        for i in 0..self.frames {
            self.motion.frame(r, i);
            if i % 8 == 7 {
                r.wait();
            }
            judge.progress.inc(1);
            let n = i + 1;
            if still && (self.frames <= 64 || n.is_power_of_two() || n == self.frames) {
                let value = r.read_aov(gpu_aov);
                let mask = mask.get_or_insert_with(|| judge.mask_of(r, &value));
                let m = metrics::metrics(&value.pixels, &judge.reference.value, mask);
                convergence.push(ConvergencePoint {
                    frames: n,
                    rmse: m.rmse,
                    relative_error: m.relative_error,
                });
            }
            if let Some((k, Measured { truth, .. })) = next.next_if(|(_, m)| m.frame == i) {
                let value = r.read_aov(gpu_aov);
                let m_now = judge.mask_against(r, &value, truth);
                let m = metrics::metrics(&value.pixels, &truth.value, &m_now);
                shown.push((
                    i,
                    judge.frame_pngs(method, n, &value.pixels, truth, &m_now)?,
                ));
                path.push(ConvergencePoint {
                    frames: n,
                    rmse: m.rmse,
                    relative_error: m.relative_error,
                });
                // Consecutive measured frames whose camera or objects moved: a still scene's
                // frames show no motion to compensate (and a reference that does not change).
                if let Some((pk, pv, pm)) = &prev
                    && self.changes(along[*pk].frame, i)
                {
                    let motion = r.read_aov(Aov::Motion).pixels;
                    let before = &along[*pk];
                    let t = metrics::frame_change(
                        (&value.pixels, &m_now),
                        (&pv.pixels, pm),
                        &motion,
                        None,
                    );
                    let twin = along[k].twin.as_ref().zip(before.twin.as_ref());
                    let rc = metrics::frame_change(
                        (&truth.value, &m_now),
                        (&before.truth.value, pm),
                        &motion,
                        twin.map(|(a, b)| (a.value.as_slice(), b.value.as_slice())),
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
            None => judge.mask_of(r, &value),
        };
        Ok(Frames {
            value,
            mask,
            convergence,
            path,
            change,
            shown,
        })
    }

    /// A method's figures along the path into `report`: its per-frame errors, the still
    /// camera's error ([`Self::still_error`]), its instability (from `change`) and its frames to
    /// settle after each cut and after each time the objects stop.
    pub fn figures(
        &self,
        report: &mut MethodReport,
        (path, change, shown): (Vec<ConvergencePoint>, Change, Shown),
        make: &dyn Fn() -> Result<Renderer>,
        (gpu_aov, judge, along): (Aov, &Judge, &Along),
    ) -> Result<()> {
        report.path_still = self.still_error(make, (gpu_aov, judge), along)?;
        report.instability = change.map(|(t, r)| metrics::instability(t, r));
        (report.video_jod, report.video_frames) = self.video(&report.name, shown, judge, along);
        report.settle = self.settle(&path);
        report.settle_stops = self.settle_stops(&path);
        report.path = path;
        Ok(())
    }

    /// ColorVideoVDP's JOD of the technique's frames against the reference's over the longest
    /// run of consecutive measured frames (`--every 1` measures them all), played at the path's
    /// frame rate, and the run's length; none where no two measured frames are consecutive or
    /// the metric refuses the run (one line says why).
    fn video(
        &self,
        method: &str,
        shown: Shown,
        judge: &Judge,
        along: &Along,
    ) -> (Option<f64>, Option<u32>) {
        let Motion::Path(p) = &self.motion else {
            return (None, None);
        };
        // The longest run of consecutive frame indices: [start, start + len) in `shown`.
        let (mut best, mut start) = ((0, 0), 0);
        for k in 0..shown.len() {
            if k > 0 && shown[k].0 != shown[k - 1].0 + 1 {
                start = k;
            }
            if k + 1 - start > best.1 {
                best = (start, k + 1 - start);
            }
        }
        if best.1 < 2 {
            return (None, None);
        }
        let run = &shown[best.0..best.0 + best.1];
        let test: Vec<image::RgbImage> = run.iter().map(|(_, im)| im.clone()).collect();
        let reference: Vec<image::RgbImage> = run
            .iter()
            .map(|(i, _)| {
                let m = along.iter().find(|m| m.frame == *i);
                judge.srgb(&m.expect("a measured frame's reference").truth.value)
            })
            .collect();
        match nearfield_eval::video::jod(&test, &reference, p.fps) {
            Ok(j) => (Some(j), Some(best.1 as u32)),
            Err(e) => {
                judge
                    .progress
                    .suspend(|| eprintln!("nearfield: {method}: no ColorVideoVDP score: {e}"));
                (None, None)
            }
        }
    }

    /// The mean error of a still camera after [`STILL_FRAMES`] frames at up to eight evenly
    /// spaced measured views of the path (`make`: a fresh renderer of the technique), each
    /// against its reference: the error the path's frames are held to.
    pub fn still_error(
        &self,
        make: &dyn Fn() -> Result<Renderer>,
        (gpu_aov, judge): (Aov, &Judge),
        along: &Along,
    ) -> Result<Option<f64>> {
        if along.is_empty() {
            return Ok(None);
        }
        let step = along.len().div_ceil(8);
        let mut sum = 0.0;
        let mut n = 0;
        for Measured {
            frame: j, truth, ..
        } in along.iter().step_by(step)
        {
            let mut r = make()?;
            r.set_camera(self.camera(*j));
            r.set_time(self.time(*j));
            for _ in 0..STILL_FRAMES {
                r.render_frame();
            }
            let value = r.read_aov(gpu_aov);
            let mask = judge.mask_against(&mut r, &value, truth);
            sum += metrics::metrics(&value.pixels, &truth.value, &mask).relative_error;
            n += 1;
        }
        Ok(Some(sum / n as f64))
    }
}

/// The references of a path's measured frames, each from its frame's camera (traced, or read from
/// the cache); none for a still or turning camera. A frame of a pair whose change the instability
/// sums ([`Run::changes`]) is traced a second time with the next seed. `loaded`'s camera is the
/// last frame's again afterwards.
pub(super) fn path_truth(
    args: &CompareArgs,
    loaded: &mut Loaded,
    run: &Run,
    settings: &ReferenceSettings,
) -> Result<Along> {
    let measured = run.measured(args.every);
    let paired = |k: usize| {
        let i = measured[k];
        (k > 0 && run.changes(measured[k - 1], i))
            || measured.get(k + 1).is_some_and(|&n| run.changes(i, n))
    };
    let twin_settings = ReferenceSettings {
        seed: settings.seed.wrapping_add(1),
        ..*settings
    };
    let mut out = Vec::with_capacity(measured.len());
    for (k, &i) in measured.iter().enumerate() {
        loaded.camera = run.camera(i);
        loaded.scene.pose(run.time(i));
        let twin = paired(k);
        eprintln!(
            "nearfield: reference of frame {} of {} ({} of {} measured{})",
            i + 1,
            run.frames,
            k + 1,
            measured.len(),
            if twin { ", and with the next seed" } else { "" }
        );
        let trace = |s: &ReferenceSettings| {
            crate::reference::compute(&args.scene, &args.reference, loaded, s).map(|(img, _)| img)
        };
        out.push(Measured {
            frame: i,
            truth: trace(settings)?,
            twin: twin.then(|| trace(&twin_settings)).transpose()?,
        });
    }
    loaded.camera = run.camera(run.frames - 1);
    loaded.scene.pose(run.time(run.frames - 1));
    Ok(out)
}

/// The summary of a method's path: its per-frame error's mean, 95th percentile and largest, each
/// against the still camera's, and its instability.
pub(super) fn path_line(m: &nearfield_eval::report::MethodReport) -> String {
    let (mean, p95, max) = nearfield_eval::report::path_summary(&m.path);
    let settled = nearfield_eval::report::path_largest_settled(&m.path);
    let still = m.path_still.unwrap_or(f64::NAN);
    let mut line = format!(
        "{:<10} along the path: {} frames, relative error mean {mean:.4} ({:.2}× still {still:.4}), 95th percentile {p95:.4}, largest {max:.4}, after frame 16 {settled:.4} ({:.2}× still)",
        m.name,
        m.path.len(),
        mean / still,
        settled / still
    );
    if let Some(i) = m.instability {
        line += &format!(", instability {i:.2}× the reference's");
    }
    if let (Some(j), Some(n)) = (m.video_jod, m.video_frames) {
        line += &format!(", ColorVideoVDP {j:.2} JOD over {n} frames");
    }
    if !m.settle.is_empty() {
        line += &format!(", settles in {:?} frames after the cuts", m.settle);
    }
    if !m.settle_stops.is_empty() {
        line += &format!(
            ", settles in {:?} frames after the objects stop",
            m.settle_stops
        );
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use nearfield_scene::{CameraPath, Keyframe};

    #[test]
    fn a_technique_settles_at_the_first_frame_within_5_percent_of_its_settled_error() {
        let (a, b) = (
            Camera::new(glam::Vec3::new(0.0, 1.0, 4.0), glam::Vec3::ZERO, 45.0),
            Camera::new(glam::Vec3::new(4.0, 1.0, 0.0), glam::Vec3::ZERO, 45.0),
        );
        let keys = [
            Keyframe::from((0.0, a)),
            Keyframe {
                t: 1.0,
                camera: b,
                cut: true,
            },
            Keyframe::from((3.0, b)),
        ];
        let path = CameraPath::new(10.0, keys).unwrap();
        let run = Run::new(Motion::Path(path), None, a, &Default::default());
        assert_eq!(run.cuts(), vec![10]);
        // Measured: frames 10..42 after the cut (and the last, 30); not the others.
        let measured = run.measured(1000);
        assert_eq!(measured.first(), Some(&10));
        assert!(measured.contains(&30) && !measured.contains(&9));
        // An error falling from 0.5 by 0.05 a frame to 0.2, then flat: within 5 % of 0.2 at
        // the seventh frame after the cut (0.5, 0.45, …, 0.2).
        let falling = |frames: std::ops::Range<u32>| -> Vec<ConvergencePoint> {
            frames
                .map(|i| ConvergencePoint {
                    frames: i + 1,
                    rmse: 0.0,
                    relative_error: (0.5 - 0.05 * (i - 10) as f64).max(0.2),
                })
                .collect()
        };
        let points = falling(10..31);
        assert_eq!(
            run.settle(&points),
            Vec::<u32>::new(),
            "a window the path cuts short"
        );
        let long = CameraPath::new(10.0, [keys[0], keys[1], Keyframe::from((6.0, b))]).unwrap();
        let run = Run::new(Motion::Path(long), None, a, &Default::default());
        let points = falling(10..61);
        assert_eq!(run.settle(&points), vec![7]);
    }

    /// `cornell-moving`'s box slides for 2 s and stands for 1 s: at 30 fps it comes to rest at
    /// frame 60, and the frames to settle are counted from there, the settled value the mean of
    /// frames 76–90 (the path ends before frame 92).
    #[test]
    fn a_technique_settles_after_the_objects_stop() {
        let scene = nearfield_scene::builtin::scene("cornell-moving").unwrap();
        let camera = scene.default_camera();
        let path = CameraPath::standing(camera, 3.0, 30.0).unwrap();
        let run = Run::new(Motion::Path(path), None, camera, &scene);
        assert_eq!(run.frames, 91);
        assert_eq!(run.stops(), vec![60]);
        assert!(run.cuts().is_empty());
        let measured = run.measured(1000);
        assert!(measured.contains(&60) && measured.contains(&89) && !measured.contains(&59));
        let points: Vec<ConvergencePoint> = (0..91)
            .map(|i| ConvergencePoint {
                frames: i + 1,
                rmse: 0.0,
                relative_error: (0.5 - 0.05 * (i as f64 - 60.0)).clamp(0.2, 0.5),
            })
            .collect();
        assert_eq!(run.settle_stops(&points), vec![7]);
        // A still scene has no stops.
        let still = nearfield_scene::builtin::scene("cornell").unwrap();
        let path = CameraPath::standing(camera, 3.0, 30.0).unwrap();
        assert!(
            Run::new(Motion::Path(path), None, camera, &still)
                .stops()
                .is_empty()
        );
    }
}

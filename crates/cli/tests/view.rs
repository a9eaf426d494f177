//! `nearfield view` in a real window (Xvfb, lavapipe where there is no GPU):
//! - its screenshot after N frames is the image `nearfield render` makes of the same camera and
//!   settings, single and A/B split (FLIP bound below, measured 0 on lavapipe);
//! - a scripted session of 100+ switches of technique, image, resolution, scene and split keeps
//!   wgpu's live object counts the same after every full cycle;
//! - out-of-range and malformed values typed into a session are refused one by one, the viewer
//!   neither panics nor changes state.
//!
//! Needs `xvfb-run` (apt: xvfb, xauth; scripts/setup.sh installs it). Without it the tests skip,
//! unless REQUIRE_GPU=1, where they fail.

use nearfield_eval::metrics::{Mask, flip_mean};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Mean FLIP allowed between the viewer's screenshot and `render`'s image. Both come from the
/// same renderer and frame sequence, so on lavapipe (llvmpipe 15) the measured value is 0 (the
/// files are byte-identical); the bound leaves room for drivers whose results vary by a code
/// value from run to run.
const FLIP_BOUND: f64 = 1e-3;

fn have_xvfb() -> bool {
    let ok = Command::new("xvfb-run")
        .arg("--help")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
            "REQUIRE_GPU=1 but xvfb-run is missing (apt: xvfb xauth; scripts/setup.sh)"
        );
        eprintln!("skipping: xvfb-run not installed");
    }
    ok
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearfield-view-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `nearfield view ARGS` in a virtual X server: (exit status, stdout, stderr).
fn view(args: &[&str]) -> (i32, String, String) {
    view_with(args, &[])
}

/// [`view`] with environment variables `envs`.
fn view_with(args: &[&str], envs: &[(&str, &Path)]) -> (i32, String, String) {
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(env!("CARGO_BIN_EXE_nearfield"))
        .arg("view")
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .expect("run xvfb-run");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn render(args: &[&str], out: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .arg("render")
        .args(args)
        .arg("-o")
        .arg(out)
        .output()
        .expect("run nearfield render");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// Mean FLIP over the columns `x0..x1`.
fn flip_in(test: &image::RgbImage, reference: &image::RgbImage, x0: u32, x1: u32) -> f64 {
    assert_eq!(test.dimensions(), reference.dimensions());
    let (w, h) = test.dimensions();
    let valid = (0..w * h).map(|i| (x0..x1).contains(&(i % w))).collect();
    let mask = Mask {
        width: w,
        height: h,
        valid,
        silhouette_pixels: 0,
        depth_checked: false,
    };
    flip_mean(test, reference, &mask)
}

const SCENE: &[&str] = &["builtin:cornell", "--size", "320x180"];

#[test]
fn screenshot_after_30_frames_equals_render() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("screenshot");
    let shot = dir.join("view.png");
    let args = [SCENE, &["--method", "hbil", "--frames", "30"]].concat();
    let (code, _, err) = view(&[&args[..], &["--screenshot", shot.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("median frame time"), "{err}");
    let reference = dir.join("render.png");
    render(&args, &reference);
    let flip = flip_in(&rgb(&shot), &rgb(&reference), 0, 320);
    eprintln!("hbil, 30 frames: FLIP(view, render) = {flip:.6}");
    assert!(flip <= FLIP_BOUND, "FLIP {flip} > {FLIP_BOUND}");
}

/// The viewer plays a moving scene's animation on its frame clock: its 45th frame shows the box
/// where `render --frames 45` shows it (moved since the first frame), hbil's history included.
#[test]
fn a_moving_scene_plays_in_the_viewer_as_render_plays_it() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("moving");
    let shot = dir.join("view.png");
    let args = [
        "builtin:cornell-moving",
        "--size",
        "320x180",
        "--method",
        "hbil",
    ];
    let frames = [&args[..], &["--frames", "45"]].concat();
    let (code, _, err) = view(&[&frames[..], &["--screenshot", shot.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    let (later, first) = (dir.join("render.png"), dir.join("first.png"));
    render(&frames, &later);
    render(&args, &first);
    let flip = flip_in(&rgb(&shot), &rgb(&later), 0, 320);
    let moved = flip_in(&rgb(&shot), &rgb(&first), 0, 320);
    eprintln!(
        "cornell-moving, 45 frames: FLIP(view, render) = {flip:.6}, against frame 1 {moved:.6}"
    );
    assert!(flip <= FLIP_BOUND, "FLIP {flip} > {FLIP_BOUND}");
    assert!(
        moved > 10.0 * FLIP_BOUND.max(1e-4),
        "the box moved: {moved}"
    );
}

/// The viewer records the camera of every frame as a camera path; `render --path` plays the
/// recording and shows what the viewer showed, hbil's history included (the frame after
/// `stop-path` is rendered at the last recorded camera, which `--frames` one beyond the path's
/// holds).
#[test]
fn a_recorded_camera_path_replays_what_the_viewer_showed() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("record");
    let (path, shot) = (dir.join("walk.json"), dir.join("view.png"));
    let mut script = format!("record-path {}\n", path.display());
    script += &"orbit 2\n".repeat(8);
    script += &format!("stop-path\nscreenshot {}\nquit\n", shot.display());
    let script_file = dir.join("record.txt");
    std::fs::write(&script_file, script).unwrap();
    let args = [SCENE, &["--method", "hbil"]].concat();
    let (code, _, err) = view(
        &[
            &args[..],
            &["--script", script_file.to_str().unwrap(), "--frames", "200"],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("(9 frames)"), "{err}");
    let recorded = nearfield_scene::CameraPath::load(&path).unwrap();
    assert_eq!(recorded.frames(), 9);
    let replay = dir.join("replay.png");
    let path_arg = path.to_str().unwrap();
    render(
        &[&args[..], &["--path", path_arg, "--frames", "10"]].concat(),
        &replay,
    );
    let flip = flip_in(&rgb(&shot), &rgb(&replay), 0, 320);
    eprintln!("hbil along a recorded path: FLIP(view, render --path) = {flip:.6}");
    assert!(flip <= FLIP_BOUND, "FLIP {flip} > {FLIP_BOUND}");
}

#[test]
fn split_view_shows_each_technique_on_its_side() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("split");
    let shot = dir.join("view.png");
    let (code, _, err) = view(
        &[
            SCENE,
            &[
                "--method",
                "ssdo",
                "--split-with",
                "gtao",
                "--frames",
                "30",
                "--screenshot",
                shot.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let (a, b) = (dir.join("ssdo.png"), dir.join("gtao.png"));
    render(
        &[SCENE, &["--method", "ssdo", "--frames", "30"]].concat(),
        &a,
    );
    render(
        &[SCENE, &["--method", "gtao", "--frames", "30"]].concat(),
        &b,
    );
    let shot = rgb(&shot);
    // The divider is at column 160; FLIP's filters see a few pixels across it.
    let left = flip_in(&shot, &rgb(&a), 0, 150);
    let right = flip_in(&shot, &rgb(&b), 170, 320);
    let crossed = flip_in(&shot, &rgb(&b), 0, 150);
    eprintln!(
        "split: FLIP left vs ssdo {left:.6}, right vs gtao {right:.6}, left vs gtao {crossed:.6}"
    );
    assert!(left <= FLIP_BOUND && right <= FLIP_BOUND, "{left} {right}");
    assert!(crossed > 10.0 * FLIP_BOUND, "the sides differ: {crossed}");
}

/// Parses the `resources …` lines a script's `report` prints.
fn reports(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter(|l| l.starts_with("resources "))
        .map(|l| {
            l.split_once(' ')
                .unwrap()
                .1
                .split_once(' ')
                .unwrap()
                .1
                .to_string()
        })
        .collect()
}

#[test]
fn a_hundred_switches_leak_no_gpu_objects() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("leak");
    // One cycle: 12 switches that end where they began; each scene switch waits for its probe
    // volume, so that what a cycle builds does not depend on how far a background bake got.
    let cycle = "method hbil\naov extra:reprojected\nsize 96x54\nscene builtin:boxes\n\
                 bake-wait\nsplit 0.5\nmethod b ssdo\naov ao\nsplit off\n\
                 scene builtin:cornell\nbake-wait\nsize 64x36\naov final\nmethod none\n\
                 report\n";
    let mut script = String::from("size 64x36\nwait 2\nreport\n");
    for _ in 0..9 {
        script.push_str(cycle);
    }
    script.push_str("quit\n");
    let path = dir.join("leak.txt");
    std::fs::write(&path, &script).unwrap();
    let (code, out, err) = view(&["--script", path.to_str().unwrap(), "--frames", "1000"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("GPU error"),
        "{err}"
    );
    let counts = reports(&out);
    assert_eq!(counts.len(), 10, "{out}");
    eprintln!(
        "live objects: start {}, after each cycle {counts:?}",
        counts[0]
    );
    // Passes are specialised for the lights and far field they bind (the book's architecture
    // page, "Specialised kernels"), and the device's pipeline cache keeps every variant it has
    // built: the second cycle, which starts where the first ended, meets a few combinations the
    // first did not (30 → 33 pipelines on lavapipe). From then on nothing may grow.
    for (i, c) in counts.iter().enumerate().skip(2) {
        assert_eq!(
            c, &counts[2],
            "after cycle {i}: {c} vs after cycle 2: {}",
            counts[2]
        );
    }
    // Same state as at the start (the hbil images of cycle 1 are gone with it), but for the
    // compiled pipelines the first cycles added to the device's cache (bounded by its capacity).
    let (start, start_pipelines) = counts[0].rsplit_once(" pipelines=").unwrap();
    let (after, after_pipelines) = counts[2].rsplit_once(" pipelines=").unwrap();
    assert_eq!(start, after);
    let (p0, p1): (usize, usize) = (
        start_pipelines.parse().unwrap(),
        after_pipelines.parse().unwrap(),
    );
    assert!(
        p1 >= p0 && p1 - p0 <= 2 * nearfield_render::pipeline_cache::CAPACITY,
        "pipelines {p0} → {p1}"
    );
}

#[test]
fn values_outside_their_ranges_are_refused_without_harm() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("garbage");
    let bad = [
        "set samples 0",
        "set samples 2.5",
        "set samples 1e12",
        "set radius -1",
        "set radius nan",
        "set radius inf",
        "set mode sideways",
        "set nosuch 1",
        "quality insane",
        "method nosuch",
        "method ssdo:samples=-3",
        "aov nosuch",
        "size 0x0",
        "size 99999x99999",
        "exposure 1e30",
        "exposure nan",
        "tonemap weird",
        "env /nonexistent/sky.hdr",
        "env constant:-1,0,0",
        "env-intensity -5",
        "env-rotation inf",
        "scene /nonexistent/scene.glb",
        "scene builtin:nosuch",
        "light 99 on",
        "split 7",
        "split -0.1",
        "camera /nonexistent/camera.json",
        "save-camera /nonexistent/dir/camera.json",
        "orbit nan",
        "set b samples 1e9",
    ];
    let mut script = String::from("method ssdo\n");
    for b in bad {
        script.push_str(b);
        script.push('\n');
    }
    let shot = dir.join("after.png");
    script.push_str(&format!(
        "wait 1\nscreenshot {}\nquit\n",
        shot.to_str().unwrap()
    ));
    let path = dir.join("garbage.txt");
    std::fs::write(&path, &script).unwrap();
    let args = [
        SCENE,
        &["--script", path.to_str().unwrap(), "--frames", "200"],
    ]
    .concat();
    let (code, _, err) = view(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("GPU error"),
        "{err}"
    );
    let refused = err
        .lines()
        .filter(|l| l.starts_with("nearfield: view: "))
        .count();
    // One line per refused value, plus "saved …".
    assert_eq!(refused, bad.len() + 1, "{err}");
    // The state is still `ssdo` with defaults: the same image as after `method ssdo` alone.
    let clean = dir.join("clean.txt");
    let clean_shot = dir.join("clean.png");
    let frames = bad.len() + 2; // the same frame index at the screenshot
    std::fs::write(
        &clean,
        format!(
            "method ssdo\nwait {}\nscreenshot {}\nquit\n",
            frames - 1,
            clean_shot.to_str().unwrap()
        ),
    )
    .unwrap();
    let (code, _, err) = view(
        &[
            SCENE,
            &["--script", clean.to_str().unwrap(), "--frames", "200"],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let flip = flip_in(&rgb(&shot), &rgb(&clean_shot), 0, 320);
    assert!(
        flip <= FLIP_BOUND,
        "state changed by refused values: FLIP {flip}"
    );
}

/// `xwd` (x11-apps) and Debian's ImageMagick `convert` take the screenshot of the X screen; with
/// REQUIRE_GPU=1 their absence is a failure (scripts/setup.sh installs them).
fn have_screen_grab() -> bool {
    let ok =
        Command::new("xwd").arg("-help").output().is_ok() && Path::new("/usr/bin/convert").exists();
    if !ok {
        assert!(
            std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
            "REQUIRE_GPU=1 but xwd or /usr/bin/convert is missing (apt: x11-apps imagemagick; \
             scripts/setup.sh)"
        );
        eprintln!("skipping: xwd or /usr/bin/convert not installed");
    }
    ok
}

/// The position in `screen` where `view` appears with the smallest largest channel difference,
/// and that difference. Candidates are first tested on a sparse grid of the view's pixels.
fn locate(screen: &image::RgbImage, view: &image::RgbImage) -> Option<((u32, u32), u8)> {
    let (sw, sh) = screen.dimensions();
    let (vw, vh) = view.dimensions();
    if vw > sw || vh > sh {
        return None;
    }
    let largest_difference = |x0: u32, y0: u32, step: u32, stop_above: u8| -> u8 {
        let mut worst = 0u8;
        for y in (0..vh).step_by(step as usize) {
            for x in (0..vw).step_by(step as usize) {
                let a = screen.get_pixel(x0 + x, y0 + y).0;
                let b = view.get_pixel(x, y).0;
                for c in 0..3 {
                    worst = worst.max(a[c].abs_diff(b[c]));
                }
                if worst > stop_above {
                    return worst;
                }
            }
        }
        worst
    };
    let mut best: Option<((u32, u32), u8)> = None;
    for y0 in 0..=sh - vh {
        for x0 in 0..=sw - vw {
            if largest_difference(x0, y0, 23, 8) > 8 {
                continue;
            }
            let d = largest_difference(x0, y0, 1, u8::MAX);
            if best.is_none_or(|(_, b)| d < b) {
                best = Some(((x0, y0), d));
            }
        }
    }
    best
}

/// Largest difference allowed between a presented pixel and `render`'s PNG, in levels of 255
/// (egui dithers its output by less than one level).
const PRESENTED_BOUND: u8 = 2;

#[test]
fn the_window_presents_the_pixels_render_writes() {
    if !have_xvfb() || !have_screen_grab() {
        return;
    }
    let dir = scratch("presented");
    let ready = dir.join("ready.png");
    let script = dir.join("session.txt");
    // The screenshot marks that frames have been presented; the window stays open meanwhile.
    std::fs::write(
        &script,
        format!("wait 10\nscreenshot {}\nwait 100000\n", ready.display()),
    )
    .unwrap();
    let shot = dir.join("screen.png");
    let args = [SCENE, &["--method", "none"]].concat();
    let viewer = format!(
        "{} view {} --script {}",
        env!("CARGO_BIN_EXE_nearfield"),
        args.join(" "),
        script.display()
    );
    let grab = format!(
        "{viewer} & pid=$!; for i in $(seq 600); do [ -s {ready} ] && break; sleep 0.2; done; \
         sleep 2; xwd -root -silent | /usr/bin/convert xwd:- {shot}; status=$?; kill $pid; \
         wait $pid; exit $status",
        ready = ready.display(),
        shot = shot.display()
    );
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x720x24", "bash", "-c", &grab])
        .output()
        .expect("run xvfb-run");
    assert!(
        out.status.success() && shot.exists(),
        "screen grab failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let reference = dir.join("render.png");
    render(&args, &reference);
    let (screen, view) = (rgb(&shot), rgb(&reference));
    let ((x, y), worst) = locate(&screen, &view).unwrap_or_else(|| {
        panic!(
            "the 3D view is not on the screen (within 8 levels anywhere): {}",
            shot.display()
        )
    });
    let mean = {
        let mut sum = 0u64;
        for (px, py, p) in view.enumerate_pixels() {
            let s = screen.get_pixel(x + px, y + py).0;
            sum += (0..3)
                .map(|c| u64::from(s[c].abs_diff(p.0[c])))
                .sum::<u64>();
        }
        sum as f64 / (3 * view.width() * view.height()) as f64
    };
    eprintln!(
        "presented view at ({x}, {y}): largest difference {worst}/255, mean {mean:.4}/255 \
         from render's PNG"
    );
    assert!(
        worst <= PRESENTED_BOUND,
        "presented pixels differ by {worst} levels (> {PRESENTED_BOUND})"
    );
}

/// The viewer's far control: `far volume` bakes in the background and its frames then equal
/// `render --far volume`; an environment change rebakes (the old volume stays until the new one
/// is in the frame), after which the frames equal `render` of the new environment's volume.
#[test]
fn the_far_control_bakes_and_rebakes_in_the_background() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("far");
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    let script = format!(
        "far volume\nbake-wait\nwait 2\nscreenshot {}\nenv-intensity 2\nbake-wait\nwait 2\n\
         screenshot {}\nquit\n",
        a.display(),
        b.display()
    );
    let path = dir.join("far.txt");
    std::fs::write(&path, script).unwrap();
    let cache = dir.join("cache");
    let (code, _, err) = view_with(
        &[
            SCENE,
            &["--script", path.to_str().unwrap(), "--frames", "1000"],
        ]
        .concat(),
        &[("NEARFIELD_CACHE", &cache)],
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("bak"), "the bake reports progress: {err}");
    for (shot, intensity) in [(&a, "1"), (&b, "2")] {
        let reference = dir.join(format!("render-{intensity}.png"));
        render(
            &[SCENE, &["--far", "volume", "--env-intensity", intensity]].concat(),
            &reference,
        );
        let flip = flip_in(&rgb(shot), &rgb(&reference), 0, 320);
        eprintln!("far volume, intensity {intensity}: FLIP(view, render) = {flip:.6}");
        assert!(flip <= FLIP_BOUND, "intensity {intensity}: FLIP {flip}");
    }
    let flip = flip_in(&rgb(&a), &rgb(&b), 0, 320);
    assert!(flip > 0.01, "the two volumes' images differ: FLIP {flip}");
}

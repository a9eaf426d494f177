//! `nearfield reference` and `nearfield compare` end to end: the cache is reused, and on a scene
//! whose answer is exact (a lone plane: ao = 1 everywhere for GPU `none` and the reference) the
//! report's metrics are exactly zero. Also `nearfield pareto` (a front that agrees with
//! `compare`), `compare --image` (an image measured beside the techniques gets the technique's
//! own numbers when it is that technique's AOV) and `nearfield export` (an exported built-in
//! renders the same depth).

use std::process::Command;

fn run(args: &[&str], cache: &std::path::Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .args(args)
        .env("NEARFIELD_CACHE", cache)
        .output()
        .expect("run nearfield");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn gpu_available(stderr: &str) -> bool {
    if stderr.contains("no GPU adapter") {
        assert!(
            std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
            "REQUIRE_GPU=1 but: {stderr}"
        );
        return false;
    }
    true
}

#[test]
fn reference_is_cached_and_compare_reports_exact_zero_error() {
    let dir = std::env::temp_dir().join(format!("nearfield-compare-{}", std::process::id()));
    let cache = dir.join("cache");
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("ao.exr");
    let args = [
        "reference",
        "builtin:plane",
        "--size",
        "48x32",
        "--aov",
        "ao",
        "--radius",
        "2",
        "--spp",
        "16",
        "-o",
        exr.to_str().unwrap(),
    ];
    let (code, _, err) = run(&args, &cache);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("M rays/s"), "{err}");
    let (code, _, err) = run(&args, &cache);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("from cache"),
        "second run did not use the cache: {err}"
    );

    let out = dir.join("report");
    let (code, stdout, err) = run(
        &[
            "compare",
            "builtin:plane",
            "--size",
            "48x32",
            "--aov",
            "ao",
            "--radius",
            "2",
            "--spp",
            "16",
            "--methods",
            "none",
            "--out",
            out.to_str().unwrap(),
        ],
        &cache,
    );
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("none"), "{stdout}");
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let m = &metrics["methods"][0]["metrics"];
    assert!(m["pixels"].as_u64().unwrap() > 300, "{m}");
    for key in ["bias", "mae", "rmse", "relative_error", "flip"] {
        assert_eq!(m[key].as_f64().unwrap(), 0.0, "{key}: {m}");
    }
    assert_eq!(metrics["mask"]["border"].as_u64().unwrap(), 2);
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for needed in [
        "none.png",
        "reference.png",
        "none-error.png",
        "linear-gradient",
    ] {
        assert!(html.contains(needed), "report lacks {needed}");
        if needed.ends_with(".png") {
            assert!(out.join(needed).is_file(), "{needed} not written");
        }
    }
    // No network: nothing in the report points off the machine.
    assert!(!html.contains("http://") && !html.contains("https://"));
}

/// Chromium, headless, as this machine's network allows it (no background connections).
fn chromium(profile: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--allow-file-access-from-files",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .output()
        .expect("run chromium")
}

fn have_chromium() -> bool {
    let ok = Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
            "REQUIRE_GPU=1 but chromium is missing (apt: chromium; scripts/setup.sh)"
        );
        eprintln!("skipping: chromium not installed");
    }
    ok
}

/// The report in `out`, moved to another folder and opened from disk in headless Chromium with
/// `#selftest`: no script or console error, a metrics row per method, the self-test passes.
/// Returns where it was moved.
fn report_in_browser(
    dir: &std::path::Path,
    out: &std::path::Path,
    methods: &[&str],
) -> std::path::PathBuf {
    let out = out.to_path_buf();
    // Relative paths only: the folder works wherever it is put.
    let moved = dir.join(format!(
        "moved-{}",
        out.file_name().unwrap().to_string_lossy()
    ));
    std::fs::rename(&out, &moved).unwrap();
    let html = std::fs::read_to_string(moved.join("report.html")).unwrap();
    assert!(
        !html.contains(dir.to_str().unwrap()) && !html.contains("/.cache/"),
        "the report names a directory"
    );
    let url = format!("file://{}/report.html", moved.display());
    let o = chromium(
        &dir.join("profile"),
        &[
            "--virtual-time-budget=10000",
            "--dump-dom",
            &format!("{url}#selftest"),
        ],
    );
    let dom = String::from_utf8_lossy(&o.stdout);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "chromium failed: {log}");
    let console_errors: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("CONSOLE") && (l.contains("ERROR") || l.contains("Uncaught")))
        .collect();
    assert!(
        console_errors.is_empty(),
        "console errors: {console_errors:?}"
    );
    assert!(!dom.contains("data-errors"), "script errors: {dom}");
    assert!(
        dom.contains(r#"data-ready="1""#),
        "the page did not load: {dom}"
    );
    assert!(
        dom.contains(r#"data-selftest="ok""#),
        "self-test: {}",
        dom.split("data-selftest=")
            .nth(1)
            .unwrap_or("(did not finish)")
    );
    let table = dom
        .split(r#"<table id="metrics""#)
        .nth(1)
        .and_then(|t| t.split("</table>").next())
        .expect("the metrics table is on the page");
    for m in methods {
        assert!(
            table.contains(&format!(">{m}</a>")),
            "no row for {m}: {table}"
        );
    }
    moved
}

/// The report, moved to another folder, opened from disk in headless Chromium: it loads without
/// a script error or console error, shows the metrics table with a row per method, and its own
/// self-test (`#selftest`: sort by a column both ways, flip each image with a key and the
/// slider, zoom ×4 on a click and back, every image loads) passes in the real browser.
#[test]
fn report_works_in_a_browser_from_any_folder() {
    if !have_chromium() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("nearfield-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("made");
    let (code, _, err) = run(
        &[
            "compare",
            "builtin:cornell",
            "--size",
            "64x48",
            "--aov",
            "ao",
            "--radius",
            "1",
            "--spp",
            "8",
            "--methods",
            "none,ssao,gtao",
            "--out",
            out.to_str().unwrap(),
        ],
        &dir.join("cache"),
    );
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    let moved = report_in_browser(&dir, &out, &["none", "ssao", "gtao"]);
    let url = format!("file://{}/report.html", moved.display());
    // What is presented: a screenshot of the page shows dark text on the light page.
    let shot = dir.join("page.png");
    let o = chromium(
        &dir.join("profile"),
        &[
            "--window-size=1200,900",
            &format!("--screenshot={}", shot.display()),
            &url,
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&shot).unwrap().to_rgb8();
    let dark = img.pixels().filter(|p| p.0.iter().all(|&c| c < 80)).count();
    let light = img
        .pixels()
        .filter(|p| p.0.iter().all(|&c| c > 230))
        .count();
    let n = (img.width() * img.height()) as usize;
    eprintln!(
        "report screenshot: {:.2} % dark, {:.1} % light pixels",
        100.0 * dark as f64 / n as f64,
        100.0 * light as f64 / n as f64
    );
    assert!(dark * 200 > n && light * 2 > n, "the page looks blank");
}

#[test]
fn pareto_writes_a_front_that_compare_agrees_with() {
    let dir = std::env::temp_dir().join(format!("nearfield-pareto-{}", std::process::id()));
    let cache = dir.join("cache");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("front");
    let (code, stdout, err) = run(
        &[
            "pareto",
            "builtin:boxes",
            "--size",
            "64x36",
            "--methods",
            "gtao,ssao",
            "--vary",
            "slices=1,3",
            "--vary",
            "samples=4",
            "--radius",
            "1",
            "--spp",
            "16",
            "--warmup",
            "1",
            "--timed",
            "2",
            "--out",
            out.to_str().unwrap(),
        ],
        &cache,
    );
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("gtao:slices=1"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("pareto.json")).unwrap()).unwrap();
    let methods = json["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 2);
    // gtao: default, slices=1, slices=3; ssao (no slices setting): default, samples=4.
    let specs: Vec<&str> = methods
        .iter()
        .flat_map(|m| m["points"].as_array().unwrap())
        .map(|p| p["spec"].as_str().unwrap())
        .collect();
    assert_eq!(
        specs,
        [
            "gtao",
            "gtao:slices=1",
            "gtao:slices=3",
            "ssao",
            "ssao:samples=4"
        ]
    );
    let mut fronts = 0;
    for m in methods {
        for p in m["points"].as_array().unwrap() {
            let (ms, e) = (p["ms"].as_f64().unwrap(), p["error"].as_f64().unwrap());
            assert!(ms > 0.0 && e.is_finite() && e >= 0.0, "{p}");
            fronts += p["front"].as_bool().unwrap() as u32;
        }
        assert!(m["default_slack"].as_f64().unwrap() >= 0.0);
    }
    assert!(fronts >= 1);
    let svg = std::fs::read_to_string(out.join("pareto.svg")).unwrap();
    assert_eq!(
        svg.matches("<title>").count(),
        5,
        "one dot per configuration"
    );
    // The errors are compare's.
    let cmp = dir.join("cmp");
    let (code, _, err) = run(
        &[
            "compare",
            "builtin:boxes",
            "--size",
            "64x36",
            "--methods",
            "gtao:slices=1",
            "--radius",
            "1",
            "--spp",
            "16",
            "--out",
            cmp.to_str().unwrap(),
        ],
        &cache,
    );
    assert_eq!(code, 0, "{err}");
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(cmp.join("metrics.json")).unwrap()).unwrap();
    let want = metrics["methods"][0]["metrics"]["relative_error"]
        .as_f64()
        .unwrap();
    let got = methods[0]["points"][1]["error"].as_f64().unwrap();
    assert!((got - want).abs() < 1e-9, "pareto {got} vs compare {want}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_image_measured_beside_the_techniques_gets_their_numbers() {
    let dir = std::env::temp_dir().join(format!("nearfield-image-{}", std::process::id()));
    let cache = dir.join("cache");
    std::fs::create_dir_all(&dir).unwrap();
    // gtao's ao as a file, then measured as an --image beside gtao itself.
    let exr = dir.join("gtao-ao.exr");
    let (code, _, err) = run(
        &[
            "render",
            "builtin:cornell",
            "--size",
            "64x36",
            "--method",
            "gtao",
            "--radius",
            "1",
            "--aov",
            "ao",
            "-o",
            exr.to_str().unwrap(),
        ],
        &cache,
    );
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    let out = dir.join("cmp");
    let image = "other=gtao-ao.exr";
    let (code, stdout, err) = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .current_dir(&dir)
        .args([
            "compare",
            "builtin:cornell",
            "--size",
            "64x36",
            "--methods",
            "gtao",
            "--radius",
            "1",
            "--spp",
            "16",
            "--image",
            image,
            "--out",
            "cmp",
        ])
        .env("NEARFIELD_CACHE", &cache)
        .output()
        .map(|o| {
            (
                o.status.code().unwrap_or(-1),
                String::from_utf8_lossy(&o.stdout).into_owned(),
                String::from_utf8_lossy(&o.stderr).into_owned(),
            )
        })
        .unwrap();
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("other"), "{stdout}");
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("metrics.json")).unwrap()).unwrap();
    let m = metrics["methods"].as_array().unwrap();
    assert_eq!(m.len(), 2);
    assert_eq!(m[1]["name"], "other");
    let (a, b) = (
        m[0]["metrics"]["relative_error"].as_f64().unwrap(),
        m[1]["metrics"]["relative_error"].as_f64().unwrap(),
    );
    assert!(
        a > 0.0 && (a - b).abs() < 1e-6,
        "gtao {a}, its own image {b}"
    );
    assert!(out.join("other.png").is_file() && out.join("other-error.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_writes_gltf_that_loads_back() {
    let dir = std::env::temp_dir().join(format!("nearfield-export-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = dir.join("cornell.glb");
    let (code, _, err) = run(
        &["export", "builtin:cornell", "--out", glb.to_str().unwrap()],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("28 triangles"), "{err}");
    // The file renders like the built-in: the same depth from the same camera, to within the
    // float rounding of the exported camera matrix.
    let a = dir.join("a.exr");
    let b = dir.join("b.exr");
    for (scene, out) in [("builtin:cornell", &a), (glb.to_str().unwrap(), &b)] {
        let (code, _, err) = run(
            &[
                "render",
                scene,
                "--size",
                "48x27",
                "--method",
                "none",
                "--aov",
                "depth",
                "-o",
                out.to_str().unwrap(),
            ],
            &dir,
        );
        if !gpu_available(&err) {
            return;
        }
        assert_eq!(code, 0, "{scene}: {err}");
    }
    let depth = |p: &std::path::Path| -> Vec<f32> {
        let img = exr::prelude::read_first_rgba_layer_from_file(
            p,
            |r, _| vec![0f32; r.width() * r.height()],
            |v: &mut Vec<f32>, pos, (d, _, _, _): (f32, f32, f32, f32)| {
                v[pos.y() * 48 + pos.x()] = d
            },
        )
        .unwrap();
        img.layer_data.channel_data.pixels
    };
    let (da, db) = (depth(&a), depth(&b));
    let covered = da.iter().filter(|d| **d > 0.0).count();
    assert!(covered > 48 * 27 / 5, "{covered} covered pixels");
    let worst = da
        .iter()
        .zip(&db)
        .map(|(x, y)| (x - y).abs())
        .fold(0f32, f32::max);
    assert!(worst < 1e-3, "depth differs by up to {worst} m");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `compare --walk`: each technique runs the walk's frames with its history carried over, and
/// every `--every`-th frame (and the last) is measured against the reference traced from that
/// frame's camera. On the lone plane ao = 1 for `none` and the truth, so every frame's error is
/// exactly zero; one reference per measured camera lands in the cache.
#[test]
fn compare_along_a_walk_measures_every_kth_frame_against_its_own_reference() {
    let dir = std::env::temp_dir().join(format!("nearfield-walk-{}", std::process::id()));
    let cache = dir.join("cache");
    let out = dir.join("walk");
    std::fs::create_dir_all(&dir).unwrap();
    let args = [
        "compare",
        "builtin:plane",
        "--walk",
        "--every",
        "40",
        "--size",
        "32x24",
        "--aov",
        "ao",
        "--radius",
        "2",
        "--spp",
        "8",
        "--methods",
        "none",
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, stdout, err) = run(&args, &cache);
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    let report: nearfield_eval::report::Report =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let path = &report.methods[0].path;
    // 121 frames at 30 fps: frames 40, 80 and 120, and the last.
    let frames: Vec<u32> = path.iter().map(|p| p.frames).collect();
    assert_eq!(frames, vec![40, 80, 120, 121]);
    for p in path {
        assert_eq!(p.relative_error, 0.0, "frame {}", p.frames);
    }
    assert!(stdout.contains("along the path: 4 frames"), "{stdout}");
    // A still camera at those views is exact too; frames 120 and 121 are consecutive, and
    // neither `none` nor the truth changes between them (ao = 1): an instability of 1.
    assert_eq!(report.methods[0].path_still, Some(0.0));
    assert_eq!(report.methods[0].instability, Some(1.0));
    // ColorVideoVDP over the longest consecutive run (120, 121): identical frames, 10 JOD.
    let m = &report.methods[0];
    assert_eq!(m.video_frames, Some(2));
    assert!(
        (m.video_jod.unwrap() - 10.0).abs() < 1e-3,
        "{:?}",
        m.video_jod
    );
    assert!(
        stdout.contains("ColorVideoVDP 10.00 JOD over 2 frames"),
        "{stdout}"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("Error along the camera path"));
    let cached = std::fs::read_dir(cache.join("reference")).unwrap().count();
    assert!(cached >= 4, "{cached} references cached for 4 cameras");
    // The sequence: each measured frame's image, error and reference, stepped in the browser.
    for f in ["none-0040.png", "none-0121-error.png", "reference-0080.png"] {
        assert!(out.join("frames").join(f).is_file(), "frames/{f}");
    }
    assert!(html.contains(r#"class="seq" data-method="none""#));
    if have_chromium() {
        report_in_browser(&dir, &out, &["none"]);
    }
    // A path file of three frames, each measured.
    let file = dir.join("path.json");
    std::fs::write(
        &file,
        r#"{"fps": 2, "keyframes": [
            {"t": 0, "eye": [0, 1.5, 3], "target": [0, 0, 0], "yfov_deg": 50},
            {"t": 1, "eye": [0.3, 1.5, 2.9], "target": [0, 0, 0], "yfov_deg": 50}]}"#,
    )
    .unwrap();
    let file = file.to_str().unwrap();
    let mut args: Vec<&str> = args.to_vec();
    args.splice(2..5, ["--path", file, "--every", "1"]);
    let (code, _, err) = run(&args, &cache);
    assert_eq!(code, 0, "{err}");
    let report: nearfield_eval::report::Report =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let m = &report.methods[0];
    assert_eq!(
        m.path.iter().map(|p| p.frames).collect::<Vec<_>>(),
        vec![1, 2, 3]
    );
    assert_eq!(m.instability, Some(1.0));
    assert_eq!(m.video_frames, Some(3));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A path with a cut: the Cornell box from its camera for half a second, then a jump into a
/// corner held for 1.2 s. Every frame after the cut is measured. `none` keeps nothing from frame
/// to frame, so it is settled at once; hbil's history starts over at the cut and settles within
/// its interleave's 16 frames. The camera stands still on either side of the cut: no pair of
/// frames gives an instability figure.
#[test]
fn compare_reports_the_frames_a_technique_takes_to_settle_after_a_cut() {
    let dir = std::env::temp_dir().join(format!("nearfield-cut-{}", std::process::id()));
    let cache = dir.join("cache");
    let out = dir.join("cut");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cut.json");
    std::fs::write(
        &file,
        r#"{"fps": 30, "keyframes": [
            {"t": 0, "eye": [0, 1, 3.9], "target": [0, 0.9, 0], "yfov_deg": 38},
            {"t": 0.5, "eye": [0, 1, 3.9], "target": [0, 0.9, 0], "yfov_deg": 38},
            {"t": 0.5334, "eye": [0.8, 1.5, 0.8], "target": [-0.6, 0.5, -0.8], "yfov_deg": 38, "cut": true},
            {"t": 1.7334, "eye": [0.8, 1.5, 0.8], "target": [-0.6, 0.5, -0.8], "yfov_deg": 38}]}"#,
    )
    .unwrap();
    let args = [
        "compare",
        "builtin:cornell",
        "--path",
        file.to_str().unwrap(),
        "--every",
        "1000",
        "--size",
        "48x36",
        "--aov",
        "ao",
        "--radius",
        "0.5",
        "--far",
        "sky",
        "--spp",
        "16",
        "--methods",
        "none,hbil",
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, stdout, err) = run(&args, &cache);
    if !gpu_available(&err) {
        return;
    }
    assert_eq!(code, 0, "{err}");
    let report: nearfield_eval::report::Report =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let settle = |name: &str| {
        report
            .methods
            .iter()
            .find(|m| m.name == name)
            .unwrap()
            .settle
            .clone()
    };
    assert!(stdout.contains("settles in [1] frames"), "{stdout}");
    assert_eq!(settle("none"), vec![1]);
    let hbil = settle("hbil");
    assert_eq!(hbil.len(), 1);
    assert!(
        (1..=16).contains(&hbil[0]),
        "hbil settles in {hbil:?} frames"
    );
    assert!(report.methods.iter().all(|m| m.instability.is_none()));
    let _ = std::fs::remove_dir_all(&dir);
}

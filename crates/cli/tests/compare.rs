//! `nearfield reference` and `nearfield compare` end to end: the cache is reused, and on a scene
//! whose answer is exact (a lone plane: ao = 1 everywhere for GPU `none` and the reference) the
//! report's metrics are exactly zero.

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
    // Relative paths only: the folder works wherever it is put.
    let moved = dir.join("moved");
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
    for m in ["none", "ssao", "gtao"] {
        assert!(
            table.contains(&format!(">{m}</a>")),
            "no row for {m}: {table}"
        );
    }
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

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

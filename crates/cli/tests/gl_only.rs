//! On a machine whose only adapter is GL (no Vulkan driver), every command that needs the GPU
//! exits with status 2 and one line naming what the adapter lacks and how to install a Vulkan
//! driver — never a panic, never a wgpu backtrace. The Vulkan driver is hidden from the process
//! (the loader's `VK_ICD_FILENAMES` and `VK_DRIVER_FILES` point at nothing), which leaves Mesa's
//! llvmpipe on GL where EGL is installed, or no adapter at all. Commands that need no GPU
//! (`bake`) still run.

use std::process::Command;
use std::time::{Duration, Instant};

fn without_vulkan(args: &[&str], cache: &std::path::Path) -> (i32, String, Duration) {
    let t = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .args(args)
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env_remove("WGPU_BACKEND")
        .env_remove("WGPU_ADAPTER_NAME")
        .env("NEARFIELD_CACHE", cache)
        .output()
        .expect("run nearfield");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        t.elapsed(),
    )
}

#[test]
fn without_a_vulkan_driver_every_gpu_command_exits_2_with_one_line() {
    let dir = std::env::temp_dir().join(format!("nearfield-gl-only-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let d = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let png = d("out.png");
    let report = d("report");
    let shot = d("shot.png");
    let fit_out = d("fit.json");
    let pareto_out = d("pareto");
    let mut cases: Vec<Vec<&str>> = vec![
        vec!["render", "builtin:cornell", "--size", "16x16", "-o", &png],
        vec![
            "render",
            "builtin:cornell",
            "--size",
            "16x16",
            "--method",
            "vbgi",
            "-o",
            &png,
        ],
        vec![
            "compare",
            "builtin:cornell",
            "--size",
            "16x16",
            "--spp",
            "1",
            "--out",
            &report,
        ],
        vec![
            "bench",
            "builtin:cornell",
            "--size",
            "16x16",
            "--methods",
            "gtao",
        ],
        vec![
            "fit",
            "gtao",
            "--params",
            "falloff",
            "--scenes",
            "builtin:cornell",
            "--holdout",
            "none",
            "--size",
            "16x16",
            "--spp",
            "1",
            "--out",
            &fit_out,
        ],
        vec![
            "pareto",
            "builtin:cornell",
            "--methods",
            "gtao",
            "--size",
            "16x16",
            "--spp",
            "1",
            "--out",
            &pareto_out,
        ],
    ];
    if std::env::var_os("DISPLAY").is_some() {
        cases.push(vec![
            "view",
            "builtin:cornell",
            "--frames",
            "1",
            "--screenshot",
            &shot,
        ]);
    }
    let mut gl_seen = false;
    for args in &cases {
        let (code, stderr, took) = without_vulkan(args, &dir);
        assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
        assert_eq!(code, 2, "{args:?}: status {code}\n{stderr}");
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{args:?}: more than one line:\n{stderr}");
        assert!(
            lines[0].contains("Install a Vulkan driver")
                && lines[0].contains("mesa-vulkan-drivers"),
            "{args:?}: {}",
            lines[0]
        );
        gl_seen |= lines[0].contains("(Gl,");
        // The adapter is refused before a scene is rendered or a reference traced.
        assert!(took < Duration::from_secs(20), "{args:?} took {took:?}");
        eprintln!("{args:?}: {} in {took:.2?}", lines[0]);
    }
    // Where EGL is installed (CI's machines: Mesa's GL with llvmpipe) the GL adapter is the one
    // refused, with what it lacks.
    if std::path::Path::new("/usr/lib/x86_64-linux-gnu/libEGL_mesa.so.0").exists() {
        assert!(
            gl_seen,
            "a GL adapter was expected with Mesa's EGL installed"
        );
    }
    // A command that needs no GPU still runs.
    let (code, stderr, _) = without_vulkan(
        &[
            "bake",
            "builtin:cornell",
            "--probes",
            "2,2,2",
            "--rays",
            "16",
            "--out",
            &d("v.nfv"),
        ],
        &dir,
    );
    assert_eq!(code, 0, "bake: {stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

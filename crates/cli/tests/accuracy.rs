//! Making the passes fast kept their accuracy: every technique's error at its defaults on every
//! built-in scene, for ao, env-irradiance and indirect-irradiance, is at most 2 % (relative)
//! above the error recorded before the speed work (data/accuracy.json, measured with
//! `nearfield compare` at commit 2c69997), plus 2e-4 absolute for errors near zero (an open
//! plane's ao error is 4e-4: rounding, not bias). A scene listed in the baseline's `sizes` is
//! measured at its own size, recorded anew there (`city`: at 96×54 R = 1 m spans about a pixel,
//! so a march that finds nothing scored better than one that finds the buildings' contact
//! lines; at 256×144 it spans four and more; the book, "Results").

use std::process::Command;

#[test]
fn no_technique_lost_accuracy_at_its_defaults() {
    let baseline: serde_json::Value =
        serde_json::from_str(include_str!("data/accuracy.json")).expect("baseline JSON");
    let dir = std::env::temp_dir().join(format!("nearfield-accuracy-{}", std::process::id()));
    let cache = dir.join("cache");
    std::fs::create_dir_all(&dir).unwrap();
    let errors = baseline["errors"].as_object().expect("errors");
    let mut worse = Vec::new();
    let mut checked = 0;
    for (key, old) in errors {
        let (scene, aov) = key.split_once('/').expect("SCENE/AOV");
        let out = dir.join(key.replace('/', "-"));
        let size = baseline["sizes"][scene]
            .as_str()
            .or(baseline["size"].as_str())
            .unwrap();
        let run = Command::new(env!("CARGO_BIN_EXE_nearfield"))
            .args(["compare", &format!("builtin:{scene}"), "--size", size])
            .args(["--radius", baseline["radius"].as_str().unwrap()])
            .args(["--aov", aov, "--spp"])
            .arg(baseline["spp"].to_string())
            .arg("--out")
            .arg(&out)
            .env("NEARFIELD_CACHE", &cache)
            .output()
            .expect("run nearfield");
        let stderr = String::from_utf8_lossy(&run.stderr);
        if stderr.contains("no GPU adapter") {
            assert!(
                std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
                "REQUIRE_GPU=1 but: {stderr}"
            );
            return;
        }
        assert!(run.status.success(), "{key}: {stderr}");
        let metrics: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("metrics.json")).unwrap()).unwrap();
        for m in metrics["methods"].as_array().unwrap() {
            let name = m["name"].as_str().unwrap();
            let now = m["metrics"]["relative_error"].as_f64().unwrap();
            let then = old[name]
                .as_f64()
                .unwrap_or_else(|| panic!("{key}: no recorded error for {name}"));
            checked += 1;
            if now > then * 1.02 + 2e-4 {
                worse.push(format!("{key} {name}: {then:.5} → {now:.5}"));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(checked, 27 * 10, "every technique on every scene and AOV");
    assert!(worse.is_empty(), "errors rose: {worse:#?}");
}

//! Making the passes fast kept their accuracy: every technique's error at its defaults on every
//! built-in scene, for ao, env-irradiance and indirect-irradiance, is at most 2 % (relative)
//! above the error recorded before the speed work (data/accuracy.json, measured with
//! `nearfield compare` at commit 2c69997), plus 2e-4 absolute for errors near zero (an open
//! plane's ao error is 4e-4: rounding, not bias). A scene listed in the baseline's `sizes` is
//! measured at its own size, recorded anew there (`city`: at 96×54 R = 1 m spans about a pixel,
//! so a march that finds nothing scored better than one that finds the buildings' contact
//! lines; at 448×252 it spans four and more; the book, "Results"). `variants` are settings other
//! than the defaults that the guard keeps as well (vbgi's `resolution=half` on `city`).

use std::process::Command;

#[test]
fn no_technique_lost_accuracy_at_its_defaults() {
    let baseline: serde_json::Value =
        serde_json::from_str(include_str!("data/accuracy.json")).expect("baseline JSON");
    let dir = std::env::temp_dir().join(format!("nearfield-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let guard = Guard {
        baseline: &baseline,
        dir: &dir,
    };
    let mut worse = Vec::new();
    let mut checked = 0;
    for (key, old) in baseline["errors"].as_object().expect("errors") {
        let Some(now) = guard.errors(key, None) else {
            return;
        };
        for (name, now) in now {
            let then = old[&name]
                .as_f64()
                .unwrap_or_else(|| panic!("{key}: no recorded error for {name}"));
            checked += 1;
            if now > then * 1.02 + 2e-4 {
                worse.push(format!("{key} {name}: {then:.5} → {now:.5}"));
            }
        }
    }
    // Settings other than the defaults that the guard keeps too (`variants`): run after the
    // defaults, so that their scene's reference is in the cache.
    for (key, old) in baseline["variants"].as_object().expect("variants") {
        let methods: Vec<&str> = old
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        let now = guard.errors(key, Some(&methods.join(","))).unwrap();
        for (name, now) in now {
            let then = old[&name].as_f64().unwrap();
            checked += 1;
            if now > then * 1.02 + 2e-4 {
                worse.push(format!("{key} {name}: {then:.5} → {now:.5}"));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(
        checked,
        27 * 10 + 1,
        "every technique on every scene and AOV, and the variants"
    );
    assert!(worse.is_empty(), "errors rose: {worse:#?}");
}

/// One guard run's setting: the baseline and the directory its outputs and cache go to.
struct Guard<'a> {
    baseline: &'a serde_json::Value,
    dir: &'a std::path::Path,
}

impl Guard<'_> {
    /// `compare` on `key` (SCENE/AOV) at the guard's setting, `methods` or every technique at its
    /// defaults: (name, relative error) per technique. `None` where there is no GPU adapter
    /// (and REQUIRE_GPU is not set).
    fn errors(&self, key: &str, methods: Option<&str>) -> Option<Vec<(String, f64)>> {
        let (scene, aov) = key.split_once('/').expect("SCENE/AOV");
        let out = self.dir.join(key.replace('/', "-"));
        let size = self.baseline["sizes"][scene]
            .as_str()
            .or(self.baseline["size"].as_str())
            .unwrap();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_nearfield"));
        cmd.args(["compare", &format!("builtin:{scene}"), "--size", size])
            .args(["--radius", self.baseline["radius"].as_str().unwrap()])
            .args(["--aov", aov, "--spp"])
            .arg(self.baseline["spp"].to_string())
            .arg("--out")
            .arg(&out)
            .env("NEARFIELD_CACHE", self.dir.join("cache"));
        if let Some(m) = methods {
            cmd.args(["--methods", m]);
        }
        let run = cmd.output().expect("run nearfield");
        let stderr = String::from_utf8_lossy(&run.stderr);
        if stderr.contains("no GPU adapter") {
            assert!(
                std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
                "REQUIRE_GPU=1 but: {stderr}"
            );
            return None;
        }
        assert!(run.status.success(), "{key}: {stderr}");
        let metrics: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("metrics.json")).unwrap()).unwrap();
        Some(
            metrics["methods"]
                .as_array()
                .unwrap()
                .iter()
                .map(|m| {
                    let name = m["name"].as_str().unwrap().to_string();
                    (name, m["metrics"]["relative_error"].as_f64().unwrap())
                })
                .collect(),
        )
    }
}

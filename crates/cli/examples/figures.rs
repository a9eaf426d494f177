//! Measures every number and makes every figure of the book (scripts/figures.sh runs it from
//! the repository root after a release build):
//! - `nearfield compare` of every technique on cornell and columns for ao, env-irradiance,
//!   indirect-irradiance, diffuse and lambertian, and (where ../shared/assets has it) on Crytek
//!   Sponza for ao, env-irradiance and diffuse;
//! - `nearfield bench` of every technique;
//! - each technique's failure strip (docs/src/img/failures/TECH.png);
//! - the demo strip (docs/src/img/cornell-compare.png, the same command as `make demo`);
//! - the vbgi page's crops (docs/src/img/crops-wall.png, crops-box.png, vbgi-denoisers-wall.png);
//! - the far field's Sponza strip (docs/src/img/sponza-far.png);
//! - the near and far page's Sponza strip with an added object (docs/src/img/sponza-helmet.png);
//!
//! into docs/src/generated/results.json, then the pages rendered from it (book_reference).
//! Scratch output goes to target/figures/. `FIGURES_QUICK=1` runs smaller images and fewer
//! samples (to try the pipeline, not to publish). `FIGURES_ONLY=bench` measures only the frame
//! times again (dated, the runs kept), `lambertian` only the `lambertian` runs (the AOV the far
//! field's defaults change); `crops`, `far`, `near-far` and `demo` remake only those
//! pictures.

use nearfield_cli::measure::schema::{Bench, Failure, MethodError, MetricsFile, Results, Run};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = "target/release/nearfield";
const TECHNIQUES: &str = "none,ssao,ssdo,ssdo-vpl,instant-radiosity,s3ho,ssbn,gtao,hbil,vbgi";
/// Techniques with an indirect term, one bounce (the reference's indirect is one bounce).
const INDIRECT: &str = "ssdo,ssdo-vpl,instant-radiosity,s3ho,hbil:source=direct,vbgi:source=direct";

fn quick() -> bool {
    std::env::var("FIGURES_QUICK").as_deref() == Ok("1")
}

fn nearfield(args: &[String]) -> String {
    eprintln!("figures: nearfield {}", args.join(" "));
    let out = Command::new(BIN).args(args).output().unwrap_or_else(|e| {
        panic!("{BIN}: {e} (build it: cargo build --release -p nearfield-cli)")
    });
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "nearfield {}: {stderr}",
        args.join(" ")
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn words(s: &str) -> Vec<String> {
    s.split_whitespace().map(str::to_string).collect()
}

fn json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

struct Scene {
    name: &'static str,
    args: String,
}

fn scenes(assets: &Path) -> Vec<Scene> {
    let mut v = vec![
        Scene {
            name: "cornell",
            args: "builtin:cornell".into(),
        },
        Scene {
            name: "columns",
            args: "builtin:columns".into(),
        },
    ];
    let sponza = assets.join("scenes/crytek_sponza/Sponza.gltf");
    let env = assets.join("env/rooitou_park_1k.hdr");
    if sponza.is_file() && env.is_file() {
        v.push(Scene {
            name: "sponza",
            args: format!(
                "{} --eye 9,1.5,-0.4 --target -5,3.5,0.2 --fov 60 --env {}",
                sponza.display(),
                env.display()
            ),
        });
    } else {
        eprintln!("figures: {} not found, Sponza left out", sponza.display());
    }
    v
}

/// `compare` into target/figures/ID; the per-method error from metrics.json.
fn compare(id: &str, scene: &Scene, rest: &str) -> (String, Vec<MethodError>, String) {
    let out = PathBuf::from("target/figures").join(id);
    let cmd = format!("compare {} {rest} --out {}", scene.args, out.display());
    nearfield(&words(&cmd));
    let path = out.join("metrics.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let m: MetricsFile =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let methods = m
        .methods
        .iter()
        .map(|x| MethodError {
            name: x.name.clone(),
            error: if m.aov == "ao" {
                x.metrics.mae
            } else {
                x.metrics.relative_error
            },
        })
        .collect();
    let adapter = m.adapter.clone();
    (
        format!("nearfield {}", words(&cmd).join(" ")),
        methods,
        adapter,
    )
}

fn main() {
    let assets =
        PathBuf::from(std::env::var("NEARFIELD_ASSETS").unwrap_or("../shared/assets".into()));
    // FIGURES_ONLY=crops or far remakes only the crops or the far-field strip (neither is in
    // results.json).
    // FIGURES_ONLY=bench measures the frame times alone into results.json, dated.
    match std::env::var("FIGURES_ONLY").as_deref() {
        Ok("crops") => return crops(),
        Ok("far") => return far_strip(&assets),
        Ok("near-far") => return near_far_strip(&assets),
        Ok("demo") => return demo_strip(),
        Ok("bench") => return bench_only(),
        Ok("lambertian") => return lambertian_only(&assets),
        _ => {}
    }
    let mut runs = Vec::new();
    let mut adapter = String::new();
    for scene in scenes(&assets) {
        for aov in AOVS {
            // `lambertian` is compared with the full path tracer, which has no near-field
            // radius: on a scene far larger than R it measures the far field, not the technique.
            // Sponza's one-bounce indirect light is left out with it (see the results page).
            if scene.name == "sponza" && matches!(aov, "lambertian" | "indirect-irradiance") {
                continue;
            }
            let (run, a) = measure(&scene, aov, &assets);
            adapter = a;
            runs.push(run);
        }
    }

    let bench = bench(None);

    let (_, spp, path_spp) = samples();
    // Failure pictures are looked at: larger.
    let failure_size = if quick() { "192x108" } else { "384x216" };

    // Failure strips: what each technique gets wrong, where it shows.
    std::fs::create_dir_all("docs/src/img/failures").expect("docs/src/img/failures");
    let cornell = &scenes(&assets)[0];
    let columns = &scenes(&assets)[1];
    let cases: [(&str, &str, &Scene, &str, u32, &str); 9] = [
        (
            "ssao",
            "too little occlusion almost everywhere: within R its few samples miss much of the walls and blocks that occlude, and nothing behind the first depth layer counts — the tall block's face beside the red wall most of all",
            cornell,
            "ao",
            1,
            "ssao",
        ),
        (
            "ssdo",
            "far too little one-bounce light: only senders the screen shows and a sample lands on within R contribute, so most of the light from the walls onto the floor, the blocks and each other is missing",
            cornell,
            "indirect-irradiance",
            1,
            "ssdo",
        ),
        (
            "ssdo-vpl",
            "the sky as a finite set of shadow-mapped directional lights: most surfaces too dark, the short block's top too bright, where the lights' coarse shadows and the restored small-scale shadows do not add up to the sky",
            cornell,
            "env-irradiance",
            16,
            "ssdo-vpl",
        ),
        (
            "instant-radiosity",
            "virtual point lights spread the bounce too evenly: too bright high on the walls and at the back, too dark in the corners and under the blocks, where the clamped 1/d² removes near light that the screen-space bounce does not restore",
            cornell,
            "indirect-irradiance",
            1,
            "instant-radiosity",
        ),
        (
            "s3ho",
            "16 SH coefficients cannot hold a sharp visibility edge: the sun's shadow on the back wall and the blocks' contact shadows are smeared — too dark in the lit part, too bright along the edges",
            cornell,
            "lambertian",
            16,
            "s3ho",
        ),
        (
            "ssbn",
            "one cone around the bent normal stands for the visible sky: too bright everywhere, most of all on the floor and the block faces that see the walls",
            cornell,
            "env-irradiance",
            16,
            "ssbn",
        ),
        (
            "gtao",
            "occlusion without light: no colour bleeding from the walls, so the floor, the blocks and the back wall are too dark",
            cornell,
            "diffuse",
            16,
            "gtao",
        ),
        (
            "hbil",
            "horizons take what rises above them as infinitely thick and see only the column's front: its faces get too little bounce light, the floor around it is off both ways",
            columns,
            "indirect-irradiance",
            1,
            "hbil:source=direct",
        ),
        (
            "vbgi",
            "thickness from the second depth layer still misses what no layer sees: the side walls near the open front get too much bounce, the back wall too little, and in one frame the 4×4 interleaving shows",
            cornell,
            "indirect-irradiance",
            1,
            "vbgi:source=direct",
        ),
    ];
    let mut failures = Vec::new();
    for (technique, what, scene, aov, frames, spec) in cases {
        let (spp, extra) = if aov == "lambertian" {
            (path_spp, "--max-depth 8")
        } else {
            (spp, "")
        };
        let image = format!("img/failures/{technique}.png");
        let rest = format!(
            "--size {failure_size} --radius 1 --aov {aov} --frames {frames} --spp {spp} {extra} --methods {spec} --strip docs/src/{image} --strip-errors"
        );
        let (command, methods, _) = compare(&format!("failure-{technique}"), scene, &rest);
        failures.push(Failure {
            technique: technique.into(),
            what: what.into(),
            scene: scene.name.into(),
            aov: aov.into(),
            command: command
                .replace(
                    &format!(" --strip docs/src/{image} --strip-errors"),
                    " --strip F.png --strip-errors",
                )
                .replace(&format!(" --out target/figures/failure-{technique}"), ""),
            image,
            relative_error: methods[0].error,
        });
    }

    demo_strip();

    crops();
    far_strip(&assets);
    near_far_strip(&assets);

    let results = Results {
        adapter,
        date: today(),
        runs,
        bench,
        failures,
    };
    write_results(&results);
}

const RESULTS: &str = "docs/src/generated/results.json";

fn today() -> String {
    Command::new("date")
        .args(["-u", "+%Y-%m-%d"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default()
}

fn write_results(results: &Results) {
    let text = serde_json::to_string_pretty(results).expect("results serialise") + "\n";
    nearfield_scene::atomic::write_bytes(Path::new(RESULTS), text.as_bytes())
        .unwrap_or_else(|e| panic!("write {RESULTS}: {e}"));
    eprintln!("figures: wrote {RESULTS}");
}

/// The runs' image size, samples per pixel of the one-bounce references and of the path tracer.
fn samples() -> (&'static str, u32, u32) {
    if quick() {
        ("96x54", 16, 32)
    } else {
        ("192x108", 128, 256)
    }
}

const AOVS: [&str; 5] = [
    "ao",
    "env-irradiance",
    "indirect-irradiance",
    "diffuse",
    "lambertian",
];

/// One run of the results: every technique's error on `scene` for `aov` at R = 1 m.
fn measure(scene: &Scene, aov: &str, assets: &Path) -> (Run, String) {
    let (size, spp, path_spp) = samples();
    let (methods, frames, spp, extra) = match aov {
        "indirect-irradiance" => (INDIRECT, 1, spp, ""),
        "lambertian" => (TECHNIQUES, 16, path_spp, "--max-depth 8"),
        _ => (TECHNIQUES, 16, spp, ""),
    };
    let id = format!("{}-{aov}", scene.name);
    let rest = format!(
        "--size {size} --radius 1 --aov {aov} --frames {frames} --spp {spp} {extra} --methods {methods}"
    );
    let (command, methods, adapter) = compare(&id, scene, &rest);
    let run = Run {
        scene: scene.name.into(),
        aov: aov.into(),
        metric: if aov == "ao" { "MAE" } else { "relative error" }.into(),
        command: command.replace(&assets.display().to_string(), "../shared/assets"),
        methods,
    };
    (run, adapter)
}

/// `FIGURES_ONLY=lambertian`: the `lambertian` runs (the image against the path tracer, the AOV
/// the far field's defaults change) measured again, every other run kept.
fn lambertian_only(assets: &Path) {
    let mut results: Results = serde_json::from_value(json(Path::new(RESULTS)))
        .unwrap_or_else(|e| panic!("{RESULTS}: {e}"));
    for scene in scenes(assets).iter().filter(|s| s.name != "sponza") {
        let (run, _) = measure(scene, "lambertian", assets);
        match results
            .runs
            .iter_mut()
            .find(|r| r.scene == run.scene && r.aov == run.aov)
        {
            Some(old) => *old = run,
            None => results.runs.push(run),
        }
    }
    write_results(&results);
}

/// `FIGURES_ONLY=bench`: the frame times measured again, the runs and failures kept.
fn bench_only() {
    let mut results: Results = serde_json::from_value(json(Path::new(RESULTS)))
        .unwrap_or_else(|e| panic!("{RESULTS}: {e}"));
    results.bench = bench(Some(today()));
    write_results(&results);
}

/// Frame times: every technique in turn, on the default scene. `date`: set when they are
/// measured apart from the runs.
fn bench(date: Option<String>) -> Bench {
    let bench_size = if quick() { "320x180" } else { "640x360" };
    std::fs::create_dir_all("target/figures").expect("target/figures");
    let bench_json = PathBuf::from("target/figures/bench.json");
    let bench_cmd = format!(
        "bench builtin:cornell --size {bench_size} --methods {TECHNIQUES} --frames {} --warmup 4 --json {}",
        if quick() { 4 } else { 24 },
        bench_json.display()
    );
    nearfield(&words(&bench_cmd));
    let b = json(&bench_json);
    let from = b["overhead_from"].as_str().unwrap_or("wall").to_string();
    let frame_ms = TECHNIQUES
        .split(',')
        .map(|t| {
            let m = &b["methods"][t];
            let ms = if from == "gpu" {
                m["gpu_total"]["median_ms"].as_f64()
            } else {
                m["wall"]["median_ms"].as_f64()
            };
            MethodError {
                name: t.into(),
                error: ms.unwrap_or(f64::NAN),
            }
        })
        .collect();
    Bench {
        command: format!("nearfield {bench_cmd}").replace(" --json target/figures/bench.json", ""),
        adapter: format!(
            "{} ({})",
            b["adapter"]["name"].as_str().unwrap_or_default(),
            b["adapter"]["device_type"].as_str().unwrap_or_default()
        ),
        from,
        frame_ms,
        date,
    }
}

/// The far field's strip (docs/src/img/sponza-far.png): Sponza's arcade, `lambertian` of `none`
/// and `vbgi` with the open sky beyond R, `vbgi` with the probe volume, and the path tracer
/// (4608 spp, its standard error 4.9 % of its mean), all at one exposure (+8 EV).
fn far_strip(assets: &Path) {
    let Some(sponza) = scenes(assets).into_iter().find(|s| s.name == "sponza") else {
        return;
    };
    let dir = Path::new("target/figures/far");
    std::fs::create_dir_all(dir).expect("target/figures/far");
    let view = format!("{} --size 160x90 --radius 1 --aov lambertian", sponza.args);
    let mut images = String::new();
    for (name, method, frames) in [("none-sky", "none", 1), ("vbgi-sky", "vbgi", 16)] {
        let file = dir.join(format!("{name}.exr"));
        nearfield(&words(&format!(
            "render {view} --method {method} --frames {frames} --far sky -o {}",
            file.display()
        )));
        images.push_str(&format!(" --image {name}={}", file.display()));
    }
    nearfield(&words(&format!(
        "compare {view} --methods vbgi --frames 16 --far volume --spp 4608 --max-depth 32 \
         --exposure 8{images} --strip docs/src/img/sponza-far.png --out {}",
        dir.join("compare").display()
    )));
}

/// The demo strip, as `make demo` makes it (docs/src/img/cornell-compare.png): the Cornell box
/// with a box its volume's bake never saw.
fn demo_strip() {
    nearfield(&words(
        "compare builtin:cornell-dynamic --size 384x288 --aov lambertian --frames 16 --spp 256 \
         --max-depth 8 --methods none,ssao,ssdo,s3ho,hbil,vbgi --out target/figures/demo \
         --strip docs/src/img/cornell-compare.png",
    ));
}

/// The near and far page's strip (docs/src/img/sponza-helmet.png): Sponza with the damaged
/// helmet added after the bake (dynamic), `lambertian` of `none`, `hbil` and `vbgi` with the
/// default volume and R = auto, and the path tracer, at one exposure (+8 EV).
fn near_far_strip(assets: &Path) {
    let Some(sponza) = scenes(assets).into_iter().find(|s| s.name == "sponza") else {
        return;
    };
    let helmet = assets.join("scenes/damaged_helmet/DamagedHelmet.gltf");
    let dir = Path::new("target/figures/near-far");
    std::fs::create_dir_all(dir).expect("target/figures/near-far");
    nearfield(&words(&format!(
        "compare {} --add {}@4.2,-0.02,0.6,0.6 --size 160x90 --aov lambertian --methods \
         none,hbil,vbgi --frames 16 --spp 4608 --max-depth 32 --exposure 8 --footprint \
         --strip docs/src/img/sponza-helmet.png --out {}",
        sponza.args,
        helmet.display(),
        dir.display()
    )));
}

/// The vbgi page's crops of the right wall and the short box's top at 1280×720 after 16
/// frames: hbil, hbil with the svgf denoiser, vbgi; and of the wall with vbgi's two denoisers
/// (vbgi-denoisers-wall.png).
fn crops() {
    let crops = Path::new("target/figures/crops");
    std::fs::create_dir_all(crops).expect("target/figures/crops");
    let mut shots = Vec::new();
    for (title, spec) in [
        ("hbil", "--method hbil"),
        ("hbil denoise=svgf", "--method hbil --set denoise=svgf"),
        ("vbgi", "--method vbgi"),
        (
            "vbgi denoise=bilateral",
            "--method vbgi --set denoise=bilateral",
        ),
    ] {
        let file = crops.join(format!("{}.png", title.replace([' ', '='], "-")));
        nearfield(&words(&format!(
            "render builtin:cornell --frames 16 {spec} -o {}",
            file.display()
        )));
        shots.push((title, image::open(&file).expect("render's PNG").to_rgb8()));
    }
    let three = &["hbil", "hbil denoise=svgf", "vbgi"][..];
    let crops_of = [
        ("crops-wall", three, (840, 60, 220, 600)),
        ("crops-box", three, (600, 400, 320, 160)),
        (
            "vbgi-denoisers-wall",
            &["vbgi", "vbgi denoise=bilateral"][..],
            (840, 60, 220, 600),
        ),
    ];
    for (name, titles, (x, y, w, h)) in crops_of {
        let panels: Vec<_> = shots
            .iter()
            .filter(|(title, _)| titles.contains(title))
            .map(|(title, img)| nearfield_eval::strip::Panel {
                image: image::imageops::crop_imm(img, x, y, w, h).to_image(),
                title: title.to_string(),
                subtitle: String::new(),
            })
            .collect();
        let strip = nearfield_eval::strip::strip(&panels);
        let path = PathBuf::from(format!("docs/src/img/{name}.png"));
        nearfield_scene::atomic::write_atomically(&path, |tmp| {
            strip.save_with_format(tmp, image::ImageFormat::Png)
        })
        .expect("write the crops");
    }
}

//! The book's generated pages (docs/src/generated/): the command-line reference, read from the
//! clap definitions, and the settings tables, read from the settings declarations, so that
//! neither can drift from the program. `cargo run -p nearfield-cli --example book_reference`
//! writes them; `tests/book.rs` checks that the committed ones are current.

use clap::CommandFactory;
use std::fmt::Write as _;

/// Text for a markdown table cell: one line, `|` escaped.
fn cell(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace('|', "\\|")
}

/// How an argument is written on the command line.
fn spelling(arg: &clap::Arg) -> String {
    let value = arg
        .get_value_names()
        .map(|v| {
            v.iter()
                .map(|n| format!("<{n}>"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_else(|| format!("<{}>", arg.get_id().as_str().to_uppercase()));
    let takes_value = arg.get_num_args().is_some_and(|n| n.takes_values())
        || (arg.get_num_args().is_none() && arg.get_action().takes_values());
    if arg.is_positional() {
        return format!("[{}]", value.trim_matches(|c| c == '<' || c == '>'));
    }
    let mut names = Vec::new();
    if let Some(s) = arg.get_short() {
        names.push(format!("-{s}"));
    }
    if let Some(l) = arg.get_long() {
        names.push(format!("--{l}"));
    }
    let names = names.join(", ");
    if takes_value {
        format!("{names} {value}")
    } else {
        names
    }
}

/// The command-line reference: every subcommand with its usage and a table of its arguments
/// (spelling, meaning, default).
pub fn cli_reference() -> String {
    let mut cli = crate::Cli::command();
    cli.build();
    let mut out = String::from(
        "<!-- generated from the clap definitions (crates/cli/src/); regenerate with \
         `cargo run -p nearfield-cli --example book_reference` -->\n\n## Reference of every \
         option\n\n",
    );
    for sub in cli.get_subcommands_mut() {
        let name = sub.get_name().to_string();
        let about = sub.get_about().map(|a| a.to_string()).unwrap_or_default();
        let usage = sub.render_usage().to_string();
        let usage = usage.trim_start_matches("Usage: ");
        let _ = write!(
            out,
            "### `nearfield {name}`\n\n{about}\n\n```text\n{}\n```\n\n| argument | meaning | default |\n|---|---|---|\n",
            usage
        );
        for arg in sub.get_arguments() {
            if arg.is_hide_set() || matches!(arg.get_id().as_str(), "help" | "version") {
                continue;
            }
            let help = arg
                .get_long_help()
                .or(arg.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default();
            let values: Vec<String> = arg
                .get_possible_values()
                .iter()
                .filter(|v| !v.is_hide_set())
                .map(|v| format!("`{}`", v.get_name()))
                .collect();
            let help = if values.is_empty() || help.contains(values[0].trim_matches('`')) {
                help
            } else {
                format!("{help} ({})", values.join(", "))
            };
            let default: Vec<String> = arg
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .collect();
            let default = if default.is_empty() {
                String::new()
            } else {
                format!("`{}`", default.join(","))
            };
            let _ = writeln!(
                out,
                "| `{}` | {} | {} |",
                cell(&spelling(arg)),
                cell(&help),
                default
            );
        }
        out.push('\n');
    }
    out
}

/// Every generated page: (file name in docs/src/generated/, content); the results pages when
/// measured results are given.
pub fn generated_pages(
    results: Option<&Results>,
    fits: &[Fit],
    fronts: &[Front],
) -> Vec<(String, String)> {
    let mut pages = nearfield_render::settings::book_pages();
    pages.push(("cli.md".into(), cli_reference()));
    if !fits.is_empty() {
        pages.push(("fits.md".into(), fits_page(fits)));
    }
    if !fronts.is_empty() {
        pages.push(("pareto.md".into(), fronts_page(fronts)));
    }
    if let Some(r) = results {
        pages.extend(results_pages(r));
    }
    pages
}

/// Reads docs/src/generated/results.json below `root` (the repository), if it is there.
pub fn read_results(root: &std::path::Path) -> Result<Option<Results>, String> {
    let path = root.join("docs/src/generated/results.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

// ---- Results: measured by `examples/figures.rs` into docs/src/generated/results.json, rendered
// ---- into the book's results tables (and the README's headline) by `results_pages`.

use serde::{Deserialize, Serialize};

/// One technique's error in one run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MethodError {
    /// The spec as run, e.g. `hbil:source=direct`.
    pub name: String,
    pub error: f64,
}

/// One `nearfield compare` run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Run {
    /// Short scene name (`cornell`, `columns`, `sponza`).
    pub scene: String,
    pub aov: String,
    /// `MAE` or `relative error`.
    pub metric: String,
    pub command: String,
    pub methods: Vec<MethodError>,
}

/// A technique's failure picture: its image, its signed error and the reference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Failure {
    pub technique: String,
    /// What the picture shows going wrong.
    pub what: String,
    pub scene: String,
    pub aov: String,
    pub command: String,
    /// Book-relative path of the strip.
    pub image: String,
    pub relative_error: f64,
}

/// Frame times of one `nearfield bench` run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bench {
    pub command: String,
    pub adapter: String,
    /// `wall` (CPU adapters) or `gpu`.
    pub from: String,
    /// Median frame time per technique, milliseconds.
    pub frame_ms: Vec<MethodError>,
}

/// Everything `examples/figures.rs` measured.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Results {
    pub adapter: String,
    pub date: String,
    pub runs: Vec<Run>,
    pub bench: Bench,
    pub failures: Vec<Failure>,
}

/// The registered technique a spec belongs to (`hbil:source=direct` → `hbil`).
pub fn technique_of(spec: &str) -> &str {
    spec.split(':').next().unwrap_or(spec)
}

const GENERATED: &str = "<!-- generated from docs/src/generated/results.json, measured by \
                         scripts/figures.sh; do not edit -->\n\n";

fn cost_vs_ssao(r: &Results, technique: &str) -> Option<f64> {
    let ms = |n: &str| {
        r.bench
            .frame_ms
            .iter()
            .find(|m| m.name == n)
            .map(|m| m.error)
    };
    Some(ms(technique)? / ms("ssao")?)
}

fn best(run: &Run) -> Option<&MethodError> {
    run.methods
        .iter()
        .min_by(|a, b| a.error.total_cmp(&b.error))
}

/// The scenes of the runs, in order.
fn scene_names(r: &Results) -> Vec<&str> {
    let mut scenes: Vec<&str> = Vec::new();
    for run in &r.runs {
        if !scenes.contains(&run.scene.as_str()) {
            scenes.push(&run.scene);
        }
    }
    scenes
}

/// Per AOV the technique (spec) that is closest to each scene's best: the smallest geometric
/// mean over the scenes of its error divided by the scene's best error (scale-free, so one
/// scene with large errors does not decide alone). (AOV, metric, spec, its runs.)
fn headline_rows(r: &Results) -> Vec<(String, String, String, Vec<&Run>)> {
    let mut aovs: Vec<&str> = Vec::new();
    for run in &r.runs {
        if !aovs.contains(&run.aov.as_str()) {
            aovs.push(&run.aov);
        }
    }
    let mut rows = Vec::new();
    for aov in aovs {
        let runs: Vec<&Run> = r.runs.iter().filter(|x| x.aov == aov).collect();
        let mut names: Vec<&str> = Vec::new();
        for run in &runs {
            for m in &run.methods {
                if m.name != "none" && !names.contains(&m.name.as_str()) {
                    names.push(&m.name);
                }
            }
        }
        let score = |name: &str| -> Option<f64> {
            let mut log_sum = 0.0;
            for run in &runs {
                let e = run.methods.iter().find(|m| m.name == name)?.error;
                let b = best(run)?.error;
                log_sum += (e.max(1e-9) / b.max(1e-9)).ln();
            }
            Some(log_sum / runs.len() as f64)
        };
        let Some(name) = names
            .iter()
            .filter_map(|n| score(n).map(|s| (*n, s)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(n, _)| n)
        else {
            continue;
        };
        rows.push((
            aov.to_string(),
            runs[0].metric.clone(),
            name.to_string(),
            runs,
        ));
    }
    rows
}

/// The headline table (README and the results page): per AOV the technique closest to the best
/// on every scene, its error on each scene (in brackets: without near-field light, `none`),
/// and its frame time relative to ssao.
pub fn headline(r: &Results) -> String {
    let scenes = scene_names(r);
    let mut out = format!(
        "| AOV (metric) | best technique | {} | frame time vs `ssao` |\n|---|---|{}---|\n",
        scenes.join(" | "),
        "---|".repeat(scenes.len())
    );
    for (aov, metric, name, runs) in headline_rows(r) {
        let cells: Vec<String> = scenes
            .iter()
            .map(|scene| {
                let Some(run) = runs.iter().find(|x| x.scene == *scene) else {
                    return "–".into();
                };
                let find = |n: &str| run.methods.iter().find(|m| m.name == n).map(|m| m.error);
                match (find(&name), find("none")) {
                    (Some(e), Some(none)) => format!("{e:.4} ({none:.4})"),
                    (Some(e), None) => format!("{e:.4}"),
                    _ => "–".into(),
                }
            })
            .collect();
        let cost = cost_vs_ssao(r, technique_of(&name))
            .map(|c| format!("{c:.2}×"))
            .unwrap_or_else(|| "–".into());
        let _ = writeln!(
            out,
            "| `{aov}` ({metric}) | `{name}` | {} | {cost} |",
            cells.join(" | ")
        );
    }
    out
}

fn scenes_sentence(r: &Results) -> String {
    let scenes = scene_names(r);
    format!(
        "Scenes: {} ({}); measured on {} ({}). Frame times: `{}` (median {} time; on a CPU \
         adapter only ratios mean anything).",
        scenes.len(),
        scenes.join(", "),
        r.adapter,
        r.date,
        r.bench.command,
        r.bench.from
    )
}

/// The summary page: the headline, then every run with every technique (best in bold), then
/// the frame times.
fn summary_page(r: &Results) -> String {
    let mut out = String::from(GENERATED);
    let _ = write!(out, "{}\n{}\n\n", headline(r), scenes_sentence(r));
    let order = crate::book::registry_order();
    let _ = write!(
        out,
        "### Every run\n\n| scene | AOV (metric) | {} |\n|---|---|{}\n",
        order
            .iter()
            .map(|t| format!("`{t}`"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(order.len())
    );
    for run in &r.runs {
        let best = best(run).map(|b| b.name.clone());
        let cells: Vec<String> = order
            .iter()
            .map(
                |t| match run.methods.iter().find(|m| technique_of(&m.name) == *t) {
                    Some(m) => {
                        let v = format!("{:.4}", m.error);
                        if Some(&m.name) == best.as_ref() {
                            format!("**{v}**")
                        } else {
                            v
                        }
                    }
                    None => "–".into(),
                },
            )
            .collect();
        let _ = writeln!(
            out,
            "| {} | `{}` ({}) | {} |",
            run.scene,
            run.aov,
            run.metric,
            cells.join(" | ")
        );
    }
    out.push_str("\nBold: best in the row; –: the technique has no such term. Commands:\n\n");
    for run in &r.runs {
        let _ = writeln!(out, "- `{}`", run.command);
    }
    let _ = write!(
        out,
        "\n### Frame time\n\n| technique | median ms | vs `ssao` |\n|---|---|---|\n"
    );
    for m in &r.bench.frame_ms {
        let _ = writeln!(
            out,
            "| `{}` | {:.1} | {} |",
            m.name,
            m.error,
            cost_vs_ssao(r, &m.name)
                .map(|c| format!("{c:.2}×"))
                .unwrap_or_else(|| "–".into())
        );
    }
    let _ = writeln!(out, "\n`{}` on {}.", r.bench.command, r.bench.adapter);
    out
}

/// One technique's results: each run it took part in, its rank, and the best of the run.
fn technique_page(r: &Results, technique: &str) -> String {
    let mut out = String::from(GENERATED);
    let _ = write!(
        out,
        "| scene | AOV (metric) | spec | error | rank | best in the run | `none` |\n|---|---|---|---|---|---|---|\n"
    );
    let mut rows = 0;
    for run in &r.runs {
        let mut sorted: Vec<&MethodError> = run.methods.iter().collect();
        sorted.sort_by(|a, b| a.error.total_cmp(&b.error));
        let none = run
            .methods
            .iter()
            .find(|m| m.name == "none")
            .map(|m| format!("{:.4}", m.error))
            .unwrap_or_else(|| "–".into());
        for m in run
            .methods
            .iter()
            .filter(|m| technique_of(&m.name) == technique)
        {
            let rank = sorted.iter().position(|s| s.name == m.name).unwrap_or(0) + 1;
            let b = sorted[0];
            let _ = writeln!(
                out,
                "| {} | `{}` ({}) | `{}` | {:.4} | {rank} of {} | `{}` {:.4} | {none} |",
                run.scene,
                run.aov,
                run.metric,
                m.name,
                m.error,
                sorted.len(),
                b.name,
                b.error
            );
            rows += 1;
        }
    }
    if rows == 0 {
        out.push_str("| – | – | – | – | – | – | – |\n");
    }
    let cost = cost_vs_ssao(r, technique)
        .map(|c| format!("{c:.2}× the frame time of `ssao`"))
        .unwrap_or_else(|| "not benchmarked".into());
    let _ = write!(out, "\nCost: {cost}. {}\n", scenes_sentence(r));
    out
}

/// A technique's failure figure with its caption.
fn failure_page(f: &Failure) -> String {
    let mut what = f.what.chars();
    let what = what
        .next()
        .map(|c| c.to_uppercase().chain(what).collect::<String>())
        .unwrap_or_default();
    format!(
        "{GENERATED}![{t}: {alt}](../{img})\n\n*{what}.* Left to right: `{t}`, its signed error \
         (blue: too dark, red: too bright, grey: not compared), the reference. `{aov}` on {scene}, \
         relative error {err:.4}. `{cmd}`\n",
        t = f.technique,
        alt = f.what,
        img = f.image,
        aov = f.aov,
        scene = f.scene,
        err = f.relative_error,
        cmd = f.command
    )
}

/// The registered techniques in their order.
pub fn registry_order() -> Vec<&'static str> {
    nearfield_render::technique::names()
}

/// Every page rendered from `results`: results-summary.md, results-TECH.md and failure-TECH.md.
pub fn results_pages(r: &Results) -> Vec<(String, String)> {
    let mut pages = vec![("results-summary.md".to_string(), summary_page(r))];
    for t in registry_order() {
        if t == "none" {
            continue;
        }
        pages.push((format!("results-{t}.md"), technique_page(r, t)));
    }
    for f in &r.failures {
        pages.push((format!("failure-{}.md", f.technique), failure_page(f)));
    }
    pages
}

/// Replaces the README's headline table between `<!-- results:headline -->` and
/// `<!-- /results:headline -->`; an error when the markers are missing.
pub fn rewrite_readme_headline(readme: &str, r: &Results) -> Result<String, String> {
    let (open, close) = ("<!-- results:headline -->\n", "<!-- /results:headline -->");
    let start = readme
        .find(open)
        .ok_or("README: no <!-- results:headline --> marker")?
        + open.len();
    let end = readme[start..]
        .find(close)
        .ok_or("README: no <!-- /results:headline --> marker")?
        + start;
    let mut out = readme.to_string();
    out.replace_range(start..end, &headline(r));
    Ok(out)
}

// ---- Fits: `nearfield fit` runs of scripts/fits.sh in docs/src/fits/TECHNIQUE.json, each the
// ---- source of a technique's `quality=fitted` preset (crates/render/src/settings/fitted.rs).

/// The errors of one side (training or held-out scenes) of a fit, before and after.
#[derive(Clone, Debug, Deserialize)]
pub struct FitSide {
    pub before: f64,
    pub after: f64,
    pub per_scene: std::collections::BTreeMap<String, FitScene>,
}

#[derive(Clone, Debug, Deserialize)]
pub struct FitScene {
    pub before: f64,
    pub after: f64,
}

/// What `nearfield fit` writes (the fields the book shows).
#[derive(Clone, Debug, Deserialize)]
pub struct Fit {
    pub method: String,
    pub params: std::collections::BTreeMap<String, serde_json::Value>,
    pub spec: String,
    pub metric: String,
    pub aov: String,
    pub frames: u32,
    pub size: [u32; 2],
    pub spp: u32,
    pub train: FitSide,
    pub holdout: FitSide,
    pub evaluations: usize,
    pub stopped: String,
    pub seconds: f64,
    pub command: String,
}

impl Fit {
    /// `key=value` of the fitted settings, as the preset states them.
    pub fn settings(&self) -> Vec<(String, String)> {
        self.params
            .iter()
            .map(|(k, v)| (k.clone(), v.to_string()))
            .collect()
    }

    /// The held-out error's relative change, in percent (negative: lower).
    pub fn holdout_change(&self) -> f64 {
        100.0 * (self.holdout.after / self.holdout.before - 1.0)
    }
}

/// Reads docs/src/fits/TECHNIQUE.json below `root` for every registered technique that has one,
/// in registry order.
pub fn read_fits(root: &std::path::Path) -> Result<Vec<Fit>, String> {
    let mut fits = Vec::new();
    for t in registry_order() {
        let path = root.join(format!("docs/src/fits/{t}.json"));
        match std::fs::read_to_string(&path) {
            Ok(text) => fits
                .push(serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(format!("{}: {e}", path.display())),
        }
    }
    Ok(fits)
}

/// The results table's "fitted" rows: per technique, what was fitted on which AOV, and the
/// training and held-out errors before and after, side by side.
pub fn fits_table(fits: &[Fit]) -> String {
    let mut out = String::from(
        "| technique | fitted on | `quality=fitted` | train: default → fitted | held out: default → fitted |\n|---|---|---|---|---|\n",
    );
    for f in fits {
        let set: Vec<String> = f
            .settings()
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        out += &format!(
            "| `{}` | `{}`, {} frame{} | `{}` | {:.4} → **{:.4}** | {:.4} → **{:.4}** ({:+.1} %) |\n",
            f.method,
            f.aov,
            f.frames,
            if f.frames == 1 { "" } else { "s" },
            set.join(" "),
            f.train.before,
            f.train.after,
            f.holdout.before,
            f.holdout.after,
            f.holdout_change()
        );
    }
    out
}

/// docs/src/generated/fits.md: the table, every scene's errors and the command of each fit.
fn fits_page(fits: &[Fit]) -> String {
    let mut out = String::from(
        "<!-- generated from docs/src/fits/*.json, measured by scripts/fits.sh; do not edit -->\n\n",
    );
    out += &fits_table(fits);
    for f in fits {
        out += &format!(
            "\n#### `{}`\n\n`{}` of `{}` at {}×{}, reference {} spp; {} evaluations ({}), {:.0} s:\n\n```text\nnearfield {}\n```\n\n| scene | side | default | fitted |\n|---|---|---|---|\n",
            f.method,
            f.metric,
            f.aov,
            f.size[0],
            f.size[1],
            f.spp,
            f.evaluations,
            f.stopped,
            f.seconds,
            f.command
        );
        for (side, s) in [("train", &f.train), ("held out", &f.holdout)] {
            for (scene, e) in &s.per_scene {
                out += &format!(
                    "| {} | {side} | {:.4} | {:.4} |\n",
                    cell(scene),
                    e.before,
                    e.after
                );
            }
        }
    }
    out
}

/// Replaces the README's text between `<!-- NAME -->` and `<!-- /NAME -->`.
fn replace_marked(readme: &str, name: &str, text: &str) -> Result<String, String> {
    let (open, close) = (format!("<!-- {name} -->\n"), format!("<!-- /{name} -->"));
    let start = readme
        .find(&open)
        .ok_or(format!("README: no {open} marker"))?
        + open.len();
    let end = readme[start..]
        .find(&close)
        .ok_or(format!("README: no {close} marker"))?
        + start;
    let mut out = readme.to_string();
    out.replace_range(start..end, text);
    Ok(out)
}

/// Replaces the README's fitted table between `<!-- results:fitted -->` and
/// `<!-- /results:fitted -->`.
pub fn rewrite_readme_fits(readme: &str, fits: &[Fit]) -> Result<String, String> {
    replace_marked(readme, "results:fitted", &fits_table(fits))
}

// ---- Fronts: `nearfield pareto` runs of scripts/pareto-book.sh in
// ---- docs/src/pareto/SCENE-AOV/pareto.json (and its pareto.svg).

pub use crate::pareto::{MethodFront as FrontMethod, Point as FrontPoint};

/// What `nearfield pareto` writes (the fields the book shows); `dir` is its folder's name.
#[derive(Clone, Debug, Deserialize)]
pub struct Front {
    #[serde(skip)]
    pub dir: String,
    pub scene: String,
    pub aov: String,
    pub size: [u32; 2],
    pub radius: f32,
    pub frames: u32,
    pub spp: u32,
    pub adapter: String,
    pub timing: String,
    pub none_ms: f64,
    pub methods: Vec<FrontMethod>,
    pub command: String,
}

/// Reads docs/src/pareto/*/pareto.json below `root`, in folder order.
pub fn read_fronts(root: &std::path::Path) -> Result<Vec<Front>, String> {
    let dir = root.join("docs/src/pareto");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Ok(Vec::new());
    };
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("pareto.json").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut fronts = Vec::new();
    for name in names {
        let path = dir.join(&name).join("pareto.json");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut f: Front =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        f.dir = name;
        fronts.push(f);
    }
    Ok(fronts)
}

/// docs/src/generated/pareto.md: per scene and AOV the plot, and per technique its default,
/// the configurations on its front and how far the default is from it.
fn fronts_page(fronts: &[Front]) -> String {
    let mut out = String::from(
        "<!-- generated from docs/src/pareto/*/pareto.json, measured by scripts/pareto-book.sh; do not edit -->\n\n",
    );
    for f in fronts {
        let scene = crate::pareto::short_scene(&f.scene);
        let _ = writeln!(out, "### {scene}: `{}`\n", f.aov);
        let _ = writeln!(
            out,
            "![{} error against time on {scene}](pareto/{}/pareto.svg)\n",
            f.aov, f.dir
        );
        let _ = writeln!(
            out,
            "{}×{}, R = {} m, {} frame{}, reference {} spp; {} time per frame on {} (`none`: {:.1} ms).\n",
            f.size[0],
            f.size[1],
            f.radius,
            f.frames,
            if f.frames == 1 { "" } else { "s" },
            f.spp,
            f.timing,
            f.adapter,
            f.none_ms
        );
        out += "| technique | default: ms, rel. error | its front (ms, rel. error) | default vs front |\n|---|---|---|---|\n";
        for m in &f.methods {
            let d = &m.points[0];
            let mut front: Vec<&FrontPoint> =
                m.points.iter().filter(|p| p.technique_front).collect();
            front.sort_by(|a, b| a.ms.total_cmp(&b.ms));
            let list: Vec<String> = front
                .iter()
                .map(|p| {
                    format!(
                        "{}{} ({:.1}, {:.4})",
                        if p.front { "**" } else { "" },
                        p.label,
                        p.ms,
                        p.error
                    ) + if p.front { "**" } else { "" }
                })
                .collect();
            let _ = writeln!(
                out,
                "| {} | {:.1}, {:.4} | {} | {} |",
                m.name,
                d.ms,
                d.error,
                list.join("; "),
                if m.default_slack <= 0.0 {
                    "on its front".to_string()
                } else if m.default_near_front {
                    format!("near (+{:.1} % time)", 100.0 * m.default_slack)
                } else {
                    format!("off: +{:.0} % time", 100.0 * m.default_slack)
                }
            );
        }
        let _ = writeln!(
            out,
            "\nBold: on the front of all techniques. Command: `{}`\n",
            f.command
        );
    }
    out
}

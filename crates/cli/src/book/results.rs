//! The results pages: measured by `examples/figures.rs` into docs/src/generated/results.json,
//! rendered into the book's results tables (and the README's headline) by `results_pages`.

use super::*;

pub use crate::measure::schema::{Bench, Failure, MethodError, Results, Run};

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

/// ", measured on DATE" where the frame times are later than the runs (`FIGURES_ONLY=bench`).
fn bench_date(r: &Results) -> String {
    match &r.bench.date {
        Some(d) if *d != r.date => format!(", measured on {d}"),
        _ => String::new(),
    }
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
         adapter only ratios mean anything){}.",
        scenes.len(),
        scenes.join(", "),
        r.adapter,
        r.date,
        r.bench.command,
        r.bench.from,
        bench_date(r)
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
    let _ = writeln!(
        out,
        "\n`{}` on {}{}.",
        r.bench.command,
        r.bench.adapter,
        bench_date(r)
    );
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

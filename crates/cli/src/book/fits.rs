//! The fits page: `nearfield fit` runs of scripts/fits.sh in docs/src/fits/TECHNIQUE.json, each
//! the source of a technique's `quality=fitted` preset (crates/render/src/settings/fitted.rs).

use super::*;

pub use crate::measure::schema::{FitFile as Fit, FitScene, FitSide};

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
pub(super) fn fits_page(fits: &[Fit]) -> String {
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

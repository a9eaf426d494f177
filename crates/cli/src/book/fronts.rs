//! The pareto page: `nearfield pareto` runs of scripts/pareto-book.sh in
//! docs/src/pareto/SCENE-AOV/pareto.json (and its pareto.svg).

use super::*;

pub use crate::measure::schema::{
    MethodFront as FrontMethod, ParetoFile as Front, Point as FrontPoint,
};

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
pub(super) fn fronts_page(fronts: &[Front]) -> String {
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

//! The comparison report: `metrics.json` and a self-contained `report.html` that shows, per
//! method, its image, the reference, the signed error heat map with its colour bar, and the
//! numbers. Images are PNG files beside the HTML, referenced by relative paths, so the report
//! opens from disk in any browser with no server and no network.

use crate::image_ops::diverging;
use crate::metrics::{MaskSettings, Metrics};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// One method's results.
#[derive(Clone, Debug, Serialize)]
pub struct MethodReport {
    pub name: String,
    pub metrics: Metrics,
    /// Heat-map range: the map shows [−range, +range].
    pub error_range: f32,
    /// File names (relative to the report) of the method's image and heat map.
    pub image: String,
    pub heatmap: String,
    /// Error after each rendered frame (still camera, more than one frame), else empty.
    pub convergence: Vec<ConvergencePoint>,
}

/// The error after `frames` frames.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ConvergencePoint {
    pub frames: u32,
    pub rmse: f64,
    pub relative_error: f64,
}

const CURVE_COLOURS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
];

/// An inline SVG of relative error against frame count (log2 frame axis) for every method that
/// has a curve; empty when none has.
pub fn convergence_svg(methods: &[MethodReport]) -> String {
    let curves: Vec<&MethodReport> = methods
        .iter()
        .filter(|m| !m.convergence.is_empty())
        .collect();
    if curves.is_empty() {
        return String::new();
    }
    let (w, h, left, bottom, top, right) = (560.0, 300.0, 60.0, 40.0, 12.0, 130.0);
    let max_frames = curves
        .iter()
        .flat_map(|m| m.convergence.iter().map(|p| p.frames))
        .max()
        .unwrap_or(1)
        .max(2) as f64;
    let max_err = curves
        .iter()
        .flat_map(|m| m.convergence.iter().map(|p| p.relative_error))
        .fold(0.0f64, f64::max)
        .max(1e-6)
        * 1.1;
    let x = |f: u32| left + (f as f64).log2() / max_frames.log2() * (w - left - right);
    let y = |e: f64| top + (1.0 - e / max_err) * (h - top - bottom);
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" style="background:#fff;border:1px solid #ccc">
<line x1="{left}" y1="{y0}" x2="{x1}" y2="{y0}" stroke="#000"/><line x1="{left}" y1="{top}" x2="{left}" y2="{y0}" stroke="#000"/>
<text x="{xm}" y="{yl}" text-anchor="middle" font-size="12">frames (log scale)</text>
<text x="14" y="{ym}" font-size="12" transform="rotate(-90 14 {ym})" text-anchor="middle">relative error</text>"##,
        y0 = h - bottom,
        x1 = w - right,
        xm = (left + w - right) / 2.0,
        yl = h - 6.0,
        ym = (top + h - bottom) / 2.0,
    );
    let mut f = 1u32;
    while f as f64 <= max_frames {
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle">{f}</text>"##,
            x(f),
            h - bottom + 14.0
        );
        f *= 2;
    }
    for i in 0..=4 {
        let e = max_err * i as f64 / 4.0;
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="end">{e:.3}</text>"##,
            left - 4.0,
            y(e) + 4.0
        );
    }
    for (i, m) in curves.iter().enumerate() {
        let colour = CURVE_COLOURS[i % CURVE_COLOURS.len()];
        let points: Vec<String> = m
            .convergence
            .iter()
            .map(|p| format!("{:.1},{:.1}", x(p.frames), y(p.relative_error)))
            .collect();
        let _ = write!(
            svg,
            r##"<polyline fill="none" stroke="{colour}" stroke-width="2" points="{}"/><text x="{:.1}" y="{:.1}" font-size="12" fill="{colour}">{}</text>"##,
            points.join(" "),
            w - right + 8.0,
            top + 16.0 * (i + 1) as f64,
            escape(&m.name)
        );
    }
    svg.push_str("</svg>");
    svg
}

/// Everything in metrics.json.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub scene: String,
    pub aov: String,
    pub size: [u32; 2],
    pub radius: String,
    pub adapter: String,
    /// Where the reference came from (file or cache path) and its sampling.
    pub reference: ReferenceInfo,
    pub mask: MaskSettings,
    /// The pixel rectangle [x0, y0, x1, y1) the metrics were restricted to, if any.
    pub region: Option<[u32; 4]>,
    /// Pixels excluded as silhouettes (dilated), and whether depth was available to find them.
    pub silhouette_pixels: usize,
    pub depth_checked: bool,
    /// RMS of the reference's per-pixel standard error (mean of RGB) over the compared pixels:
    /// errors below this are the reference's own noise.
    pub reference_noise: f64,
    pub methods: Vec<MethodReport>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReferenceInfo {
    pub path: String,
    pub spp: Option<u32>,
    pub seed: Option<u32>,
    pub image: String,
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes `dir/metrics.json` and `dir/report.html` (the PNGs are written by the caller).
pub fn write(dir: &Path, report: &Report) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(report).map_err(std::io::Error::other)?;
    nearfield_scene::atomic::write_bytes(&dir.join("metrics.json"), json.as_bytes())
        .map_err(std::io::Error::other)?;
    let stops: Vec<String> = (0..=10)
        .map(|i| {
            let t = -1.0 + 0.2 * i as f32;
            let [r, g, b] = diverging(t);
            format!("rgb({r},{g},{b}) {}%", i * 10)
        })
        .collect();
    let gradient = stops.join(", ");
    let mut h = String::new();
    let _ = write!(
        h,
        r#"<!doctype html><html><head><meta charset="utf-8"><title>nearfield compare — {scene} — {aov}</title>
<style>body{{font-family:sans-serif;margin:1.5em;background:#fafafa}}table{{border-collapse:collapse;margin:1em 0}}
td,th{{border:1px solid #ccc;padding:4px 8px;text-align:right}}th{{background:#eee}}
.row{{display:flex;gap:12px;flex-wrap:wrap;align-items:flex-start}}figure{{margin:0}}figcaption{{font-size:90%;color:#444}}
img{{image-rendering:pixelated;max-width:480px;border:1px solid #999}}.bar{{width:320px;height:14px;border:1px solid #999;background:linear-gradient(to right,{gradient})}}
.ticks{{display:flex;justify-content:space-between;width:322px;font-size:80%}}</style></head><body>
<h1>{aov} on {scene}</h1>
<p>{w}×{hh} pixels, near-field radius {radius}, adapter {adapter}. Reference: {refpath}{spp}.
Metrics over pixels that both images see as surface, outside a {border}-pixel border band, excluding {sil} silhouette pixels
(view depth differing by more than {tol}%, dilated by 1){nodepth}. Error e = method − reference on the mean of RGB.
The reference's own noise (RMS standard error over these pixels) is {noise:.5}.</p>
<table><tr><th>method</th><th>pixels</th><th>bias</th><th>MAE</th><th>RMSE</th><th>relative error</th><th>FLIP</th></tr>"#,
        scene = escape(&report.scene),
        aov = escape(&report.aov),
        w = report.size[0],
        hh = report.size[1],
        radius = escape(&report.radius),
        adapter = escape(&report.adapter),
        refpath = escape(&report.reference.path),
        spp = match (report.reference.spp, report.reference.seed) {
            (Some(s), Some(seed)) => format!(" ({s} spp, seed {seed})"),
            _ => String::new(),
        },
        border = report.mask.border,
        sil = report.silhouette_pixels,
        tol = report.mask.depth_tolerance * 100.0,
        noise = report.reference_noise,
        nodepth = if report.depth_checked {
            ""
        } else {
            "; the reference carries no depth, so only coverage silhouettes were excluded"
        },
    );
    for m in &report.methods {
        let x = &m.metrics;
        let _ = write!(
            h,
            "<tr><th>{}</th><td>{}</td><td>{:+.5}</td><td>{:.5}</td><td>{:.5}</td><td>{:.4}</td><td>{}</td></tr>",
            escape(&m.name),
            x.pixels,
            x.bias,
            x.mae,
            x.rmse,
            x.relative_error,
            x.flip
                .map(|f| format!("{f:.4}"))
                .unwrap_or_else(|| "–".into())
        );
    }
    h.push_str("</table>");
    let curve = convergence_svg(&report.methods);
    if !curve.is_empty() {
        let _ = write!(
            h,
            "<h2>Error against frames</h2><p>Relative error after each frame, same mask as above.</p>{curve}<table><tr><th>method</th><th>frames</th><th>RMSE</th><th>relative error</th></tr>"
        );
        for m in &report.methods {
            for p in &m.convergence {
                let _ = write!(
                    h,
                    "<tr><th>{}</th><td>{}</td><td>{:.5}</td><td>{:.4}</td></tr>",
                    escape(&m.name),
                    p.frames,
                    p.rmse,
                    p.relative_error
                );
            }
        }
        h.push_str("</table>");
    }
    for m in &report.methods {
        let _ = write!(
            h,
            r#"<h2>{name}</h2><div class="row">
<figure><img src="{img}" alt="{name}"><figcaption>{name} (tonemapped)</figcaption></figure>
<figure><img src="{refimg}" alt="reference"><figcaption>reference (tonemapped)</figcaption></figure>
<figure><img src="{heat}" alt="error"><figcaption>signed error, method − reference (grey: excluded)
<div class="bar"></div><div class="ticks"><span>{lo:+.4}</span><span>0</span><span>{hi:+.4}</span></div></figcaption></figure>
</div>"#,
            name = escape(&m.name),
            img = escape(&m.image),
            refimg = escape(&report.reference.image),
            heat = escape(&m.heatmap),
            lo = -m.error_range,
            hi = m.error_range,
        );
    }
    h.push_str("</body></html>\n");
    nearfield_scene::atomic::write_bytes(&dir.join("report.html"), h.as_bytes())
        .map_err(std::io::Error::other)
}

//! The comparison report: `metrics.json` and a self-contained `report.html` that shows, per
//! method, its image, the reference, the signed error heat map with its colour bar, and the
//! numbers. Images are PNG files beside the HTML, referenced by relative paths, so the report
//! opens from disk in any browser with no server and no network.

use crate::image_ops::diverging;
use crate::metrics::{MaskSettings, Metrics};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// One method's results.
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    /// With `--footprint`: the relative error of the change the scene's dynamic objects make
    /// to the ambient light around them, against the path tracer's (none adds nothing: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub footprint: Option<f64>,
    /// Along a camera path (`--path`, `--walk`): the error of every measured frame (`frames`:
    /// the frame's number from 1) against the reference from that frame's camera.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<ConvergencePoint>,
    /// Along a path: the mean error of a still camera at up to eight of the measured frames'
    /// views after 16 frames there (the error the path's frames are held to).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path_still: Option<f64>,
    /// Along a path measured at consecutive frames: the motion-compensated frame-to-frame change
    /// over the reference's own, free of its noise (`metrics::instability`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instability: Option<f64>,
    /// Along a path: ColorVideoVDP's JOD of the technique's frames against the reference's
    /// over the longest run of consecutive measured frames, as the report shows them
    /// ([`crate::video`]), and how many frames that run holds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video_jod: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video_frames: Option<u32>,
    /// Along a path with cuts: the frames to settle after each (the first within 5 % of the
    /// error of frames 17–32 after it, the cut's own frame counted as 1).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settle: Vec<u32>,
    /// Along a path over moving objects: the frames to settle after each time they come to
    /// rest (the same rule as `settle`, from the first frame at rest).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settle_stops: Vec<u32>,
}

/// The frames after which a path's frames are held to the still camera's error: a technique's
/// history needs them to fill (the book, "In motion").
pub const SETTLE_FRAMES: u32 = 16;

/// The largest relative error of a path's measured frames after the first [`SETTLE_FRAMES`].
pub fn path_largest_settled(points: &[ConvergencePoint]) -> f64 {
    points
        .iter()
        .filter(|p| p.frames > SETTLE_FRAMES)
        .map(|p| p.relative_error)
        .fold(0.0, f64::max)
}

/// Mean, 95th percentile and largest relative error over a path's measured frames (0 for none).
pub fn path_summary(points: &[ConvergencePoint]) -> (f64, f64, f64) {
    if points.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mut e: Vec<f64> = points.iter().map(|p| p.relative_error).collect();
    e.sort_by(f64::total_cmp);
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    // Nearest rank.
    let p95 = e[((0.95 * e.len() as f64).ceil() as usize).clamp(1, e.len()) - 1];
    (mean, p95, e[e.len() - 1])
}

/// The error after `frames` frames.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
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
    curves_svg(methods, |m| &m.convergence, true)
}

/// An inline SVG of relative error over the frames of a camera path for every method measured
/// along one; empty when none was.
pub fn path_svg(methods: &[MethodReport]) -> String {
    curves_svg(methods, |m| &m.path, false)
}

/// Relative error against frames, one curve per method that has points (`log`: a log2 frame
/// axis with ticks at powers of two, else linear with five ticks).
fn curves_svg(
    methods: &[MethodReport],
    points: fn(&MethodReport) -> &[ConvergencePoint],
    log: bool,
) -> String {
    let curves: Vec<&MethodReport> = methods.iter().filter(|m| !points(m).is_empty()).collect();
    if curves.is_empty() {
        return String::new();
    }
    let (w, h, left, bottom, top, right) = (560.0, 300.0, 60.0, 40.0, 12.0, 130.0);
    let max_frames = curves
        .iter()
        .flat_map(|m| points(m).iter().map(|p| p.frames))
        .max()
        .unwrap_or(1)
        .max(2) as f64;
    let max_err = curves
        .iter()
        .flat_map(|m| points(m).iter().map(|p| p.relative_error))
        .fold(0.0f64, f64::max)
        .max(1e-6)
        * 1.1;
    let x = |f: u32| {
        let t = if log {
            (f as f64).log2() / max_frames.log2()
        } else {
            (f as f64 - 1.0) / (max_frames - 1.0)
        };
        left + t * (w - left - right)
    };
    let y = |e: f64| top + (1.0 - e / max_err) * (h - top - bottom);
    let label = if log { "frames (log scale)" } else { "frame" };
    let mut svg = format!(
        r##"<svg width="{w}" height="{h}" style="background:#fff;border:1px solid #ccc">
<line x1="{left}" y1="{y0}" x2="{x1}" y2="{y0}" stroke="#000"/><line x1="{left}" y1="{top}" x2="{left}" y2="{y0}" stroke="#000"/>
<text x="{xm}" y="{yl}" text-anchor="middle" font-size="12">{label}</text>
<text x="14" y="{ym}" font-size="12" transform="rotate(-90 14 {ym})" text-anchor="middle">relative error</text>"##,
        y0 = h - bottom,
        x1 = w - right,
        xm = (left + w - right) / 2.0,
        yl = h - 6.0,
        ym = (top + h - bottom) / 2.0,
    );
    let ticks: Vec<u32> = if log {
        (0..32)
            .map(|k| 1u32 << k)
            .take_while(|&f| f as f64 <= max_frames)
            .collect()
    } else {
        (0..=4)
            .map(|k| 1 + ((max_frames - 1.0) * k as f64 / 4.0).round() as u32)
            .collect()
    };
    for f in ticks {
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle">{f}</text>"##,
            x(f),
            h - bottom + 14.0
        );
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
        let points: Vec<String> = points(m)
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

/// Everything in metrics.json (written by `write`, read back by the book's figures and the
/// tests with the same type).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub scene: String,
    pub aov: String,
    pub size: [u32; 2],
    pub radius: String,
    pub adapter: String,
    /// Where the reference came from (a file's name, or the cache entry's; never a directory,
    /// so that the folder can be moved and shared) and its sampling.
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
    /// The reference's relative noise: Σ σ / Σ |reference| over the compared pixels, on the scale
    /// of the relative error (a perfect estimate shows about 0.8 × this).
    pub reference_relative_noise: f64,
    pub methods: Vec<MethodReport>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ReferenceInfo {
    pub path: String,
    pub spp: Option<u32>,
    pub seed: Option<u32>,
    pub image: String,
}

/// An HTML id for a method's section.
fn anchor(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

/// The report's behaviour: sortable metrics table; per method an image that flips between the
/// method, the reference and the error (buttons, slider, keys 1-3 and space) and zooms ×4 where
/// clicked. With `#selftest` in the address it exercises all of that itself and writes the
/// outcome into `body[data-selftest]` (the browser test reads it).
/// The report's script (report.js): sorting, flipping and zooming the images, stepping a path's
/// frames, and the `#selftest` the browser test runs.
const SCRIPT: &str = concat!("<script>\n", include_str!("report.js"), "</script>\n");

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
.frame{{overflow:auto;max-width:min(100%,960px);max-height:80vh;border:1px solid #999;display:inline-block;cursor:zoom-in}}
.frame.zoomed{{cursor:zoom-out}}.frame img{{image-rendering:pixelated;display:block;max-width:none}}.frames img{{image-rendering:pixelated;margin-right:4px}}
.controls{{margin:4px 0}}.controls button.on{{background:#333;color:#fff}}.which{{font-size:90%;color:#444}}
th[data-sort]{{cursor:pointer}}th.asc::after{{content:" ▲"}}th.desc::after{{content:" ▼"}}section.flip:focus{{outline:2px solid #88f}}.bar{{width:320px;height:14px;border:1px solid #999;background:linear-gradient(to right,{gradient})}}
.ticks{{display:flex;justify-content:space-between;width:322px;font-size:80%}}</style></head><body>
<h1>{aov} on {scene}</h1>
<p>{w}×{hh} pixels, near-field radius {radius}, adapter {adapter}. Reference: {refpath}{spp}.
Metrics over pixels that both images see as surface, outside a {border}-pixel border band, excluding {sil} silhouette pixels
(view depth differing by more than {tol}%, dilated by 1){nodepth}. Error e = method − reference on the mean of RGB.
The reference's own noise (RMS standard error over these pixels) is {noise:.5}; relative to
the reference, Σσ/Σref = {rel_noise:.4}.</p>
<p>Click a column's heading to sort by it. Under each method: <b>1</b> / <b>2</b> / <b>3</b> (or the slider, or the buttons) flip one image between the method, the reference and the signed error; <b>space</b> swaps method and reference; a click zooms ×4 there, another click zooms back.</p>
<table id="metrics"><thead><tr><th data-sort="text">method</th><th data-sort="num">pixels</th><th data-sort="num">bias</th><th data-sort="num">MAE</th><th data-sort="num">RMSE</th><th data-sort="num">relative error</th><th data-sort="num">FLIP</th></tr></thead><tbody>"#,
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
        rel_noise = report.reference_relative_noise,
        nodepth = if report.depth_checked {
            ""
        } else {
            "; the reference carries no depth, so only coverage silhouettes were excluded"
        },
    );
    metrics_rows(&mut h, report);
    convergence(&mut h, report);
    path(&mut h, report);
    sequence(&mut h, report);
    for m in &report.methods {
        method_section(&mut h, report, m);
    }
    h.push_str(SCRIPT);
    h.push_str("</body></html>\n");
    nearfield_scene::atomic::write_bytes(&dir.join("report.html"), h.as_bytes())
        .map_err(std::io::Error::other)
}

/// The metrics table's rows, one per method.
fn metrics_rows(h: &mut String, report: &Report) {
    for m in &report.methods {
        let x = &m.metrics;
        let _ = write!(
            h,
            "<tr><th><a href=\"#m-{id}\">{name}</a></th><td data-v=\"{}\">{}</td><td data-v=\"{}\">{:+.5}</td><td data-v=\"{}\">{:.5}</td><td data-v=\"{}\">{:.5}</td><td data-v=\"{}\">{:.4}</td><td data-v=\"{}\">{}</td></tr>",
            x.pixels,
            x.pixels,
            x.bias,
            x.bias,
            x.mae,
            x.mae,
            x.rmse,
            x.rmse,
            x.relative_error,
            x.relative_error,
            x.flip.unwrap_or(f64::NAN),
            x.flip
                .map(|f| format!("{f:.4}"))
                .unwrap_or_else(|| "–".into()),
            id = anchor(&m.name),
            name = escape(&m.name),
        );
    }
    h.push_str("</tbody></table>");
}

/// The convergence curve and its table, where any method has one.
fn convergence(h: &mut String, report: &Report) {
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
}

/// The error over a camera path's frames and its summary, where any method was measured along
/// one.
fn path(h: &mut String, report: &Report) {
    let curve = path_svg(&report.methods);
    if curve.is_empty() {
        return;
    }
    let _ = write!(
        h,
        "<h2>Error along the camera path</h2><p>Relative error of each measured frame against the reference from that frame's camera, each technique's history carried from frame to frame. Still: the mean error a still camera reaches after 16 frames at up to eight of those views. Instability: the motion-compensated change from frame to frame over the reference's own (free of its noise: the cross product of two traces with different seeds; measured with <code>--every 1</code>). ColorVideoVDP: the perceptual quality of the frames as shown here against the reference's, played at the path's rate, in JOD (10: no visible difference; the reference's noise counts as a difference), over the longest run of consecutive measured frames.</p>{curve}<table><tr><th>method</th><th>frames measured</th><th>mean</th><th>95th percentile</th><th>largest</th><th>largest after frame 16</th><th>still</th><th>instability</th><th>ColorVideoVDP (JOD)</th><th>frames to settle after a cut</th><th>frames to settle after the objects stop</th></tr>"
    );
    for m in report.methods.iter().filter(|m| !m.path.is_empty()) {
        let (mean, p95, max) = path_summary(&m.path);
        let _ = write!(
            h,
            "<tr><th>{}</th><td>{}</td><td>{mean:.4}</td><td>{p95:.4}</td><td>{max:.4}</td><td>{:.4}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&m.name),
            m.path.len(),
            path_largest_settled(&m.path),
            m.path_still.map_or("–".into(), |e| format!("{e:.4}")),
            m.instability.map_or("–".into(), |e| format!("{e:.2}×")),
            match (m.video_jod, m.video_frames) {
                (Some(j), Some(n)) => format!("{j:.2} ({n} frames)"),
                _ => "–".into(),
            },
            frame_list(&m.settle),
            frame_list(&m.settle_stops),
        );
    }
    h.push_str("</table>");
}

/// Frame counts as a comma-separated list, or "–" for none.
fn frame_list(frames: &[u32]) -> String {
    if frames.is_empty() {
        return "–".to_string();
    }
    frames
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Along a path: each method's measured frames, the reference's and the signed error side by
/// side, stepped with a slider (the frames' PNGs are in `frames/`).
fn sequence(h: &mut String, report: &Report) {
    let methods: Vec<&MethodReport> = report
        .methods
        .iter()
        .filter(|m| !m.path.is_empty())
        .collect();
    if methods.is_empty() {
        return;
    }
    h.push_str("<h2>The sequence</h2><p>Each measured frame: the technique, the reference from that frame's camera, and the signed error (its own range per frame). Drag the slider or use the arrow keys.</p>");
    for m in methods {
        let frames: Vec<String> = m.path.iter().map(|p| format!("{:04}", p.frames)).collect();
        let last = frames.len() - 1;
        let _ = write!(
            h,
            r#"<section class="seq" data-method="{name}" data-frames="{frames}" tabindex="0"><h3>{name}</h3>
<div class="controls"><input type="range" min="0" max="{last}" step="1" value="{last}" aria-label="frame"> <span class="which"></span></div>
<div class="frames"><img alt="{name}" width="{w}" height="{hh}"><img alt="reference" width="{w}" height="{hh}"><img alt="signed error" width="{w}" height="{hh}"></div>
</section>"#,
            name = escape(&m.name),
            frames = frames.join("|"),
            w = report.size[0],
            hh = report.size[1],
        );
    }
}

/// A method's section: its image, the reference and the signed error, flipped in place.
fn method_section(h: &mut String, report: &Report, m: &MethodReport) {
    let _ = write!(
        h,
        r#"<section class="flip" id="m-{id}" tabindex="0"><h2>{name}</h2>
<div class="controls"><button data-i="0">1 {name}</button><button data-i="1">2 reference</button><button data-i="2">3 error</button>
<input type="range" min="0" max="2" step="1" value="0" aria-label="method, reference, error"> <span class="which"></span></div>
<div class="frame"><img data-srcs="{img}|{refimg}|{heat}" data-names="{name} (tonemapped)|reference (tonemapped)|signed error, method − reference (grey: excluded)" src="{img}" alt="{name}" width="{w}" height="{hh}"></div>
<div class="legend"><div class="bar"></div><div class="ticks"><span>{lo:+.4}</span><span>0</span><span>{hi:+.4}</span></div></div>
</section>"#,
        id = anchor(&m.name),
        name = escape(&m.name),
        img = escape(&m.image),
        refimg = escape(&report.reference.image),
        heat = escape(&m.heatmap),
        lo = -m.error_range,
        hi = m.error_range,
        w = report.size[0],
        hh = report.size[1],
    );
}

//! Plots as self-contained SVG: the error-against-time fronts of `nearfield pareto` (beside
//! `strip.rs`, the comparison strips).

/// One configuration of a plotted technique.
#[derive(Clone, Copy, Debug)]
pub struct Point<'a> {
    /// Time (log scale).
    pub x: f64,
    /// Error (log scale).
    pub y: f64,
    /// On the front of all series / of its own series.
    pub front: bool,
    pub own_front: bool,
    /// Shown on hover.
    pub label: &'a str,
}

/// One technique's configurations.
#[derive(Clone, Debug)]
pub struct Series<'a> {
    pub name: &'a str,
    pub points: Vec<Point<'a>>,
}

const PALETTE: &[&str] = &[
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// Ticks of a log axis between `lo` and `hi`: 1, 2, 5 × powers of ten.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = decade * m;
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
        decade *= 10.0;
    }
    out
}

fn fmt_tick(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').to_string()
    }
}

/// The plot's size, margins and log axes: where a (time, error) point is drawn.
struct Axes {
    w: f64,
    h: f64,
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
    /// Time and error ranges, with a margin.
    t: (f64, f64),
    e: (f64, f64),
}

fn finite(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

impl Axes {
    fn new(methods: &[Series]) -> Self {
        let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        let pts = methods.iter().flat_map(|m| m.points.iter());
        for p in pts.filter(|p| finite(p.x) && finite(p.y)) {
            t0 = t0.min(p.x);
            t1 = t1.max(p.x);
            e0 = e0.min(p.y);
            e1 = e1.max(p.y);
        }
        if t0 > t1 {
            (t0, t1, e0, e1) = (1.0, 10.0, 0.01, 1.0);
        }
        // A margin of 10 % (in log) on each side.
        let pad = |a: f64, b: f64| {
            let (la, lb) = (a.log10(), b.log10().max(a.log10() + 0.3));
            let m = 0.1 * (lb - la);
            (10f64.powf(la - m), 10f64.powf(lb + m))
        };
        Axes {
            w: 760.0,
            h: 500.0,
            left: 70.0,
            right: 190.0,
            top: 40.0,
            bottom: 55.0,
            t: pad(t0, t1),
            e: pad(e0, e1),
        }
    }

    fn x(&self, t: f64) -> f64 {
        let (t0, t1) = self.t;
        self.left
            + (self.w - self.left - self.right) * (t.log10() - t0.log10())
                / (t1.log10() - t0.log10())
    }

    fn y(&self, e: f64) -> f64 {
        let (e0, e1) = self.e;
        self.h
            - self.bottom
            - (self.h - self.top - self.bottom) * (e.log10() - e0.log10())
                / (e1.log10() - e0.log10())
    }

    /// The points as a polyline's list, in time order (points off the log axes left out).
    fn line(&self, points: Vec<(f64, f64)>) -> String {
        let mut points: Vec<(f64, f64)> = points
            .into_iter()
            .filter(|(t, e)| finite(*t) && finite(*e))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points
            .iter()
            .map(|(t, e)| format!("{:.1},{:.1}", self.x(*t), self.y(*e)))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The title, the grid with its ticks, the frame and the axis labels.
    fn grid(&self, s: &mut String, title: &str, x_label: &str) {
        use std::fmt::Write;
        let Axes {
            w,
            h,
            left,
            right,
            top,
            bottom,
            ..
        } = *self;
        let _ = write!(
            s,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">
<rect width="100%" height="100%" fill="white"/>
<text x="{}" y="22" text-anchor="middle" font-size="14">{}</text>
"##,
            (left + w - right) / 2.0,
            xml(title)
        );
        for t in log_ticks(self.t.0, self.t.1) {
            let _ = writeln!(
                s,
                r##"<line x1="{0:.1}" y1="{1}" x2="{0:.1}" y2="{2}" stroke="#ddd"/><text x="{0:.1}" y="{3}" text-anchor="middle">{4}</text>"##,
                self.x(t),
                top,
                h - bottom,
                h - bottom + 16.0,
                fmt_tick(t)
            );
        }
        for e in log_ticks(self.e.0, self.e.1) {
            let _ = writeln!(
                s,
                r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="#ddd"/><text x="{3}" y="{4:.1}" text-anchor="end">{5}</text>"##,
                left,
                self.y(e),
                w - right,
                left - 6.0,
                self.y(e) + 4.0,
                fmt_tick(e)
            );
        }
        let _ = writeln!(
            s,
            r##"<rect x="{left}" y="{top}" width="{}" height="{}" fill="none" stroke="#444"/>
<text x="{}" y="{}" text-anchor="middle">{}</text>
<text transform="translate(18 {}) rotate(-90)" text-anchor="middle">relative error</text>"##,
            w - left - right,
            h - top - bottom,
            (left + w - right) / 2.0,
            h - 14.0,
            xml(x_label),
            (top + h - bottom) / 2.0
        );
    }

    /// Technique `i`: its own front, its points (the default ringed) and its legend line.
    fn series(&self, s: &mut String, i: usize, m: &Series) {
        use std::fmt::Write;
        let c = PALETTE[i % PALETTE.len()];
        let own: Vec<(f64, f64)> = m
            .points
            .iter()
            .filter(|p| p.own_front)
            .map(|p| (p.x, p.y))
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.8"/>"##,
            self.line(own)
        );
        for (k, p) in m.points.iter().enumerate() {
            if !(finite(p.x) && finite(p.y)) {
                continue;
            }
            let _ = writeln!(
                s,
                r##"<circle cx="{:.1}" cy="{:.1}" r="{}" fill="{}" stroke="{c}" stroke-width="1.5"><title>{} — {:.2} ms, rel {:.4}</title></circle>"##,
                self.x(p.x),
                self.y(p.y),
                if k == 0 { 6.0 } else { 3.5 },
                if k == 0 { "white" } else { c },
                xml(p.label),
                p.x,
                p.y
            );
        }
        let (right_edge, ly) = (self.w - self.right, self.top + 10.0 + 18.0 * i as f64);
        let _ = writeln!(
            s,
            r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="{c}" stroke-width="2"/><circle cx="{3}" cy="{1:.1}" r="3.5" fill="{c}"/><text x="{4}" y="{5:.1}">{6}</text>"##,
            right_edge + 14.0,
            ly,
            right_edge + 38.0,
            right_edge + 26.0,
            right_edge + 44.0,
            ly + 4.0,
            xml(m.name)
        );
    }
}

/// Error (log) against time (log): every configuration a dot, each technique's own front a
/// line, the front of all techniques thick and dashed, defaults ringed.
pub fn pareto_svg(methods: &[Series], title: &str, x_label: &str) -> String {
    use std::fmt::Write;
    let axes = Axes::new(methods);
    let mut s = String::new();
    axes.grid(&mut s, title, x_label);
    let global: Vec<(f64, f64)> = methods
        .iter()
        .flat_map(|m| m.points.iter())
        .filter(|p| p.front)
        .map(|p| (p.x, p.y))
        .collect();
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#000" stroke-width="4" stroke-dasharray="8 5" opacity="0.35"/>"##,
        axes.line(global)
    );
    for (i, m) in methods.iter().enumerate() {
        axes.series(&mut s, i, m);
    }
    let (right_edge, ly) = (
        axes.w - axes.right,
        axes.top + 10.0 + 18.0 * methods.len() as f64,
    );
    let _ = writeln!(
        s,
        r##"<line x1="{0}" y1="{1:.1}" x2="{2}" y2="{1:.1}" stroke="#000" stroke-width="4" stroke-dasharray="8 5" opacity="0.35"/><text x="{3}" y="{4:.1}">front of all</text>
<circle cx="{5}" cy="{6:.1}" r="6" fill="white" stroke="#000" stroke-width="1.5"/><text x="{3}" y="{7:.1}">default</text>
</svg>"##,
        right_edge + 14.0,
        ly,
        right_edge + 38.0,
        right_edge + 44.0,
        ly + 4.0,
        right_edge + 26.0,
        ly + 18.0,
        ly + 22.0
    );
    s
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

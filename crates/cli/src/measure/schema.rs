//! The schemas of the run files: each is written and read by the same type. `metrics.json`
//! (`compare`; [`MetricsFile`], crates/eval), FIT.json (`fit`), pareto.json (`pareto`) and
//! results.json (`examples/figures.rs`, read by the book).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// metrics.json: what `compare` writes (crates/eval's report).
pub use nearfield_eval::report::Report as MetricsFile;

// ---- FIT.json

/// The errors of one side (training or held-out scenes) of a fit, before and after.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FitSide {
    pub before: f64,
    pub after: f64,
    pub per_scene: BTreeMap<String, FitScene>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FitScene {
    pub before: f64,
    pub after: f64,
}

/// FIT.json: what `nearfield fit` writes and the book reads.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FitFile {
    pub method: String,
    pub params: BTreeMap<String, serde_json::Value>,
    pub start: BTreeMap<String, serde_json::Value>,
    pub spec: String,
    pub metric: String,
    pub aov: String,
    pub size: [u32; 2],
    pub frames: u32,
    pub radius: f32,
    pub spp: u32,
    pub train: FitSide,
    pub holdout: FitSide,
    pub evaluations: usize,
    /// Every evaluated point in order: the fitted settings' values and the training error.
    pub history: Vec<(Vec<f64>, f64)>,
    pub stopped: String,
    /// The scenes as given (the tables name them shortly).
    pub scenes: BTreeMap<String, String>,
    pub seconds: f64,
    pub command: String,
    pub adapter: String,
}

// ---- pareto.json

/// A measured configuration.
#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct Point {
    pub label: String,
    pub spec: String,
    /// Median frame time (ms).
    pub ms: f64,
    /// Frame time minus the `none` technique's (ms): what the technique costs.
    pub cost_ms: f64,
    pub error: f64,
    /// On the front of all techniques / of its own technique.
    pub front: bool,
    pub technique_front: bool,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct MethodFront {
    pub name: String,
    pub points: Vec<Point>,
    /// The default's time over the fastest configuration of this technique that is at least as
    /// accurate, minus 1 (0: the default is on its front).
    pub default_slack: f64,
    /// `default_slack` ≤ 0.1: the default is on or near its front.
    pub default_near_front: bool,
}

/// pareto.json: what `nearfield pareto` writes and the book reads.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ParetoFile {
    /// The folder it was read from (the book's; not written).
    #[serde(skip)]
    pub dir: String,
    pub scene: String,
    pub aov: String,
    pub metric: String,
    pub size: [u32; 2],
    pub radius: f32,
    pub frames: u32,
    pub warmup: u32,
    pub timed: u32,
    pub spp: u32,
    pub adapter: String,
    pub timing: String,
    pub none_ms: f64,
    pub methods: Vec<MethodFront>,
    pub command: String,
    pub seconds: f64,
}

// ---- results.json: measured by `examples/figures.rs` into docs/src/generated/results.json,
// ---- rendered into the book's results tables (and the README's headline).

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
    /// When the frame times were measured, where that is later than the runs
    /// (`FIGURES_ONLY=bench` measures them alone); absent: with the runs (`Results::date`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub date: Option<String>,
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

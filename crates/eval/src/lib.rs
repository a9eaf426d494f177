//! Comparing a technique's AOV with the reference: masks, error metrics, FLIP, images and the
//! HTML report. No GPU and no tracer here: inputs are float RGBA images (alpha = surface
//! coverage) plus view depth.

pub mod image_ops;
pub mod metrics;
pub mod plot;
pub mod report;
pub mod strip;
pub mod video;

pub use metrics::{Mask, MaskSettings, Metrics};

/// A file from the shared assets (`../shared/assets` beside the repository), for tests that
/// measure on real data: `Some(path)` when it is there; `None` when it is not, which is an error
/// (a panic) under `REQUIRE_GPU=1`, where CI runs every measurement.
pub fn shared_asset(relative: &str) -> Option<std::path::PathBuf> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/assets")
        .join(relative);
    if path.exists() {
        return Some(path);
    }
    assert!(
        std::env::var("REQUIRE_GPU").as_deref() != Ok("1"),
        "{} missing",
        path.display()
    );
    None
}

//! Comparing a technique's AOV with the reference: masks, error metrics, FLIP, images and the
//! HTML report. No GPU and no tracer here: inputs are float RGBA images (alpha = surface
//! coverage) plus view depth.

pub mod image_ops;
pub mod metrics;
pub mod report;

pub use metrics::{Mask, MaskSettings, Metrics};

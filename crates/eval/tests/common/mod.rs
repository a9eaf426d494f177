//! Helpers of the GPU-against-reference tests: the adapter, and `compare`'s metrics of a
//! rendered AOV.
#![allow(dead_code)]

use nearfield_eval::metrics::{self, Mask, MaskSettings, Metrics};
use nearfield_reference::ReferenceImage;
use nearfield_render::{Aov, GpuContext, Renderer};

/// The test adapter, or None (test skipped) when there is none — unless `REQUIRE_GPU=1`, which
/// turns a missing adapter into a failure (CI sets it).
pub fn context() -> Option<GpuContext> {
    match GpuContext::new(None) {
        Ok(c) => Some(c),
        Err(e) if std::env::var("REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("REQUIRE_GPU=1 but {e}")
        }
        Err(_) => None,
    }
}

/// Metrics of `aov` of `r`'s last frame against `reference`, masked as `compare` masks by
/// default (2 px border, silhouettes where the depths differ by more than 1 %).
pub fn masked_metrics(r: &mut Renderer, aov: Aov, reference: &ReferenceImage) -> Metrics {
    let size = r.size();
    let img = r.read_aov(aov);
    let depth: Vec<f32> = r.read_aov(Aov::Depth).pixels.iter().map(|p| p[0]).collect();
    let alpha: Vec<f32> = img.pixels.iter().map(|p| p[3]).collect();
    let ref_alpha: Vec<f32> = reference.value.iter().map(|p| p[3]).collect();
    let mask = Mask::new(
        size,
        &alpha,
        &depth,
        &ref_alpha,
        &reference.depth,
        MaskSettings {
            border: 2,
            depth_tolerance: 0.01,
        },
    );
    metrics::metrics(&img.pixels, &reference.value, &mask)
}

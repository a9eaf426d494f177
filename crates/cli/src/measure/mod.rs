//! The measuring service that `fit` and `pareto` share: a [`Metric`], the [`Truth`] of an AOV
//! (the reference, its mask) and a [`Target`] (a scene's renderer with its truths) that measures
//! a technique spec as `compare` does; and the run files' schemas ([`schema`]).

pub mod schema;

use anyhow::Result;
use nearfield_eval::image_ops;
use nearfield_eval::metrics::{self, Mask, MaskSettings};
use nearfield_render::{Aov, Renderer};

/// The error measure a fit minimises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    Relative,
    Rmse,
    Flip,
}

impl Metric {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "rel" => Some(Metric::Relative),
            "rmse" => Some(Metric::Rmse),
            "flip" => Some(Metric::Flip),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Metric::Relative => "rel",
            Metric::Rmse => "rmse",
            Metric::Flip => "flip",
        }
    }

    /// This metric of `test` against `reference` within `mask` (`ref_srgb`: the reference
    /// tonemapped, for FLIP).
    pub fn measure(
        self,
        test: &nearfield_render::AovImage,
        reference: &[[f32; 4]],
        ref_srgb: &image::RgbImage,
        mask: &Mask,
    ) -> f64 {
        match self {
            Metric::Relative => metrics::metrics(&test.pixels, reference, mask).relative_error,
            Metric::Rmse => metrics::metrics(&test.pixels, reference, mask).rmse,
            Metric::Flip => metrics::flip_mean(
                &image_ops::tonemap(&test.pixels, test.width, test.height),
                ref_srgb,
                mask,
            ),
        }
    }
}

/// One AOV of one scene: the truth it is measured against.
pub struct Truth {
    pub aov: Aov,
    pub reference: Vec<[f32; 4]>,
    pub ref_srgb: image::RgbImage,
    /// Made from the first rendering (coverage and depth do not depend on the settings).
    pub mask: Option<Mask>,
    /// Where the reference's coverage and depth come from, for the mask.
    pub ref_alpha: Vec<f32>,
    pub ref_depth: Vec<f32>,
}

impl Truth {
    /// The truth of `aov` from a reference image (value, coverage in alpha, depth).
    pub fn new(aov: Aov, reference: Vec<[f32; 4]>, depth: Vec<f32>, size: (u32, u32)) -> Self {
        Truth {
            aov,
            ref_srgb: image_ops::tonemap(&reference, size.0, size.1),
            ref_alpha: reference.iter().map(|p| p[3]).collect(),
            reference,
            mask: None,
            ref_depth: depth,
        }
    }
}

impl Truth {
    /// Whether the reference is zero on every covered pixel.
    pub fn is_zero(&self) -> bool {
        self.reference
            .iter()
            .all(|p| p[3] <= 0.0 || p[0].abs() + p[1].abs() + p[2].abs() == 0.0)
    }
}

/// One scene of a fit: its renderer (reused by every evaluation) and its truths.
pub struct Target {
    pub name: String,
    pub renderer: Renderer,
    pub truths: Vec<Truth>,
}

impl Target {
    /// The error of the settings `spec` on this scene: the mean of `metric` over its AOVs after
    /// `frames` frames from a restart.
    pub fn evaluate(
        &mut self,
        spec: &str,
        params: &nearfield_render::TechniqueParams,
        frames: u32,
        metric: Metric,
    ) -> Result<f64> {
        match self.renderer.set_technique(spec, params) {
            Ok(()) => {}
            // A combination the technique refuses (settings that constrain each other) is no
            // candidate: the search moves away from it.
            Err(nearfield_render::RenderError::Setting { .. }) => return Ok(f64::INFINITY),
            Err(e) => return Err(e.into()),
        }
        self.renderer.restart();
        for i in 0..frames {
            self.renderer.render_frame();
            if i % 8 == 7 {
                self.renderer.wait();
            }
        }
        let mut sum = 0.0;
        let border = crate::compare::default_border(self.renderer.size());
        for t in &mut self.truths {
            let value = self.renderer.read_aov(t.aov);
            if t.mask.is_none() {
                t.mask = Some(crate::compare::gpu_mask(
                    &mut self.renderer,
                    &value,
                    &t.ref_alpha,
                    &t.ref_depth,
                    MaskSettings {
                        border,
                        depth_tolerance: 0.01,
                    },
                    None,
                ));
            }
            let mask = t.mask.as_ref().expect("made above");
            sum += metric.measure(&value, &t.reference, &t.ref_srgb, mask);
        }
        self.renderer.check_device()?;
        Ok(sum / self.truths.len().max(1) as f64)
    }
}

/// The mean of `v` (0 when it is empty).
pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

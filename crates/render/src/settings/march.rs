//! The slice march's settings that gtao, hbil and vbgi share (technique/horizon): declared once,
//! flattened into each family's settings (`@first { march: MarchSettings }`).

use crate::{choice, declare_settings};

choice! {
    /// How last frame's pixels reach this frame.
    pub enum ReprojectMode {
        /// Forward: last frame's pixels move to their new place (depth-tested, atomics).
        Scatter = "scatter",
        /// Backward: this frame's pixels fetch through their motion vectors.
        Gather = "gather",
    }
}

choice! {
    /// Where the near-field radiance comes from (hbil, vbgi).
    pub enum Source {
        /// Last frame's diffuse radiance, reprojected (bounces accumulate, HBIL Eq. 17); this
        /// frame's direct radiance on the first frame and after a cut.
        Previous = "previous",
        /// This frame's direct radiance every frame (exactly one bounce, L_o of docs/src/aovs.md).
        Direct = "direct",
    }
}

choice! {
    /// Where the slice march runs (gtao, hbil, vbgi).
    pub enum Resolution {
        /// At every pixel.
        Full = "full",
        /// At one pixel of each 2×2 block, brought to every pixel by an edge-aware upsample.
        Half = "half",
    }
}

declare_settings! {
    /// The shared slice march: slices, steps, radius, interleaving, the radiance source and its
    /// reprojection, the running mean, the step distribution and the sender rejection.
    pub struct MarchSettings {
        slices: u32 = "2", integer(1, 32), count, "", "slices per pixel S (with interleaving a 4×4 block covers 16·S directions)";
        steps: u32 = "16", integer(1, 128), count, "", "samples per side of a slice (`samples`, `--samples`)";
        radius: f32 = "0.5", log(1e-6, 1e6), uniform, "m", "near-field radius R (`--radius`; finite); only occluders within R count";
        interleaved: bool = "on", toggle, structural, "", "4×4 deinterleaved quarter-resolution layers (HBIL Sec. 3.3)";
        resolution: Resolution = "full", choice, structural("gtao", "hbil", "vbgi"), "", "`half`: the search at one pixel of each 2×2 block (the four in turn over frames), brought to every pixel by a depth- and normal-aware bilinear upsample (a quarter of the search's work; `interleaved` does not apply)";
        reprojection: ReprojectMode = "scatter", choice, structural("hbil", "vbgi"), "", "`scatter` (forward, atomic depth test) then push/pull, or `gather` through motion vectors then push/pull";
        source: Source = "previous", choice, structural("hbil", "vbgi"), "", "near-field radiance: `previous` last frame's diffuse radiance, reprojected (bounces add up, Eq. 17); `direct` this frame's direct radiance (exactly one bounce)";
        temporal: bool = "on", toggle, denoiser, "", "running mean over frames, disocclusion-rejected (in svgf with `denoise=svgf`)";
        history: u32 = "32", integer(1, 1024), filter, "", "frames in the running mean at most";
        fresnel: bool = "on", toggle, uniform("hbil", "vbgi"), "", "(1 − F0) of the receiver on near-field light (Eq. 19)";
        step_power: f32 = "2", number(1, 4), uniform, "", "step distribution t_j ∝ ((j + ξ)/steps)^p (denser near the pixel)";
        max_pixels: f32 = "256", log(1, 8192), uniform, "pixels", "longest march (full resolution)";
        reject_a: f32 = "-0.1", number(-1, 1), uniform("hbil", "vbgi"), "", "sender rejection (HBIL Sec. 3.4): lower smoothstep edge on −n′·ω (< `reject_b`)";
        reject_b: f32 = "0.1", number(-1, 1), uniform("hbil", "vbgi"), "", "sender rejection: upper smoothstep edge";
        blur_radius: u32 = "4", integer(0, 16), filter, "pixels", "blur half width with `denoise=bilateral` (Gaussian σ = radius/2; 4 weighs a 4×4 block nearly evenly)";
        reject_depth: f32 = "0.02", log(1e-4, 1), uniform, "", "history/reprojection: largest distance from the current tangent plane, relative to view depth";
        reject_normal: f32 = "0.9", number(-1, 1), uniform, "", "history/reprojection: smallest cosine between the normals";
    }
}

/// What the declarations cannot check or imply alone: the sender rejection's edges in order, and
/// no 4×4 deinterleave at half resolution.
pub fn settle_march(m: &mut MarchSettings) -> Result<(), String> {
    if m.reject_a >= m.reject_b {
        return Err(format!(
            "reject_a {} must be below reject_b {}",
            m.reject_a, m.reject_b
        ));
    }
    // Half resolution marches full-resolution pixels, one of each 2×2 block: the 4×4
    // deinterleave does not apply.
    if m.resolution == Resolution::Half {
        m.interleaved = false;
    }
    Ok(())
}

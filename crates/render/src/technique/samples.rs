//! The hemisphere samples of the sampling techniques (ssao, ssdo, s3ho, ssbn): the WGSL of the
//! sample patterns and the screen-space visibility test (samples.wgsl, senders.wgsl), and the
//! interleaved sample sets that pattern reads.

/// WGSL library: hemisphere sample patterns and the screen-space visibility test (its images
/// and views as parameters).
pub const SAMPLES_WGSL: &str = include_str!("samples.wgsl");
/// WGSL library: the bounce's sender patches (after [`SAMPLES_WGSL`]).
pub const SENDERS_WGSL: &str = include_str!("senders.wgsl");
/// Glue (declares nothing, reads the bindings of the passes that include it under the same
/// names): the blocker test over the main view, its layers and the additional cameras, which
/// indexes the pass's `layer_views` storage array (ssdo direct and bounce, s3ho sample).
pub const LAYERS_GLUE_WGSL: &str = include_str!("layers_glue.wgsl");

/// A sampling technique's parameters' uniform (`params`, its bytes) and the interleaved sample
/// sets of `samples` directions ([`interleaved_sets`]), labelled by `technique`.
pub fn buffers(
    device: &wgpu::Device,
    technique: &str,
    params: &[u8],
    samples: u32,
) -> (wgpu::Buffer, wgpu::Buffer) {
    use wgpu::util::DeviceExt;
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(&format!("{technique} params")),
        contents: params,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let sample_sets = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(&format!("{technique} sample sets")),
        contents: bytemuck::cast_slice(&interleaved_sets(samples)),
        usage: wgpu::BufferUsages::STORAGE,
    });
    (params, sample_sets)
}

/// The paper's M×N sample texture with M = 4×4 sets: set m, sample i has a stratified elevation
/// cos θ = 1 − (i + ½)/N (uniform solid angle, so every sample stands for Δω = 2π/N), an azimuth
/// from the base-2 radical inverse and a length λ/R = v^(1/3) (points uniform in the hemisphere's
/// volume, as in samples.wgsl) from the base-3 radical inverse v of i, each rotated
/// (Cranley–Patterson) by the m-th point of the R2 sequence so that the 16 sets differ.
pub fn interleaved_sets(n: u32) -> Vec<[f32; 4]> {
    fn radical_inverse(mut i: u32, base: u32) -> f32 {
        let (mut f, mut r) = (1.0 / base as f64, 0.0f64);
        while i > 0 {
            r += f * (i % base) as f64;
            i /= base;
            f /= base as f64;
        }
        r as f32
    }
    let g = 1.324_717_957_244_746f64;
    let mut out = Vec::with_capacity(16 * n as usize);
    for m in 0..16u32 {
        let o1 = ((m as f64 + 1.0) / g).fract() as f32;
        let o2 = ((m as f64 + 1.0) / (g * g)).fract() as f32;
        for i in 0..n {
            let cos_e = 1.0 - (i as f32 + 0.5) / n as f32;
            let sin_e = (1.0 - cos_e * cos_e).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * (radical_inverse(i, 2) + o1).fract();
            let lambda = ((radical_inverse(i, 3) + o2).fract())
                .max(0.5 / n as f32)
                .cbrt();
            out.push([sin_e * phi.cos(), sin_e * phi.sin(), cos_e, lambda]);
        }
    }
    out
}

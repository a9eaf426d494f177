//! Reference images as OpenEXR: channels R, G, B (the AOV), A (1 on surfaces, 0 on background),
//! `stderr.R`, `stderr.G`, `stderr.B` (standard error of the mean) and `Z` (view depth, m), all
//! 32-bit float.

use crate::ReferenceImage;
use exr::prelude::*;
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum ExrError {
    #[error("{path}: no such file")]
    Missing { path: String },
    #[error("{path}: not a readable OpenEXR image: {msg}")]
    Read { path: String, msg: String },
    #[error("{path}: cannot write: {msg}")]
    Write { path: String, msg: String },
}

pub fn write(img: &ReferenceImage, path: &Path) -> std::result::Result<(), ExrError> {
    let size = (img.width as usize, img.height as usize);
    let channel = |name: &str, f: &dyn Fn(usize) -> f32| {
        AnyChannel::new(
            name,
            FlatSamples::F32((0..size.0 * size.1).map(f).collect()),
        )
    };
    let channels = AnyChannels::sort(smallvec::smallvec![
        channel("R", &|i| img.value[i][0]),
        channel("G", &|i| img.value[i][1]),
        channel("B", &|i| img.value[i][2]),
        channel("A", &|i| img.value[i][3]),
        channel("stderr.R", &|i| img.stderr[i][0]),
        channel("stderr.G", &|i| img.stderr[i][1]),
        channel("stderr.B", &|i| img.stderr[i][2]),
        channel("Z", &|i| img.depth[i]),
    ]);
    let layer = Layer::new(
        size,
        LayerAttributes::named("reference"),
        Encoding::FAST_LOSSLESS,
        channels,
    );
    // Atomically: the reference cache is read by other processes.
    nearfield_scene::atomic::write_atomically(path, |tmp| {
        Image::from_layer(layer).write().to_file(tmp)
    })
    .map_err(|msg| ExrError::Write {
        path: path.display().to_string(),
        msg,
    })
}

/// Reads an EXR written by [`write`], or any EXR with R, G, B channels (A defaults to 1,
/// stderr to 0, Z to 0 = unknown).
pub fn read(path: &Path) -> std::result::Result<ReferenceImage, ExrError> {
    if !path.is_file() {
        return Err(ExrError::Missing {
            path: path.display().to_string(),
        });
    }
    let err = |msg: String| ExrError::Read {
        path: path.display().to_string(),
        msg,
    };
    let image = read_all_flat_layers_from_file(path).map_err(|e| err(e.to_string()))?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| err("no layer".into()))?;
    let (w, h) = (layer.size.0, layer.size.1);
    if w == 0 || h == 0 {
        return Err(err("empty image".into()));
    }
    let find = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .map(|c| c.sample_data.values_as_f32().collect::<Vec<f32>>())
    };
    let r = find("R").ok_or_else(|| err("no R channel".into()))?;
    let g = find("G").ok_or_else(|| err("no G channel".into()))?;
    let b = find("B").ok_or_else(|| err("no B channel".into()))?;
    let a = find("A").unwrap_or_else(|| vec![1.0; w * h]);
    let zero = vec![0.0; w * h];
    let (sr, sg, sb) = (
        find("stderr.R").unwrap_or_else(|| zero.clone()),
        find("stderr.G").unwrap_or_else(|| zero.clone()),
        find("stderr.B").unwrap_or_else(|| zero.clone()),
    );
    let z = find("Z").unwrap_or(zero);
    Ok(ReferenceImage {
        width: w as u32,
        height: h as u32,
        value: (0..w * h).map(|i| [r[i], g[i], b[i], a[i]]).collect(),
        stderr: (0..w * h).map(|i| [sr[i], sg[i], sb[i]]).collect(),
        depth: z,
        rays: 0,
    })
}

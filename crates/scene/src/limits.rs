//! The documented limits on what a scene, texture or environment file may ask for. Each is
//! checked *before* the memory it implies is allocated (image sizes from their headers, counts
//! from accessors and PLY headers), so that a hostile file gets one clear error instead of an
//! allocation the machine cannot make.

use crate::SceneError;
use std::path::Path;

/// Triangles in one scene, over all meshes and instances.
pub const MAX_TRIANGLES: usize = 1 << 24;
/// Vertices in one scene, over all meshes and instances.
pub const MAX_VERTICES: usize = 1 << 24;
/// Largest side of a texture (PNG, JPEG) in pixels.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Texels in one texture (PNG, JPEG): 64 Mi, 256 MiB as RGBA8.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 26;
/// Largest side of an environment map (HDR, EXR).
pub const MAX_ENVIRONMENT_SIDE: u32 = 16384;
/// Texels in one environment map: 8192×4096, 384 MiB as RGB32F.
pub const MAX_ENVIRONMENT_PIXELS: u64 = 8192 * 4096;
/// Bytes in one file a scene refers to (a glTF buffer or image, a scene file itself).
pub const MAX_FILE_BYTES: u64 = 4 << 30;
/// Largest magnitude of a position or transform entry, in metres.
pub const MAX_COORDINATE: f32 = 1e20;
/// Nodes in one glTF file.
pub const MAX_NODES: usize = 1 << 20;

/// Checks an image's header dimensions against a side and pixel-count limit; `what` names it
/// ("texture", "environment map").
pub fn check_image_size(
    width: u32,
    height: u32,
    max_side: u32,
    max_pixels: u64,
    what: &str,
) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the {what} is empty ({width}×{height})"));
    }
    if width > max_side || height > max_side || width as u64 * height as u64 > max_pixels {
        return Err(format!(
            "the {what} is {width}×{height}, beyond the limit of {max_side} per side and {} \
             Mi texels",
            max_pixels >> 20
        ));
    }
    Ok(())
}

/// Limits for the `image` crate's decoders matching a side and pixel limit (with room for the
/// decoder's own buffers), so that even a header that lies cannot make it allocate more.
pub fn decoder_limits(max_side: u32, max_pixels: u64, bytes_per_pixel: u64) -> image::Limits {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_side);
    limits.max_image_height = Some(max_side);
    limits.max_alloc = Some(max_pixels * bytes_per_pixel * 2 + (64 << 20));
    limits
}

/// Decodes an image from memory after checking its header against the limits; errors are one
/// line.
pub fn decode_image(
    bytes: &[u8],
    max_side: u32,
    max_pixels: u64,
    what: &str,
) -> Result<image::DynamicImage, String> {
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    let (w, h) = reader()?
        .into_dimensions()
        .map_err(|e| format!("cannot read the {what}: {e}"))?;
    check_image_size(w, h, max_side, max_pixels, what)?;
    let mut r = reader()?;
    r.limits(decoder_limits(max_side, max_pixels, 16));
    r.decode()
        .map_err(|e| format!("cannot decode the {what}: {e}"))
}

/// Fails when `path` is not a regular file of at most [`MAX_FILE_BYTES`] (a device such as
/// `/dev/zero`, a directory, a FIFO would never end or not be a file at all).
pub fn check_regular_file(path: &Path) -> Result<u64, SceneError> {
    let meta = std::fs::metadata(path).map_err(|e| crate::load::io_error(path, e))?;
    if !meta.is_file() {
        return Err(SceneError::Invalid {
            path: path.to_path_buf(),
            what: "not a regular file".into(),
        });
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(SceneError::Invalid {
            path: path.to_path_buf(),
            what: format!(
                "{} bytes, beyond the limit of {} GiB",
                meta.len(),
                MAX_FILE_BYTES >> 30
            ),
        });
    }
    Ok(meta.len())
}

/// Whether a coordinate is finite and within [`MAX_COORDINATE`].
pub fn sane(x: f32) -> bool {
    x.is_finite() && x.abs() <= MAX_COORDINATE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_size_limits() {
        assert!(check_image_size(16384, 4096, 16384, MAX_TEXTURE_PIXELS, "texture").is_ok());
        assert!(check_image_size(16385, 1, 16384, MAX_TEXTURE_PIXELS, "texture").is_err());
        assert!(check_image_size(16384, 8192, 16384, MAX_TEXTURE_PIXELS, "texture").is_err());
        assert!(check_image_size(0, 8, 16384, MAX_TEXTURE_PIXELS, "texture").is_err());
    }

    #[test]
    fn a_png_header_beyond_the_limit_is_refused_before_decoding() {
        // A valid PNG signature and IHDR claiming 100000×100000, with no image data.
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
        png.extend(100_000u32.to_be_bytes());
        png.extend(100_000u32.to_be_bytes());
        png.extend([8, 6, 0, 0, 0]);
        let crc = png[12..].iter().fold(!0u32, |mut c, &b| {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    (c >> 1) ^ 0xEDB8_8320
                } else {
                    c >> 1
                };
            }
            c
        });
        png.extend((!crc).to_be_bytes());
        // An empty IDAT chunk (CRC of "IDAT") so that the header can be read through.
        png.extend(b"\0\0\0\0IDAT\x35\xaf\x06\x1e");
        let e = decode_image(&png, MAX_TEXTURE_SIDE, MAX_TEXTURE_PIXELS, "texture").unwrap_err();
        assert!(e.contains("100000×100000"), "{e}");
    }
}

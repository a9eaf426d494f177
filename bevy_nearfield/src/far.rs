//! The far field in Bevy: `nearfield bake --format bevy`'s KTX2, read once, as Bevy's
//! `IrradianceVolume` (docs/src/bevy.md, "The far field").
//!
//! The file is a 3D RGBA16F texture of Bevy 0.20's ambient-cube layout. Each texel holds
//! E(±axis)/π of the scene as the bake lit it: in cd/m² where the scene's lights are in lux and
//! candela and its environment in cd/m², so that the volume is read at intensity 1 beside the
//! same lights (the file's `intensity` undoes a power of two that kept values in half range).
//! Its key/value entry `nearfield.transform` places it: translation, scale and intensity; the
//! entry `nearfield.volume` carries the baked volume itself, which the near-field techniques of
//! the cameras with a `NearField` read as their far field ([`NearFieldVolume`]), so that Bevy's
//! volume and the technique's light are counted once (docs/src/bevy.md, "Counted once").

use bevy::asset::RenderAssetUsages;
use bevy::light::{IrradianceVolume, LightProbe};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_resource::ExtractResource;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use nearfield_scene::probes::ProbeVolume;
use nearfield_scene::probes::bevy::{KEY_TRANSFORM, KEY_VOLUME};
use std::path::Path;
use std::sync::Arc;

/// The baked volume the near-field techniques read as their far field: the light from beyond R
/// in the directions they find free, and the volume's own occlusion within R. [`BakedVolume::spawn`]
/// inserts it; without it the techniques read the camera's environment map as their sky
/// (docs/src/bevy.md, "The camera's environment map"), or a white sky where it has none.
#[derive(Resource, Clone, ExtractResource)]
#[extract_app(RenderApp)]
pub struct NearFieldVolume(pub Arc<ProbeVolume>);

/// A baked volume as Bevy places it.
#[derive(Clone, Debug)]
pub struct BakedVolume {
    /// The ambient-cube texture (3D, `Rgba16Float`).
    pub voxels: Image,
    /// The grid's box: translation and scale, no rotation.
    pub transform: Transform,
    /// The `IrradianceVolume::intensity` that reads the texels in the bake's units.
    pub intensity: f32,
    /// The baked volume (the file's `nearfield.volume`; None in a file without it).
    pub volume: Option<Arc<ProbeVolume>>,
}

impl BakedVolume {
    /// Reads `nearfield bake --format bevy`'s file.
    pub fn read(path: &Path) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::from_ktx2(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses the KTX2 bytes; a file that the bake did not write is refused.
    pub fn from_ktx2(bytes: &[u8]) -> Result<Self, String> {
        let reader = ktx2::Reader::new(bytes).map_err(|e| format!("not a KTX2 file ({e:?})"))?;
        let h = reader.header();
        if h.format != Some(ktx2::Format::R16G16B16A16_SFLOAT) || h.pixel_depth == 0 {
            return Err(
                "not a 3D RGBA16F texture (nearfield bake --format bevy writes one)".into(),
            );
        }
        let value = |key: &str| {
            reader
                .key_value_data()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| v.strip_suffix(&[0]).unwrap_or(v))
        };
        let volume = value(KEY_VOLUME)
            .map(|bytes| ProbeVolume::from_bytes(bytes, Path::new(KEY_VOLUME)))
            .transpose()
            .map_err(|e| e.to_string())?
            .map(Arc::new);
        let json = value(KEY_TRANSFORM)
            .map(|v| String::from_utf8_lossy(v).to_string())
            .ok_or("no nearfield.transform: not written by nearfield bake --format bevy")?;
        let t: serde_json::Value =
            serde_json::from_str(&json).map_err(|e| format!("nearfield.transform: {e}"))?;
        let v3 = |k: &str| -> Option<Vec3> {
            let a = t.get(k)?.as_array()?;
            let c = |i: usize| a.get(i)?.as_f64().map(|x| x as f32);
            Some(Vec3::new(c(0)?, c(1)?, c(2)?)).filter(|v| v.is_finite())
        };
        let (Some(translation), Some(scale)) = (v3("translation"), v3("scale")) else {
            return Err("nearfield.transform without a finite translation and scale".into());
        };
        let intensity = t.get("intensity").and_then(|i| i.as_f64()).unwrap_or(1.0) as f32;
        if !(intensity.is_finite() && intensity > 0.0) || scale.min_element() <= 0.0 {
            return Err(format!(
                "nearfield.transform: intensity {intensity} and scale {scale} must be > 0"
            ));
        }
        let level = reader.levels().next().ok_or("no image level")?;
        let texels = h.pixel_width as usize * h.pixel_height as usize * h.pixel_depth as usize;
        if level.data.len() != texels * 8 {
            return Err(format!(
                "level 0 holds {} bytes, not the {} of {}×{}×{} RGBA16F texels (a supercompressed or cut file)",
                level.data.len(),
                texels * 8,
                h.pixel_width,
                h.pixel_height,
                h.pixel_depth
            ));
        }
        let voxels = Image::new(
            Extent3d {
                width: h.pixel_width,
                height: h.pixel_height,
                depth_or_array_layers: h.pixel_depth,
            },
            TextureDimension::D3,
            level.data.to_vec(),
            TextureFormat::Rgba16Float,
            RenderAssetUsages::RENDER_WORLD,
        );
        Ok(BakedVolume {
            voxels,
            transform: Transform::from_translation(translation).with_scale(scale),
            intensity,
            volume,
        })
    }

    /// Spawns the volume as Bevy's light probe, at the file's intensity, and makes the baked
    /// volume the far field of every `NearField` ([`NearFieldVolume`]).
    pub fn spawn(self, commands: &mut Commands, images: &mut Assets<Image>) -> Entity {
        if let Some(v) = self.volume {
            commands.insert_resource(NearFieldVolume(v));
        }
        commands
            .spawn((
                LightProbe::default(),
                IrradianceVolume {
                    voxels: images.add(self.voxels),
                    intensity: self.intensity,
                    ..default()
                },
                self.transform,
            ))
            .id()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small baked volume as `nearfield bake --format bevy` writes it.
    fn file() -> Vec<u8> {
        let grid = nearfield_scene::probes::ProbeGrid::with_counts(
            nearfield_scene::Aabb {
                min: glam::Vec3::ZERO,
                max: glam::Vec3::splat(2.0),
            },
            [2, 2, 2],
        )
        .unwrap();
        let n = grid.count();
        let mut sh = [glam::Vec3::ZERO; nearfield_scene::probes::SH_COEFFS];
        sh[0] = glam::Vec3::splat(1.0);
        let tile = (nearfield_scene::probes::VIS_TILE * nearfield_scene::probes::VIS_TILE) as usize;
        let volume = ProbeVolume {
            grid,
            max_distance: 3.0,
            probes: vec![
                nearfield_scene::probes::Probe {
                    offset: glam::Vec3::ZERO,
                    active: true,
                    sh,
                };
                n
            ],
            visibility: vec![[1.0, 1.0]; n * tile],
            rays: 1,
            bounces: 0,
            key: 0,
        };
        nearfield_scene::probes::bevy::BevyVolume::from_volume(&volume).to_ktx2()
    }

    #[test]
    fn the_bakes_file_is_read_with_its_volume() {
        let v = BakedVolume::from_ktx2(&file()).unwrap();
        assert_eq!(v.intensity, 1.0);
        assert_eq!(v.volume.as_ref().map(|v| v.probes.len()), Some(8));
    }

    #[test]
    fn a_bad_file_is_one_error() {
        let good = file();
        let mut foreign = good.clone();
        let key = b"nearfield.transform";
        let at = foreign.windows(key.len()).position(|w| w == key).unwrap();
        foreign[at] = b'x';
        for (bytes, want) in [
            (b"not a ktx2 file".to_vec(), "not a KTX2 file"),
            (good[..good.len() / 2].to_vec(), "not a KTX2 file"),
            (foreign, "no nearfield.transform"),
        ] {
            let e = BakedVolume::from_ktx2(&bytes).unwrap_err();
            assert!(e.contains(want) && !e.contains('\n'), "{e}");
        }
    }
}

//! `nearfield bake --format bevy` writes the ambient-cube texture Bevy's `IrradianceVolume`
//! reads: read back with the `ktx2` crate, it has Bevy's documented layout (Rx × 2Ry × 3Rz,
//! RGBA16F, the X, Y, Z slabs along z, each slab's negative side at y + Ry), R = the probe
//! counts × SUBDIVISION + 2 PAD over the grid's box grown by a voxel, and every texel is the
//! volume's own lookup E(±axis)/π for a surface at that voxel facing that side (the `.nfv`
//! baked with the same settings), and the file carries that volume itself.

use nearfield_scene::probes::{
    ProbeVolume,
    bevy::{PAD, SUBDIVISION, VK_FORMAT_R16G16B16A16_SFLOAT},
};
use std::process::Command;

fn bake(args: &[&str], cache: &std::path::Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .arg("bake")
        .args(args)
        .env("NEARFIELD_CACHE", cache)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn bevy_volume_has_bevys_layout_and_our_irradiance() {
    let dir = std::env::temp_dir().join(format!("nearfield-bevy-volume-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let nfv = dir.join("v.nfv");
    let ktx = dir.join("v.ktx2");
    let common = [
        "builtin:two-rooms",
        "--probes",
        "5,3,4",
        "--rays",
        "128",
        "--bounces",
        "1",
    ];
    bake(
        &[&common[..], &["--out", nfv.to_str().unwrap()]].concat(),
        &dir,
    );
    bake(
        &[
            &common[..],
            &["--format", "bevy", "--out", ktx.to_str().unwrap()],
        ]
        .concat(),
        &dir,
    );

    let volume = ProbeVolume::read(&nfv).unwrap();
    let bytes = std::fs::read(&ktx).unwrap();
    let reader = ktx2::Reader::new(&bytes[..]).expect("a valid KTX2 file");
    let h = reader.header();
    assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
    assert_eq!(
        h.format.map(|f| f.value()),
        Some(VK_FORMAT_R16G16B16A16_SFLOAT)
    );
    // SUBDIVISION voxels per spacing, and a voxel more on each side (Bevy's box ends at
    // weight 0).
    let r = volume.grid.counts.map(|c| c * SUBDIVISION + 2 * PAD);
    assert_eq!(
        (h.pixel_width, h.pixel_height, h.pixel_depth),
        (r[0], 2 * r[1], 3 * r[2])
    );
    assert_eq!((h.level_count, h.face_count, h.layer_count), (1, 1, 0));
    // The data format descriptor says linear RGBA, 16-bit signed floats.
    let dfd = reader
        .dfd_blocks()
        .next()
        .expect("a data format descriptor");
    let basic = ktx2::DfdBlockBasic::parse(dfd.data).expect("a basic descriptor block");
    assert_eq!(basic.header.color_model, Some(ktx2::ColorModel::RGBSDA));
    assert_eq!(
        basic.header.transfer_function,
        Some(ktx2::TransferFunction::Linear)
    );
    let samples: Vec<_> = basic.sample_information().collect();
    assert_eq!(samples.len(), 4);
    let channels: Vec<u8> = samples.iter().map(|s| s.channel_type).collect();
    assert_eq!(channels, [0, 1, 2, 15], "R, G, B, A");
    assert!(samples.iter().all(|s| {
        s.bit_length.get() == 16
            && s.channel_type_qualifiers
                .contains(ktx2::ChannelTypeQualifiers::FLOAT)
    }));
    let transform = reader
        .key_value_data()
        .find(|(k, _)| *k == "nearfield.transform")
        .map(|(_, v)| {
            String::from_utf8_lossy(v)
                .trim_end_matches('\0')
                .to_string()
        })
        .expect("the transform in the key/value data");
    let transform: serde_json::Value = serde_json::from_str(&transform).unwrap();
    let g = &volume.grid;
    let step = g.spacing / SUBDIVISION as f32;
    let mut box_min = glam::Vec3::ZERO;
    for a in 0..3 {
        let scale = transform["scale"][a].as_f64().unwrap() as f32;
        let centre = transform["translation"][a].as_f64().unwrap() as f32;
        let extent = step[a] * r[a] as f32;
        assert!((scale - extent).abs() < 1e-4 * extent, "scale {a}");
        // the grid's box (the probes' cells) is the texture's less a voxel on each side
        let first_cell = centre - 0.5 * scale + step[a];
        assert!(
            (first_cell - (g.origin[a] - 0.5 * g.spacing[a])).abs() < 1e-4,
            "translation {a}"
        );
        box_min[a] = centre - 0.5 * scale;
    }
    assert_eq!(transform["intensity"].as_f64(), Some(1.0));
    // The baked volume itself rides along (NUL-terminated), for the plugin's techniques.
    let carried = reader
        .key_value_data()
        .find(|(k, _)| *k == nearfield_scene::probes::bevy::KEY_VOLUME)
        .map(|(_, v)| v.strip_suffix(&[0]).unwrap_or(v))
        .expect("the volume in the key/value data");
    let carried = ProbeVolume::from_bytes(carried, &ktx).expect("a volume");
    assert_eq!(carried, volume, "the volume carried is the one baked");

    let level = reader.levels().next().unwrap();
    assert_eq!(level.data.len(), (r[0] * 2 * r[1] * 3 * r[2] * 8) as usize);
    let texel = |x: u32, y: u32, z: u32| -> [f32; 4] {
        let i = (((z * 2 * r[1] + y) * r[0] + x) * 8) as usize;
        let c = |k: usize| {
            half::f16::from_le_bytes([level.data[i + 2 * k], level.data[i + 2 * k + 1]]).to_f32()
        };
        [c(0), c(1), c(2), c(3)]
    };
    let mut checked = 0;
    let mut largest = 0.0f32;
    // Every third voxel along each axis, every side.
    for z in (0..r[2]).step_by(3) {
        for y in (0..r[1]).step_by(3) {
            for x in (0..r[0]).step_by(3) {
                let p = box_min + step * (glam::Vec3::new(x as f32, y as f32, z as f32) + 0.5);
                for (axis, slab) in [(0usize, 0u32), (1, 1), (2, 2)] {
                    for (sign, dy) in [(1.0f32, 0), (-1.0, r[1])] {
                        let mut n = glam::Vec3::ZERO;
                        n[axis] = sign;
                        if !volume.weights(p, n, n).weights.iter().any(|w| *w > 0.0) {
                            continue; // the nearest probe stands in (a unit test)
                        }
                        let want = volume.irradiance(p, n, n);
                        let got = texel(x, y + dy, z + slab * r[2]);
                        assert_eq!(got[3], 1.0);
                        for c in 0..3 {
                            // half precision: 11 significant bits
                            assert!(
                                (got[c] - want[c]).abs() <= 1e-3 * want[c].abs() + 1e-6,
                                "voxel {x},{y},{z} axis {axis} sign {sign}: {} vs {}",
                                got[c],
                                want[c]
                            );
                            largest = largest.max(want[c]);
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked >= 6 * 30, "{checked} sides checked");
    assert!(largest > 0.0, "the volume is dark");
    std::fs::remove_dir_all(&dir).ok();
}

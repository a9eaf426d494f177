//! `nearfield bake --format bevy` writes the ambient-cube texture Bevy's `IrradianceVolume`
//! reads: read back with the `ktx2` crate, it has Bevy's documented layout (Rx × 2Ry × 3Rz,
//! RGBA16F, the X, Y, Z slabs along z, each slab's negative side at y + Ry), and every texel is
//! the volume's own E(±axis)/π of that probe (the `.nfv` baked with the same settings).

use nearfield_scene::probes::{ProbeVolume, bevy::VK_FORMAT_R16G16B16A16_SFLOAT};
use nearfield_scene::sh;
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
    let r = volume.grid.counts;
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
    for a in 0..3 {
        let scale = transform["scale"][a].as_f64().unwrap() as f32;
        let centre = transform["translation"][a].as_f64().unwrap() as f32;
        let extent = g.spacing[a] * r[a] as f32;
        assert!((scale - extent).abs() < 1e-4 * extent, "scale {a}");
        // probe 0 stands at the centre of the first of r[a] cells of the box
        let first = centre - 0.5 * scale + 0.5 * scale / r[a] as f32;
        assert!((first - g.origin[a]).abs() < 1e-4, "translation {a}");
    }
    assert_eq!(transform["intensity"].as_f64(), Some(1.0));

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
    for (index, probe) in volume.probes.iter().enumerate() {
        if !probe.active {
            continue;
        }
        let [x, y, z] = g.coords(index);
        for (axis, slab) in [(0usize, 0u32), (1, 1), (2, 2)] {
            for (sign, dy) in [(1.0f32, 0), (-1.0, r[1])] {
                let mut n = glam::Vec3::ZERO;
                n[axis] = sign;
                let want = sh::irradiance_over_pi(&probe.sh, n).max(glam::Vec3::ZERO);
                let got = texel(x, y + dy, z + slab * r[2]);
                assert_eq!(got[3], 1.0);
                for c in 0..3 {
                    // half precision: 11 significant bits
                    assert!(
                        (got[c] - want[c]).abs() <= 1e-3 * want[c].abs() + 1e-6,
                        "probe {index} axis {axis} sign {sign}: {} vs {}",
                        got[c],
                        want[c]
                    );
                    largest = largest.max(want[c]);
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 6 * 30, "{checked} sides checked");
    assert!(largest > 0.0, "the volume is dark");
    std::fs::remove_dir_all(&dir).ok();
}

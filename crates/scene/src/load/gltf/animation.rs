//! glTF node animation: every node of the file with its parent and rest transform, and the
//! translation, rotation and scale channels of every animation, checked
//! ([`crate::animation::Animation::check`]).

use crate::animation::{Animation, Interpolation, Node, Track};
use ::gltf::animation::{Property, util::ReadOutputs};
use glam::{Quat, Vec3};
use std::collections::HashMap;

/// The file's animated node hierarchy (empty without animations); `parents` maps a node to its
/// parent.
pub fn read(
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    parents: &HashMap<usize, usize>,
) -> Result<Animation, String> {
    if doc.animations().len() == 0 {
        return Ok(Animation::default());
    }
    let mut nodes: Vec<Node> = doc
        .nodes()
        .map(|n| {
            let (t, r, s) = n.transform().decomposed();
            Node {
                name: super::check::node_name(&n),
                parent: parents.get(&n.index()).map(|&p| p as u32),
                translation: Vec3::from(t),
                rotation: Quat::from_array(r),
                scale: Vec3::from(s),
                translations: None,
                rotations: None,
                scales: None,
            }
        })
        .collect();
    for (a, anim) in doc.animations().enumerate() {
        for (c, channel) in anim.channels().enumerate() {
            let at = |e: &str| format!("animation {a} channel {c}: {e}");
            types(&channel).map_err(|e| at(&e))?;
            let reader = channel.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let times: Vec<f32> = reader
                .read_inputs()
                .ok_or_else(|| at("its sampler's keyframe times cannot be read"))?
                .collect();
            let interpolation = match channel.sampler().interpolation() {
                ::gltf::animation::Interpolation::Step => Interpolation::Step,
                ::gltf::animation::Interpolation::Linear => Interpolation::Linear,
                ::gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let outputs = reader
                .read_outputs()
                .ok_or_else(|| at("its sampler's values cannot be read"))?;
            let node = &mut nodes[channel.target().node().index()];
            let vec3 = |values: Vec<[f32; 3]>| Track {
                times: times.clone(),
                values: values.into_iter().map(Vec3::from).collect(),
                interpolation,
            };
            match (channel.target().property(), outputs) {
                (Property::Translation, ReadOutputs::Translations(v)) => {
                    node.translations = Some(vec3(v.collect()));
                }
                (Property::Scale, ReadOutputs::Scales(v)) => {
                    node.scales = Some(vec3(v.collect()));
                }
                (Property::Rotation, ReadOutputs::Rotations(v)) => {
                    node.rotations = Some(Track {
                        times: times.clone(),
                        values: v.into_f32().map(Quat::from_array).collect(),
                        interpolation,
                    });
                }
                (Property::MorphTargetWeights, _) => {
                    log::warn!("{}", at("morph target weights are not played"));
                }
                (p, _) => return Err(at(&format!("its values do not fit a {p:?} channel"))),
            }
        }
    }
    let animation = Animation { nodes };
    animation.check()?;
    Ok(animation)
}

/// The accessor types glTF allows a channel (and the reader assumes): float SCALAR times; float
/// VEC3 translations and scales; float or normalized integer VEC4 rotations.
fn types(channel: &::gltf::animation::Channel) -> Result<(), String> {
    use ::gltf::accessor::{DataType as T, Dimensions as D};
    let (input, output) = (channel.sampler().input(), channel.sampler().output());
    if !(input.data_type() == T::F32 && input.dimensions() == D::Scalar) {
        return Err("its keyframe times are not float SCALAR".into());
    }
    let ok = match channel.target().property() {
        Property::Translation | Property::Scale => {
            output.data_type() == T::F32 && output.dimensions() == D::Vec3
        }
        Property::Rotation => {
            output.dimensions() == D::Vec4 && (output.data_type() == T::F32 || output.normalized())
        }
        Property::MorphTargetWeights => true,
    };
    if !ok {
        return Err(format!(
            "its values are {:?} {:?}, not a type a {:?} channel takes",
            output.dimensions(),
            output.data_type(),
            channel.target().property()
        ));
    }
    Ok(())
}

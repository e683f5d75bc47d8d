//! glTF animations (§3.11): channels of node translation, rotation and scale. Their
//! samplers' accessors are checked and charged like every other accessor (input: SCALAR
//! float; output: VEC3 float for translation and scale, VEC4 float or normalised integers for
//! rotation), their key times must be finite, ≥ 0 and strictly increasing, their values
//! finite and as many as the interpolation needs (three per key for CUBICSPLINE), and no key
//! rotation may be zero. The document pass (`document`) has checked the references (sampler,
//! node, accessors), the paths and interpolations, and that no animated node has a matrix.
//! Morph target `weights` channels (SCALAR float or normalised integers, one value per
//! target of the node's mesh per key) animate the node's mesh weights.

use super::{accessors, describe};
use crate::budget::Budget;
use crate::model::unit_quaternion;
use crate::{Animation, Channel, Interpolation, Scene, TargetPath};
use anyhow::{Context, Result, bail};
use glam::{Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::Property;
use gltf::animation::util::ReadOutputs;
use std::collections::HashMap;

/// Per glTF node, whether a translation, rotation or scale channel targets it (weights move
/// vertices, not the node).
pub fn animated_nodes(document: &gltf::Document) -> Vec<bool> {
    let mut animated = vec![false; document.nodes().len()];
    for animation in document.animations() {
        for channel in animation.channels() {
            let target = channel.target();
            if target.property() != Property::MorphTargetWeights {
                animated[target.node().index()] = true;
            }
        }
    }
    animated
}

/// Reads every animation into `scene.animations`; `scene_node_of` maps glTF nodes to
/// `scene.nodes` (channels of nodes outside the scene are checked, then dropped).
pub fn load_animations(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    scene_node_of: &[Option<usize>],
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<()> {
    for animation in document.animations() {
        let label = describe(Some(animation.index()), animation.name());
        let name = animation.name().map_or_else(|| format!("animation {}", animation.index()), str::to_string);
        let mut channels = Vec::new();
        let mut targets: HashMap<(usize, TargetPath), usize> = HashMap::new();
        for channel in animation.channels() {
            let target = channel.target();
            let node = target.node();
            let path = match target.property() {
                Property::Translation => TargetPath::Translation,
                Property::Rotation => TargetPath::Rotation,
                Property::Scale => TargetPath::Scale,
                Property::MorphTargetWeights => {
                    let targets = node.mesh().and_then(|m| m.primitives().map(|p| p.morph_targets().len()).max());
                    match targets {
                        Some(count) if count > 0 => TargetPath::Weights(count),
                        _ => bail!(
                            "animation {label} channel {}: it animates the morph weights of node {}, whose mesh has no morph targets",
                            channel.index(),
                            describe(Some(node.index()), node.name())
                        ),
                    }
                }
            };
            let here = || {
                format!(
                    "animation {label} channel {} ({} of node {}, sampler {})",
                    channel.index(),
                    path.name(),
                    describe(Some(node.index()), node.name()),
                    channel.sampler().index()
                )
            };
            if let Some(other) = targets.insert((node.index(), path), channel.index()) {
                bail!(
                    "{}: channel {other} animates the same property (glTF: the channels of one animation need distinct targets)",
                    here()
                );
            }
            let (interpolation, times, values) = read_channel(&channel, path, buffers, budget).with_context(here)?;
            if let Some(node) = scene_node_of.get(node.index()).copied().flatten() {
                budget.charge(here(), 1, std::mem::size_of::<Channel>() as u64)?;
                channels.push(Channel { node, path, interpolation, times, values });
            }
        }
        if !channels.is_empty() {
            budget.charge(
                format_args!("animation {label}"),
                1,
                (std::mem::size_of::<Animation>() + name.len()) as u64,
            )?;
            scene.animations.push(Animation { name, channels, time_offset: 0.0 });
        }
    }
    Ok(())
}

/// A channel's interpolation, key times and values, checked.
fn read_channel(
    channel: &gltf::animation::Channel,
    path: TargetPath,
    buffers: &[Vec<u8>],
    budget: &mut Budget,
) -> Result<(Interpolation, Vec<f32>, Vec<Vec4>)> {
    let sampler = channel.sampler();
    let interpolation = match sampler.interpolation() {
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let (input, output) = (sampler.input(), sampler.output());
    accessors::check(&input, "sampler.input", Dimensions::Scalar, &[DataType::F32], buffers, budget)?;
    match path {
        TargetPath::Translation | TargetPath::Scale => {
            accessors::check(&output, "sampler.output", Dimensions::Vec3, &[DataType::F32], buffers, budget)?;
            // Held as Vec4: a fourth component each.
            budget.charge("sampler.output (as 4-vectors)", output.count() as u64, 4)?;
        }
        TargetPath::Rotation => {
            let types = [DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];
            accessors::check(&output, "sampler.output", Dimensions::Vec4, &types, buffers, budget)?;
            if output.data_type() != DataType::F32 && !output.normalized() {
                bail!(
                    "sampler.output accessor {} holds {:?} integers that are not normalized (glTF allows float or normalized rotations)",
                    output.index(),
                    output.data_type()
                );
            }
        }
        TargetPath::Weights(_) => {
            let types = [DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];
            accessors::check(&output, "sampler.output", Dimensions::Scalar, &types, buffers, budget)?;
            if output.data_type() != DataType::F32 && !output.normalized() {
                bail!(
                    "sampler.output accessor {} holds {:?} integers that are not normalized (glTF allows float or normalized weights)",
                    output.index(),
                    output.data_type()
                );
            }
            budget.charge("sampler.output (as 4-vectors)", output.count() as u64, 12)?;
        }
    }
    let per_key = interpolation.values_per_key();
    let keys = input.count();
    let per_value = match path {
        TargetPath::Weights(count) => count,
        _ => 1,
    };
    if keys.checked_mul(per_key).and_then(|v| v.checked_mul(per_value)) != Some(output.count()) {
        bail!(
            "sampler.output accessor {} has {} elements but sampler.input accessor {} has {keys} keys: {} needs {} per key",
            output.index(),
            output.count(),
            input.index(),
            interpolation.name(),
            per_key * per_value
        );
    }

    let reader = channel.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let times: Vec<f32> = reader.read_inputs().context("sampler.input data out of range")?.collect();
    check_times(&times, input.index())?;
    let values: Vec<Vec4> = match reader.read_outputs().context("sampler.output data out of range")? {
        ReadOutputs::Translations(v) | ReadOutputs::Scales(v) => v.map(|v| Vec3::from(v).extend(0.0)).collect(),
        ReadOutputs::Rotations(v) => v.into_f32().map(Vec4::from).collect(),
        ReadOutputs::MorphTargetWeights(w) => {
            let flat: Vec<f32> = w.into_f32().collect();
            if flat.len() != output.count() {
                bail!("sampler data out of range (fewer elements than the accessors' counts)");
            }
            // Each value's weights as `ceil(count / 4)` 4-vectors, zero-padded.
            let chunks = path.chunks();
            let mut packed = Vec::with_capacity(flat.len().div_ceil(per_value) * chunks);
            for value in flat.chunks(per_value) {
                for c in 0..chunks {
                    let at = |i: usize| value.get(4 * c + i).copied().unwrap_or(0.0);
                    packed.push(Vec4::new(at(0), at(1), at(2), at(3)));
                }
            }
            packed
        }
    };
    let expected = output.count() / per_value * path.chunks();
    if times.len() != keys || values.len() != expected {
        bail!("sampler data out of range (fewer elements than the accessors' counts)");
    }
    if let Some(e) = values.iter().position(|v| !v.is_finite()) {
        bail!("sampler.output accessor {}: element {e} holds NaN or infinite values", output.index());
    }
    if path == TargetPath::Rotation {
        // The key values (for CUBICSPLINE the middle of each triple; tangents may be zero).
        let vertex = (0..keys).map(|k| k * per_key + per_key / 2).find(|&e| unit_quaternion(values[e]).is_none());
        if let Some(e) = vertex {
            bail!("sampler.output accessor {}: element {e} is a zero quaternion, not a rotation", output.index());
        }
    }
    Ok((interpolation, times, values))
}

/// glTF 2.0 §3.11: key times are finite, ≥ 0 and strictly increasing.
fn check_times(times: &[f32], accessor: usize) -> Result<()> {
    let mut previous: Option<f32> = None;
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            bail!("sampler.input accessor {accessor}: key {k} is {t}, not a time");
        }
        if t < 0.0 {
            bail!("sampler.input accessor {accessor}: key {k} is {t} s, before 0");
        }
        if let Some(p) = previous
            && t <= p
        {
            bail!(
                "sampler.input accessor {accessor}: key {k} ({t} s) is not after key {} ({p} s); key times must increase strictly",
                k - 1
            );
        }
        previous = Some(t);
    }
    Ok(())
}

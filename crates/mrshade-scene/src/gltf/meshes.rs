//! Mesh primitives: checked attribute reads, triangle assembly, flat normals when missing,
//! skinning attributes (`JOINTS_0`, `WEIGHTS_0`) and morph targets.

use super::{accessors, describe};
use crate::budget::Budget;
use crate::model::{MorphTarget, VertexSkin};
use crate::{Primitive, Scene};
use anyhow::{Context, Result, bail};
use glam::{Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

/// Loads every mesh; returns, per glTF mesh, the indices of its primitives in
/// `scene.primitives`.
pub fn load_meshes(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    default_material: usize,
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<Vec<Vec<usize>>> {
    let mut per_mesh = Vec::new();
    for mesh in document.meshes() {
        let mut ids = Vec::new();
        for prim in mesh.primitives() {
            let name = format!("mesh {} primitive {}", describe(Some(mesh.index()), mesh.name()), prim.index());
            let material = prim.material().index().unwrap_or(default_material);
            if let Some(ext) = prim.extension_value(super::draco::EXTENSION) {
                let p = read_draco_primitive(document, &prim, ext, buffers, &name, material, budget)
                    .with_context(|| format!("{name} ({})", super::draco::EXTENSION))?;
                scene.warnings.extend(p.1);
                ids.push(scene.primitives.len());
                scene.primitives.push(p.0);
                continue;
            }
            match read_primitive(&prim, buffers, &name, material, budget).with_context(|| name.clone())? {
                Some(p) => {
                    ids.push(scene.primitives.len());
                    scene.primitives.push(p);
                }
                None => scene.warnings.push(format!("{name}: {:?} primitives are not rendered", prim.mode())),
            }
        }
        per_mesh.push(ids);
    }
    Ok(per_mesh)
}

fn read_primitive(
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    name: &str,
    material: usize,
    budget: &mut Budget,
) -> Result<Option<Primitive>> {
    if !matches!(prim.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(None);
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));

    let pos_accessor = prim.get(&gltf::Semantic::Positions).context("no POSITION attribute")?;
    accessors::check(&pos_accessor, "POSITION", Dimensions::Vec3, &[DataType::F32], buffers, budget)?;
    let positions: Vec<Vec3> = reader.read_positions().context("POSITION data out of range")?.map(Vec3::from).collect();
    if positions.iter().any(|p| !p.is_finite()) {
        bail!("POSITION holds NaN or infinite values");
    }
    check_bounds(&pos_accessor, &positions)?;

    let normals = match prim.get(&gltf::Semantic::Normals) {
        Some(acc) => {
            accessors::check(&acc, "NORMAL", Dimensions::Vec3, &[DataType::F32], buffers, budget)?;
            check_count(acc.count(), positions.len(), "NORMAL")?;
            let n: Vec<Vec3> = reader.read_normals().context("NORMAL data out of range")?.map(Vec3::from).collect();
            if n.iter().any(|n| !n.is_finite()) {
                bail!("NORMAL holds NaN or infinite values");
            }
            // Zero normals (degenerate triangles of some exporters) point up rather than nowhere.
            Some(n.into_iter().map(|n| n.normalize_or(Vec3::Y)).collect())
        }
        None => None,
    };

    let uvs = match prim.get(&gltf::Semantic::TexCoords(0)) {
        Some(acc) => {
            accessors::check(
                &acc,
                "TEXCOORD_0",
                Dimensions::Vec2,
                &[DataType::F32, DataType::U8, DataType::U16],
                buffers,
                budget,
            )?;
            if acc.data_type() != DataType::F32 && !acc.normalized() {
                bail!("TEXCOORD_0 accessor {} holds integers that are not normalized", acc.index());
            }
            check_count(acc.count(), positions.len(), "TEXCOORD_0")?;
            let uv: Vec<Vec2> =
                reader.read_tex_coords(0).context("TEXCOORD_0 data out of range")?.into_f32().map(Vec2::from).collect();
            if uv.iter().any(|t| !t.is_finite()) {
                bail!("TEXCOORD_0 holds NaN or infinite values");
            }
            uv
        }
        None => {
            budget.charge("TEXCOORD_0 (zeros)", positions.len() as u64, 8)?;
            vec![Vec2::ZERO; positions.len()]
        }
    };

    let raw_indices: Vec<u32> = match prim.indices() {
        Some(acc) => {
            accessors::check(
                &acc,
                "indices",
                Dimensions::Scalar,
                &[DataType::U8, DataType::U16, DataType::U32],
                buffers,
                budget,
            )?;
            reader.read_indices().context("index data out of range")?.into_u32().collect()
        }
        None => {
            budget.charge("indices (implicit)", positions.len() as u64, 4)?;
            (0..positions.len() as u32).collect()
        }
    };
    // The position, not the value: a value is bytes of the file, which may be anything.
    if let Some(at) = raw_indices.iter().position(|&i| i as usize >= positions.len()) {
        bail!("index {at} of the index list is out of range for {} vertices", positions.len());
    }
    // Strips and fans triple their indices.
    budget.charge("the triangle list", raw_indices.len() as u64, 12)?;
    let indices = triangle_list(prim.mode(), &raw_indices);
    if indices.is_empty() {
        bail!("has no triangles");
    }

    let skin = read_skin(prim, &reader, positions.len(), buffers, budget)?;
    let targets = read_targets(prim, &reader, positions.len(), buffers, budget)?;
    let mut p =
        Primitive { name: name.to_string(), positions, normals: Vec::new(), uvs, indices, material, skin, targets };
    match normals {
        Some(n) => p.normals = n,
        None => {
            // One vertex (position, normal, uv) per corner.
            budget.charge("flat normals", p.indices.len() as u64, 32)?;
            make_flat_normals(&mut p)
        }
    }
    Ok(Some(p))
}

/// A Draco-compressed triangle primitive (`super::draco`), checked as any other: finite
/// positions within the POSITION accessor's bounds, flat normals where none are compressed.
fn read_draco_primitive(
    document: &gltf::Document,
    prim: &gltf::Primitive,
    ext: &serde_json::Value,
    buffers: &[Vec<u8>],
    name: &str,
    material: usize,
    budget: &mut Budget,
) -> Result<(Primitive, Vec<String>)> {
    if prim.mode() != Mode::Triangles {
        bail!("Draco compresses triangle lists, but the primitive's mode is {:?}", prim.mode());
    }
    let decoded = super::draco::decode(document, ext, buffers, budget)?;
    if let Some(acc) = prim.get(&gltf::Semantic::Positions) {
        check_bounds(&acc, &decoded.positions)?;
    }
    if decoded.indices.is_empty() {
        bail!("has no triangles");
    }
    let count = decoded.positions.len();
    let mut p = Primitive {
        name: name.to_string(),
        uvs: decoded.uvs.unwrap_or_else(|| vec![Vec2::ZERO; count]),
        positions: decoded.positions,
        normals: Vec::new(),
        indices: decoded.indices,
        material,
        skin: Vec::new(),
        targets: Vec::new(),
    };
    match decoded.normals {
        Some(n) => p.normals = n,
        None => {
            budget.charge("flat normals", p.indices.len() as u64, 32)?;
            make_flat_normals(&mut p)
        }
    }
    let warnings =
        decoded.ignored.iter().map(|a| format!("{name}: the Draco-compressed {a} attribute is not read")).collect();
    Ok((p, warnings))
}

/// `JOINTS_0` and `WEIGHTS_0` (glTF 2.0 §3.7.3.1), both or neither; the weights of every
/// vertex must sum to one (within 1 %, then renormalised: exporters round). Joint indices are
/// checked against the skin when a node uses the mesh.
fn read_skin<'a, 's, F>(
    prim: &gltf::Primitive,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    count: usize,
    buffers: &[Vec<u8>],
    budget: &mut Budget,
) -> Result<Vec<VertexSkin>>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let (joints, weights) = (prim.get(&gltf::Semantic::Joints(0)), prim.get(&gltf::Semantic::Weights(0)));
    let (joints_acc, weights_acc) = match (joints, weights) {
        (None, None) => return Ok(Vec::new()),
        (Some(j), Some(w)) => (j, w),
        (Some(_), None) => bail!("JOINTS_0 without WEIGHTS_0"),
        (None, Some(_)) => bail!("WEIGHTS_0 without JOINTS_0"),
    };
    accessors::check(&joints_acc, "JOINTS_0", Dimensions::Vec4, &[DataType::U8, DataType::U16], buffers, budget)?;
    let weight_types = [DataType::F32, DataType::U8, DataType::U16];
    accessors::check(&weights_acc, "WEIGHTS_0", Dimensions::Vec4, &weight_types, buffers, budget)?;
    if weights_acc.data_type() != DataType::F32 && !weights_acc.normalized() {
        bail!("WEIGHTS_0 accessor {} holds integers that are not normalized", weights_acc.index());
    }
    check_count(joints_acc.count(), count, "JOINTS_0")?;
    check_count(weights_acc.count(), count, "WEIGHTS_0")?;
    let joints: Vec<[u16; 4]> = reader.read_joints(0).context("JOINTS_0 data out of range")?.into_u16().collect();
    let weights: Vec<[f32; 4]> = reader.read_weights(0).context("WEIGHTS_0 data out of range")?.into_f32().collect();
    if joints.len() != count || weights.len() != count {
        bail!("JOINTS_0/WEIGHTS_0 data out of range (fewer elements than the accessors' counts)");
    }
    let mut skin = Vec::with_capacity(count);
    for (v, (joints, weights)) in joints.into_iter().zip(weights).enumerate() {
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            bail!("WEIGHTS_0 accessor {}: vertex {v} has a weight that is negative or not finite", weights_acc.index());
        }
        let sum: f32 = weights.iter().sum();
        if (sum - 1.0).abs() > 0.01 {
            bail!(
                "WEIGHTS_0 accessor {}: the weights of vertex {v} sum to {sum}, not 1 (glTF 2.0 §3.7.3.1)",
                weights_acc.index()
            );
        }
        skin.push(VertexSkin { joints, weights: weights.map(|w| w / sum) });
    }
    Ok(skin)
}

/// Morph targets (glTF 2.0 §3.7.2.2): POSITION and NORMAL displacements, float VEC3, as many
/// as the primitive's vertices (TANGENT displacements are not used).
fn read_targets<'a, 's, F>(
    prim: &gltf::Primitive,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    count: usize,
    buffers: &[Vec<u8>],
    budget: &mut Budget,
) -> Result<Vec<MorphTarget>>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let mut targets = Vec::new();
    for (t, (target, data)) in prim.morph_targets().zip(reader.read_morph_targets()).enumerate() {
        let what = |attr: &str| format!("morph target {t} {attr}");
        let mut read = |accessor: Option<gltf::Accessor>, values: Option<gltf::mesh::util::ReadPositions<'s>>, attr| {
            let (Some(accessor), Some(values)) = (accessor, values) else { return Ok(Vec::new()) };
            accessors::check(&accessor, &what(attr), Dimensions::Vec3, &[DataType::F32], buffers, budget)?;
            check_count(accessor.count(), count, &what(attr))?;
            let v: Vec<Vec3> = values.map(Vec3::from).collect();
            if v.len() != count || v.iter().any(|d| !d.is_finite()) {
                bail!("{}: out of range or holds NaN or infinite values", what(attr));
            }
            Ok::<_, anyhow::Error>(v)
        };
        let positions = read(target.positions(), data.0, "POSITION")?;
        let normals = read(target.normals(), data.1, "NORMAL")?;
        targets.push(MorphTarget {
            positions: if positions.is_empty() { vec![Vec3::ZERO; count] } else { positions },
            normals,
        });
    }
    Ok(targets)
}

/// glTF 2.0 §3.6.2.4: POSITION's `min` and `max` MUST bound its data. A file whose bounds do
/// not is damaged or hand-edited; say so instead of trusting either.
fn check_bounds(accessor: &gltf::Accessor, positions: &[Vec3]) -> Result<()> {
    let as_vec3 = |v: Option<gltf::json::Value>| -> Option<Vec3> {
        let a: Vec<f32> = serde_json::from_value(v?).ok()?;
        (a.len() == 3).then(|| Vec3::new(a[0], a[1], a[2]))
    };
    let (Some(min), Some(max)) = (as_vec3(accessor.min()), as_vec3(accessor.max())) else {
        return Ok(());
    };
    let (lo, hi) = mrshade_core::math::bounding_box(positions);
    // Exporters round the bounds they write; allow for that.
    let slack = 1e-4 * (max - min).abs().max_element().max(lo.abs().max(hi.abs()).max_element()).max(1e-3);
    if (min - lo).max_element() > slack || (hi - max).max_element() > slack {
        bail!("POSITION accessor {}: its min {min} and max {max} do not bound its data", accessor.index());
    }
    Ok(())
}

fn check_count(count: usize, expected: usize, what: &str) -> Result<()> {
    if count != expected {
        bail!("{what} has {count} elements but POSITION has {expected}");
    }
    Ok(())
}

/// Strips and fans as a plain triangle list.
fn triangle_list(mode: Mode, idx: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (2..idx.len())
            .flat_map(|i| if i % 2 == 0 { [idx[i - 2], idx[i - 1], idx[i]] } else { [idx[i - 1], idx[i - 2], idx[i]] })
            .collect(),
        Mode::TriangleFan => (2..idx.len()).flat_map(|i| [idx[0], idx[i - 1], idx[i]]).collect(),
        _ => idx[..idx.len() / 3 * 3].to_vec(),
    }
}

/// The glTF spec: "When normals are not specified, client implementations MUST calculate
/// flat normals". Every triangle gets its own three vertices (with their skinning and morph
/// displacements) and its face normal.
fn make_flat_normals(p: &mut Primitive) {
    let corners: Vec<usize> = p.indices.iter().map(|&i| i as usize).collect();
    let pick =
        |v: &[Vec3]| -> Vec<Vec3> { if v.is_empty() { Vec::new() } else { corners.iter().map(|&i| v[i]).collect() } };
    let normals = p
        .indices
        .chunks_exact(3)
        .flat_map(|tri| {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| p.positions[i as usize]);
            [(b - a).cross(c - a).normalize_or(Vec3::Y); 3]
        })
        .collect();
    p.uvs = corners.iter().map(|&i| p.uvs[i]).collect();
    if !p.skin.is_empty() {
        p.skin = corners.iter().map(|&i| p.skin[i]).collect();
    }
    for target in &mut p.targets {
        target.positions = pick(&target.positions);
        target.normals.clear(); // flat normals are not morphed
    }
    p.positions = pick(&p.positions);
    p.normals = normals;
    p.indices = (0..corners.len() as u32).collect();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3]), vec![0, 1, 2, 2, 1, 3]);
        assert_eq!(triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]), vec![0, 1, 2, 0, 2, 3]);
        assert_eq!(triangle_list(Mode::Triangles, &[0, 1, 2, 3]), vec![0, 1, 2]);
    }

    #[test]
    fn flat_normals_follow_the_winding() {
        let mut p = Primitive {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            uvs: vec![Vec2::ZERO; 3],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        make_flat_normals(&mut p);
        assert!(p.normals.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)));
    }
}

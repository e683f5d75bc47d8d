//! Mesh primitives: checked attribute reads, triangle assembly, flat normals when missing.

use super::{accessors, describe};
use crate::budget::Budget;
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

    let mut p = Primitive { name: name.to_string(), positions, normals: Vec::new(), uvs, indices, material };
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
/// flat normals". Every triangle gets its own three vertices and its face normal.
fn make_flat_normals(p: &mut Primitive) {
    let mut positions = Vec::with_capacity(p.indices.len());
    let mut normals = Vec::with_capacity(p.indices.len());
    let mut uvs = Vec::with_capacity(p.indices.len());
    for tri in p.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
        let n = (p.positions[b] - p.positions[a]).cross(p.positions[c] - p.positions[a]).normalize_or(Vec3::Y);
        for i in [a, b, c] {
            positions.push(p.positions[i]);
            uvs.push(p.uvs[i]);
            normals.push(n);
        }
    }
    p.indices = (0..positions.len() as u32).collect();
    p.positions = positions;
    p.normals = normals;
    p.uvs = uvs;
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

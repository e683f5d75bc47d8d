//! glTF 2.0 loading (`.gltf` + `.bin`, `.glb`, data URIs) into the scene model, through the
//! maintained `gltf` crate for parsing and our own checks for everything a renderer must not
//! trust: the document's references and node graph ([`document`]), buffer lengths, accessor
//! types, ranges and counts against the memory budget, index bounds, non-finite and
//! impossibly large numbers, world transforms after composition, animations of node
//! transforms ([`animations`]).

mod accessors;
mod animations;
mod buffers;
mod document;
mod draco;
mod extensions;
mod materials;
mod meshes;
mod nodes;
mod skins;

pub use extensions::SUPPORTED_EXTENSIONS;

use crate::budget::Budget;
use crate::{AssetSource, Material, Scene};
use anyhow::{Context, Result};
use mrshade_core::settings::Limits;

/// Loads the glTF file `rel` (relative to `source`): its default scene, or scene 0. Its
/// buffers and images are read relative to its folder, within `limits`.
pub fn load_gltf(source: &AssetSource, rel: &str, limits: &Limits) -> Result<Scene> {
    let what = || format!("glTF {}", source.display(rel));
    let bytes = source.read(rel).with_context(what)?;
    load_gltf_bytes(&bytes, &source.files_named_by(rel), limits).with_context(what)
}

/// Loads a glTF document from memory; external files are read from `folder`.
pub fn load_gltf_bytes(bytes: &[u8], folder: &AssetSource, limits: &Limits) -> Result<Scene> {
    let mut budget = Budget::new(limits);
    let document::Parsed { document, blob } = document::parse(bytes)?;
    let mut scene = Scene::default();
    scene.warnings.extend(extensions::warnings(&document));
    let buffers = buffers::load_buffers(&document, blob, folder, &mut budget)?;

    let mut textures = materials::TextureCache::default();
    for material in document.materials() {
        let m = materials::load_material(&material, &buffers, folder, &mut textures, &mut budget, &mut scene.warnings)
            .with_context(|| format!("material {}", describe(material.index(), material.name())))?;
        scene.materials.push(m);
    }
    scene.textures = textures.into_textures();
    // Primitives without a material use the glTF default material, appended last.
    let default_material = scene.materials.len();
    scene.materials.push(Material::default());

    let mesh_primitives = meshes::load_meshes(&document, &buffers, default_material, &mut budget, &mut scene)?;
    let animated = animations::animated_nodes(&document);
    let scene_node_of = nodes::place_nodes(&document, &mesh_primitives, &animated, &mut budget, &mut scene)?;
    skins::load_skins(&document, &buffers, &scene_node_of, &mut budget, &mut scene)?;
    animations::load_animations(&document, &buffers, &scene_node_of, &mut budget, &mut scene)?;
    // The rest pose's deformed geometry (what a still renders) must be usable too.
    let rest = scene.rest_pose();
    scene.check_deformed(&rest, |i| format!("node '{}' in its rest pose", scene.instances[i].node_name))?;
    // The poses at the ends of the animations must be usable (the start is what a still
    // renders); poses between keys are checked when they are sampled.
    if let Some((first, last)) = scene.time_range() {
        scene.pose_at(first)?;
        scene.pose_at(last)?;
    }
    Ok(scene)
}

/// `'name'` or `#index` for messages (names made printable).
pub(crate) fn describe(index: Option<usize>, name: Option<&str>) -> String {
    match (name, index) {
        (Some(n), _) => format!("'{}'", mrshade_core::text::printable(n)),
        (None, Some(i)) => format!("#{i}"),
        (None, None) => "(default)".into(),
    }
}

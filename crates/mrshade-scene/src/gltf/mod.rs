//! glTF 2.0 loading (`.gltf` + `.bin`, `.glb`, data URIs) into the scene model, through the
//! maintained `gltf` crate for parsing and our own checks for everything a renderer must not
//! trust: buffer lengths, accessor types and ranges, index bounds, non-finite numbers.

mod accessors;
mod buffers;
mod extensions;
mod materials;
mod meshes;
mod nodes;

pub use extensions::SUPPORTED_EXTENSIONS;

use crate::{AssetSource, Material, Scene};
use anyhow::{Context, Result, bail};
use gltf::json::validation::{Error as ValidationError, Validate};

/// Loads the glTF file `rel` (relative to `source`): its default scene, or scene 0.
pub fn load_gltf(source: &AssetSource, rel: &str) -> Result<Scene> {
    let bytes = source.read(rel)?;
    load_gltf_bytes(&bytes, &source.folder_of(rel)).with_context(|| format!("glTF {}", source.display(rel)))
}

/// Loads a glTF document from memory; external files are read from `folder`.
pub fn load_gltf_bytes(bytes: &[u8], folder: &AssetSource) -> Result<Scene> {
    if bytes.is_empty() {
        bail!("the file is empty");
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).context("not valid glTF 2.0")?;
    validate(&document)?;
    let mut scene = Scene::default();
    scene.warnings.extend(extensions::check(&document)?);
    let buffers = buffers::load_buffers(&document, blob, folder)?;

    let mut textures = materials::TextureCache::default();
    for material in document.materials() {
        let m = materials::load_material(&material, &buffers, folder, &mut textures, &mut scene.warnings)
            .with_context(|| format!("material {}", describe(material.index(), material.name())))?;
        scene.materials.push(m);
    }
    scene.textures = textures.into_textures();
    // Primitives without a material use the glTF default material, appended last.
    let default_material = scene.materials.len();
    scene.materials.push(Material::default());

    let mesh_primitives = meshes::load_meshes(&document, &buffers, default_material, &mut scene)?;
    nodes::place_nodes(&document, &mesh_primitives, &mut scene)?;
    if document.animations().len() > 0 || document.skins().len() > 0 {
        scene.warnings.push("animations and skins are ignored: the scene is rendered in its rest pose".into());
    }
    Ok(scene)
}

/// Runs the `gltf` crate's structural validation (indices in range, required fields), but
/// leaves `extensionsRequired` to [`extensions::check`], which knows what mrshade honours.
fn validate(document: &gltf::Document) -> Result<()> {
    let root = document.as_json();
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        if !(error == ValidationError::Unsupported && path.starts_with("extensionsRequired")) {
            errors.push(format!("{path}: {error}"));
        }
    });
    if !errors.is_empty() {
        let shown: Vec<_> = errors.iter().take(5).cloned().collect();
        bail!("invalid glTF: {}{}", shown.join("; "), if errors.len() > 5 { "; …" } else { "" });
    }
    Ok(())
}

/// `'name'` or `#index` for messages.
pub(crate) fn describe(index: Option<usize>, name: Option<&str>) -> String {
    match (name, index) {
        (Some(n), _) => format!("'{n}'"),
        (None, Some(i)) => format!("#{i}"),
        (None, None) => "(default)".into(),
    }
}

//! Which glTF extensions mrshade honours. An extension it cannot honour is a warning that
//! names it; one that the file *requires* is an error.

use anyhow::{Result, bail};

/// Extensions whose data the renderer uses.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_volume",
    "KHR_materials_emissive_strength",
];

/// Checks `extensionsRequired` and returns warnings for unsupported `extensionsUsed`.
pub fn check(document: &gltf::Document) -> Result<Vec<String>> {
    let unsupported_required: Vec<&str> =
        document.extensions_required().filter(|e| !SUPPORTED_EXTENSIONS.contains(e)).collect();
    if !unsupported_required.is_empty() {
        bail!(
            "the file requires {}, which mrshade cannot honour (supported: {})",
            unsupported_required.join(", "),
            SUPPORTED_EXTENSIONS.join(", ")
        );
    }
    Ok(document
        .extensions_used()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .map(|e| format!("extension {e} is not supported and is ignored"))
        .collect())
}

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
    super::draco::EXTENSION,
];

/// Checks the raw document's `extensionsRequired`, before anything else: a file that needs
/// an extension (Draco compression moves its geometry out of the accessors) fails structural
/// checks without it, and the extension is the reason to tell.
pub fn check_required(document: &serde_json::Value) -> Result<()> {
    let required = document.get("extensionsRequired").and_then(serde_json::Value::as_array);
    let names = required.into_iter().flatten().filter_map(serde_json::Value::as_str);
    let unsupported_required: Vec<&str> = names.filter(|e| !SUPPORTED_EXTENSIONS.contains(e)).collect();
    if !unsupported_required.is_empty() {
        bail!(
            "the file requires {}, which mrshade cannot honour (supported: {})",
            unsupported_required.join(", "),
            SUPPORTED_EXTENSIONS.join(", ")
        );
    }
    Ok(())
}

/// Warnings for the unsupported extensions of `extensionsUsed`.
pub fn warnings(document: &gltf::Document) -> Vec<String> {
    document
        .extensions_used()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .map(|e| format!("extension {e} is not supported and is ignored"))
        .collect()
}

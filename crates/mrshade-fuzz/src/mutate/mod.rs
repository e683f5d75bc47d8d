//! Structure-aware mutations: each one parses a file the way its format is built (glTF JSON
//! and its GLB container, the session's TOML, a sequence's `transforms.json`, PNG chunks, the
//! EXR header), changes it where loaders make decisions (indices, counts, sizes, transforms,
//! paths, magnitudes), and writes it back valid enough to get past the first check. A few plain
//! byte mutations cover the rest.

mod bytes;
mod deformers;
mod gltf;
mod images;
mod session;
mod transforms;
mod values;

use arbitrary::Unstructured;
use std::collections::BTreeMap;

/// Applies one mutation, chosen by `u`, to one of `files`; says what it did.
pub fn apply(files: &mut BTreeMap<String, Vec<u8>>, u: &mut Unstructured) -> String {
    let scene = files.keys().find(|n| n.ends_with(".glb") || n.ends_with(".gltf")).cloned();
    let photo = files.keys().find(|n| n.starts_with("background")).cloned();
    // A sequence's poses, intrinsics and frame images: as often as all the rest together.
    if files.contains_key("transforms.json") && u.ratio(1, 2).unwrap_or(false) {
        return transforms::mutate(files, u);
    }
    let choice = u.int_in_range(0..=99u8).unwrap_or(0);
    match (choice, scene, photo) {
        (0..=54, Some(scene), _) => gltf::mutate(files, &scene, u),
        (55..=74, ..) => session::mutate(files, u),
        (75..=84, _, Some(photo)) => images::mutate_photo(files, &photo, u),
        (85..=94, ..) => images::mutate_probe(files, u),
        _ => {
            let names: Vec<String> = files.keys().cloned().collect();
            let name = names[u.choose_index(names.len()).unwrap_or(0)].clone();
            let step = bytes::mutate(files.get_mut(&name).expect("listed"), u);
            format!("{name}: {step}")
        }
    }
}

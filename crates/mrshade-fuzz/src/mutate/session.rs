//! Session (TOML) mutations: every setting at its boundaries, products of valid settings,
//! paths that lead outside or to devices, sizes, and raw text damage.

use super::{bytes, values};
use arbitrary::Unstructured;
use std::collections::BTreeMap;

/// What a setting holds, so that most mutations get past the type check to the range check.
#[derive(Clone, Copy)]
enum Kind {
    Number,
    Path,
    Choice(&'static [&'static str]),
    /// true or false.
    Bool,
}

/// Settings a session may hold.
const KEYS: &[(&str, Kind)] = &[
    ("exposure", Kind::Number),
    ("camera", Kind::Choice(&["camera", "desk", "", "nope"])),
    ("method", Kind::Choice(&["dir", "direct", "dvct", "dlpv"])),
    ("scene", Kind::Path),
    ("background", Kind::Path),
    ("environment.image", Kind::Path),
    ("environment.intensity", Kind::Number),
    ("environment.rotation_deg", Kind::Number),
    ("output.width", Kind::Number),
    ("output.height", Kind::Number),
    ("output.supersample", Kind::Number),
    ("output.frames", Kind::Number),
    ("composite.mode", Kind::Choice(&["alpha", "additive"])),
    ("composite.alpha_epsilon", Kind::Number),
    ("composite.alpha_max", Kind::Number),
    ("shadows.resolution", Kind::Number),
    ("shadows.pcf_radius", Kind::Number),
    ("shadows.normal_offset", Kind::Number),
    ("dvct.resolution", Kind::Number),
    ("dvct.extent", Kind::Number),
    ("dvct.outer_scale", Kind::Number),
    ("dvct.outer_resolution", Kind::Number),
    ("dvct.probe_lights", Kind::Number),
    ("dvct.probe_map_resolution", Kind::Number),
    ("dvct.diffuse_aperture", Kind::Number),
    ("dvct.sample_spacing", Kind::Number),
    ("dvct.bounce_spacing", Kind::Number),
    ("dvct.bounces", Kind::Number),
    ("dvct.third_bounce_moving", Kind::Bool),
    ("dvct.trace_block", Kind::Number),
    ("dvct.photo_voxels", Kind::Bool),
    ("dvct.virtual_rays", Kind::Number),
    ("dvct.still_rays", Kind::Number),
    ("dlpv.resolution", Kind::Number),
    ("dlpv.propagation_steps", Kind::Number),
    ("dlpv.rsm_resolution", Kind::Number),
    ("dlpv.probe_lights", Kind::Number),
    ("dlpv.probe_rsm_resolution", Kind::Number),
    ("dlpv.splat", Kind::Choice(&["cell", "trilinear", "nearest"])),
    ("dlpv.sharp_probe_shadows_deg", Kind::Number),
    ("dlpv.virtual_light", Kind::Choice(&["gathered", "propagated", "volume"])),
    ("dlpv.bounce_light", Kind::Choice(&["gathered", "propagated", "volume"])),
    ("dlpv.gather_block", Kind::Number),
    ("dlpv.photo_bounce", Kind::Bool),
    ("dlpv.soft_probe_shadows", Kind::Bool),
    ("dlpv.soft_virtual_probe_shadows", Kind::Bool),
    ("dlpv.virtual_bounce", Kind::Bool),
    ("dlpv.virtual_bounce_moving", Kind::Bool),
    ("dlpv.bounce_visibility", Kind::Bool),
    ("ibl.virtual", Kind::Choice(&["prefiltered", "sh", "fis", "prt"])),
    ("ibl.samples", Kind::Number),
    ("ibl.prt_samples", Kind::Number),
    ("ibl.prt_coefficients", Kind::Number),
    ("ibl.prt_specular", Kind::Choice(&["sog", "fis", "gauss"])),
    ("dir.vpl_count", Kind::Number),
    ("dir.points_per_vpl", Kind::Number),
    ("dir.ism_resolution", Kind::Number),
    ("dir.rsm_resolution", Kind::Number),
    ("dir.interleave", Kind::Number),
    ("dir.still_interleave", Kind::Number),
    ("dir.still_splat_scale", Kind::Number),
    ("dir.near_field_samples", Kind::Number),
    ("dir.near_field_radius", Kind::Number),
    ("dir.near_field_bounce_samples", Kind::Number),
    ("dir.seed", Kind::Number),
    ("dir.clamp_distance", Kind::Number),
    ("dir.distribution", Kind::Choice(&["equal", "weighted", "flux"])),
    ("dir.temporal.base_confidence", Kind::Number),
    ("specular.enabled", Kind::Bool),
    ("specular.impostor_resolution", Kind::Number),
    ("specular.intersection", Kind::Choice(&["impostor", "cube", "layered-cube", "planar"])),
    ("specular.cube_resolution", Kind::Number),
    ("specular.linear_steps", Kind::Number),
    ("specular.binary_steps", Kind::Number),
    ("specular.max_bounces", Kind::Number),
    ("specular.max_roughness", Kind::Number),
    ("specular.backprojection_epsilon", Kind::Number),
    ("specular.refraction", Kind::Choice(&["traced", "two-interfaces", "wyman"])),
    ("specular.probe_lobe", Kind::Number),
    ("specular.internal_reflections", Kind::Choice(&["sampled", "dropped", "kept"])),
    ("specular.refraction_policy", Kind::Choice(&["keep-refraction", "rendered"])),
    ("specular.temporal_weight", Kind::Number),
    ("caustics.enabled", Kind::Bool),
    ("caustics.photon_resolution", Kind::Number),
    ("caustics.environment_directions", Kind::Number),
    ("caustics.environment_resolution", Kind::Number),
    ("caustics.buffer_divisor", Kind::Number),
    ("caustics.splat_min", Kind::Number),
    ("caustics.splat_max", Kind::Number),
    ("caustics.splat_far_max", Kind::Number),
    ("caustics.depth_epsilon", Kind::Number),
    ("caustics.concentration", Kind::Choice(&["energy", "thesis"])),
    ("reference.spp", Kind::Number),
    ("reference.max_bounces", Kind::Number),
    // Lowering a budget is fair; raising one is the user's informed choice, not an attack.
    ("limits.lights", Kind::Number),
    ("limits.gpu_mib", Kind::Number),
    ("limits.allow_read", Kind::Path),
    ("limits.sequence_frames", Kind::Number),
    ("sequence.transforms", Kind::Path),
    ("sequence.fps", Kind::Number),
    ("sequence.frames", Kind::Number),
    ("unknown.key", Kind::Number),
];

/// Mutates `session.toml`.
pub fn mutate(files: &mut BTreeMap<String, Vec<u8>>, u: &mut Unstructured) -> String {
    let Some(text) = files.get("session.toml").map(|b| String::from_utf8_lossy(b).into_owned()) else {
        return "no session".into();
    };
    if u.ratio(1, 10).unwrap_or(false) {
        let mut raw = text.into_bytes();
        let step = bytes::mutate(&mut raw, u);
        files.insert("session.toml".into(), raw);
        return format!("session.toml bytes: {step}");
    }
    let Ok(mut table) = toml::from_str::<toml::Table>(&text) else { return "session.toml not TOML".into() };
    if u.ratio(1, 5).unwrap_or(false) {
        let scene = files.keys().find(|n| n.ends_with(".glb") || n.ends_with(".gltf")).cloned();
        let step = placed(&mut table, scene, u);
        files.insert("session.toml".into(), toml::to_string(&table).unwrap_or_default().into_bytes());
        return format!("session.toml: {step}");
    }
    let mut steps = Vec::new();
    for _ in 0..u.int_in_range(1..=3u8).unwrap_or(1) {
        let (key, kind) = KEYS[u.choose_index(KEYS.len()).unwrap_or(0)];
        // One time in ten, the wrong type.
        let kind = if u.ratio(1, 10).unwrap_or(false) { Kind::Choice(&["", "true"]) } else { kind };
        let value = match kind {
            Kind::Number => {
                let n = values::number(u, None);
                if n.fract() == 0.0 && n.abs() < 9.2e18 {
                    toml::Value::Integer(n as i64)
                } else {
                    toml::Value::Float(n)
                }
            }
            Kind::Path => toml::Value::String(values::string(u).into()),
            Kind::Bool => toml::Value::Boolean(u.ratio(1, 2).unwrap_or(false)),
            Kind::Choice(options) => toml::Value::String(options[u.choose_index(options.len()).unwrap_or(0)].into()),
        };
        let value = if key == "limits.allow_read" { toml::Value::Array(vec![value]) } else { value };
        steps.push(format!("{key} = {value}"));
        set(&mut table, key, value);
    }
    files.insert("session.toml".into(), toml::to_string(&table).unwrap_or_default().into_bytes());
    format!("session.toml: {}", steps.join("; "))
}

/// An `[[insert]]` (of the session's own scene, or of any path) or a `[camera]` table, each
/// field present or not, numbers at their boundaries.
fn placed(table: &mut toml::Table, scene: Option<String>, u: &mut Unstructured) -> String {
    let numbers = |n: usize, u: &mut Unstructured| {
        toml::Value::Array((0..n).map(|_| toml::Value::Float(values::number(u, Some(1.0)))).collect())
    };
    let mut placed = toml::Table::new();
    let key = if u.ratio(1, 2).unwrap_or(false) {
        let model = scene.filter(|_| !u.ratio(1, 5).unwrap_or(false)).unwrap_or_else(|| values::string(u).into());
        placed.insert("model".into(), toml::Value::String(model));
        for (field, n) in [("translation", 3), ("rotation", 4), ("rotation_deg", 3), ("scale", 3), ("fit", 0)] {
            if u.ratio(1, 3).unwrap_or(false) {
                let value = if n == 0 { toml::Value::Float(values::number(u, Some(0.1))) } else { numbers(n, u) };
                placed.insert(field.into(), value);
            }
        }
        for field in ["parent", "animation", "name"] {
            if u.ratio(1, 4).unwrap_or(false) {
                placed.insert(field.into(), toml::Value::String(values::string(u).into()));
            }
        }
        let inserts = table.entry("insert").or_insert_with(|| toml::Value::Array(Vec::new()));
        if let Some(list) = inserts.as_array_mut() {
            list.push(toml::Value::Table(placed.clone()));
        }
        "insert"
    } else {
        for (field, n) in [("position", 3), ("look_at", 3), ("up", 3), ("yfov", 0), ("yfov_deg", 0), ("znear", 0)] {
            if u.ratio(2, 3).unwrap_or(false) {
                let value = if n == 0 { toml::Value::Float(values::number(u, Some(0.8))) } else { numbers(n, u) };
                placed.insert(field.into(), value);
            }
        }
        table.insert("camera".into(), toml::Value::Table(placed.clone()));
        "camera"
    };
    format!("{key} = {placed}")
}

fn set(table: &mut toml::Table, dotted: &str, value: toml::Value) {
    let parts: Vec<&str> = dotted.split('.').collect();
    let mut node = table;
    for part in &parts[..parts.len() - 1] {
        let entry = node.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let Some(next) = entry.as_table_mut() else { return };
        node = next;
    }
    node.insert(parts[parts.len() - 1].to_string(), value);
}

//! Tier 1 (no GPU): every composed shader validates with naga, and every struct shared by
//! Rust and WGSL has the same size and member offsets on both sides.

use mrshade_render::methods::dir::PointAnchor;
use mrshade_render::methods::dir::{filter, indirect, ism, vpl};
use mrshade_render::methods::rsm;
use mrshade_render::methods::{dlpv, dvct};
use mrshade_render::passes::deform::GpuRange;
use mrshade_render::passes::{composite, deform, direct, encode, gbuffer};
use mrshade_render::raster;
use mrshade_render::scene_gpu::{GpuInstance, GpuLight, GpuMaterial};
use mrshade_render::specular;
use mrshade_render::specular::impostors::GpuImpostor;
use mrshade_render::specular::interior::{GpuBvhNode, GpuInterior};
use mrshade_render::uniforms::FrameUniforms;
use std::mem::{offset_of, size_of};

const MODULES: &[(&str, &str)] = &[
    ("raster", raster::SHADER),
    ("gbuffer", gbuffer::SHADER),
    ("direct", direct::SHADER),
    ("composite", composite::SHADER),
    ("rsm/resolve", rsm::RESOLVE_SHADER),
    ("rsm/pyramid", rsm::PYRAMID_SHADER),
    ("vpl/allocate", vpl::ALLOCATE_SHADER),
    ("vpl/generate", vpl::GENERATE_SHADER),
    ("vpl/bounce", vpl::BOUNCE_SHADER),
    ("ism/splat", ism::SHADER),
    ("ism/raster", ism::RASTER_SHADER),
    ("ism/clear", ism::CLEAR_SHADER),
    ("indirect", indirect::SHADER),
    ("temporal", filter::TEMPORAL_SHADER),
    ("filter", filter::FILTER_SHADER),
    ("deform", deform::SHADER),
    ("ism/follow", ism::FOLLOW_SHADER),
    ("encode", encode::SHADER),
    ("specular/trace", specular::TRACE_SHADER),
    ("specular/resolve", specular::RESOLVE_SHADER),
    ("specular/photons", specular::caustics::PHOTONS_SHADER),
    ("specular/caustic_splat", specular::caustics::SPLAT_SHADER),
    ("dvct/voxelize", dvct::VOXELIZE_SHADER),
    ("dvct/light", dvct::LIGHT_SHADER),
    ("dvct/bounce", dvct::BOUNCE_SHADER),
    ("dvct/photo", dvct::PHOTO_SHADER),
    ("dvct/mips", dvct::MIPS_SHADER),
    ("dvct/cones", dvct::GATHER_SHADER),
    ("dvct/resolve", dvct::RESOLVE_SHADER),
    ("probe_sh", mrshade_render::passes::probe_sh::SHADER),
    ("prt", mrshade_render::prt::SHADER),
    ("dlpv/inject", dlpv::INJECT_SHADER),
    ("dlpv/propagate", dlpv::PROPAGATE_SHADER),
    ("dlpv/merge", dlpv::GATHER_SHADER),
    ("dlpv/vpl_aggregate", dlpv::VPL_AGGREGATE_SHADER),
    ("dlpv/mark_cells", dlpv::VPL_MARK_SHADER),
    ("dlpv/vpl_gather", dlpv::VPL_GATHER_SHADER),
    ("dlpv/visibility_maps", dlpv::VISIBILITY_MAPS_SHADER),
    ("probe_maps/near", mrshade_render::methods::probe_maps::NEAR_SHADER),
];

fn parse(name: &str, source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)))
}

#[test]
fn every_shader_validates() {
    for (name, source) in MODULES {
        let module = parse(name, source);
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    }
}

/// Size and `(member, offset)` of WGSL struct `name` in `source`.
fn wgsl_layout(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
    let module = parse(name, source);
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() == Some(name)
            && let naga::TypeInner::Struct { members, span } = &ty.inner
        {
            return (*span, members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect());
        }
    }
    panic!("struct {name} not found");
}

fn assert_layout(source: &str, name: &str, size: usize, offsets: &[(&str, usize)]) {
    let (span, members) = wgsl_layout(source, name);
    assert_eq!(span as usize, size, "size of {name}");
    let rust: Vec<(String, u32)> = offsets.iter().map(|(n, o)| (n.to_string(), *o as u32)).collect();
    assert_eq!(members, rust, "members of {name}");
}

#[test]
fn dlpv_params_match() {
    for source in [
        dlpv::INJECT_SHADER,
        dlpv::PROPAGATE_SHADER,
        dlpv::GATHER_SHADER,
        dlpv::VPL_AGGREGATE_SHADER,
        dlpv::VPL_MARK_SHADER,
        dlpv::VPL_GATHER_SHADER,
        dlpv::VISIBILITY_MAPS_SHADER,
    ] {
        assert_layout(
            source,
            "DlpvParams",
            size_of::<dlpv::DlpvParams>(),
            &[
                ("origin", offset_of!(dlpv::DlpvParams, origin)),
                ("info", offset_of!(dlpv::DlpvParams, info)),
                ("scale", offset_of!(dlpv::DlpvParams, scale)),
                ("steps", offset_of!(dlpv::DlpvParams, steps)),
                ("gathered", offset_of!(dlpv::DlpvParams, gathered)),
            ],
        );
    }
    // The RSM texel the injection reads is the one the RSM pass writes.
    assert_eq!(wgsl_layout(dlpv::INJECT_SHADER, "RsmTexel").0 as u64, mrshade_render::methods::rsm::TEXEL_BYTES);
}

/// shaders/lib/sh.wgsl has the constants of mrshade_core::sh.
#[test]
fn sh_constants_match() {
    use mrshade_core::sh::{Y0, Y1};
    let source = dlpv::PROPAGATE_SHADER;
    for (name, value) in [("SH_Y0", Y0), ("SH_Y1", Y1)] {
        let text = source.split(&format!("const {name}: f32 = ")).nth(1).and_then(|s| s.split(';').next()).unwrap();
        assert!((text.parse::<f32>().unwrap() - value).abs() < 1e-6, "{name}");
    }
    // sh9's band-2 factors, sh16's band-3 ones.
    use mrshade_core::sh::{Y2, Y3, Y20, Y22, Y32};
    for value in [Y2, Y20, Y22, Y32].into_iter().chain(Y3) {
        assert!(source.contains(&format!("{value}")), "sh9 or sh16 uses {value}");
    }
}

#[test]
fn dvct_volume_params_match() {
    for source in [dvct::VOXELIZE_SHADER, dvct::GATHER_SHADER] {
        assert_layout(
            source,
            "VolumeParams",
            size_of::<dvct::VolumeParams>(),
            &[
                ("origin", offset_of!(dvct::VolumeParams, origin)),
                ("info", offset_of!(dvct::VolumeParams, info)),
                ("cone", offset_of!(dvct::VolumeParams, cone)),
            ],
        );
    }
}

#[test]
fn frame_uniforms_match() {
    assert_layout(
        direct::SHADER,
        "Frame",
        size_of::<FrameUniforms>(),
        &[
            ("clip_from_world", offset_of!(FrameUniforms, clip_from_world)),
            ("world_from_clip", offset_of!(FrameUniforms, world_from_clip)),
            ("previous_clip_from_world", offset_of!(FrameUniforms, previous_clip_from_world)),
            ("probe_from_world", offset_of!(FrameUniforms, probe_from_world)),
            ("camera_position", offset_of!(FrameUniforms, camera_position)),
            ("size", offset_of!(FrameUniforms, size)),
            ("counts", offset_of!(FrameUniforms, counts)),
            ("exposure_env", offset_of!(FrameUniforms, exposure_env)),
        ],
    );
}

#[test]
fn lights_materials_instances_match() {
    assert_layout(
        direct::SHADER,
        "Light",
        size_of::<GpuLight>(),
        &[
            ("position", offset_of!(GpuLight, position)),
            ("direction_real", offset_of!(GpuLight, direction_real)),
            ("intensity", offset_of!(GpuLight, intensity)),
            ("cone", offset_of!(GpuLight, cone)),
            ("info", offset_of!(GpuLight, info)),
        ],
    );
    assert_layout(
        gbuffer::SHADER,
        "Material",
        size_of::<GpuMaterial>(),
        &[
            ("base_color", offset_of!(GpuMaterial, base_color)),
            ("params", offset_of!(GpuMaterial, params)),
            ("dielectric", offset_of!(GpuMaterial, dielectric)),
            ("transmission", offset_of!(GpuMaterial, transmission)),
            ("attenuation_cutoff", offset_of!(GpuMaterial, attenuation_cutoff)),
            ("emissive", offset_of!(GpuMaterial, emissive)),
            ("texture_layers", offset_of!(GpuMaterial, texture_layers)),
            ("texture_info", offset_of!(GpuMaterial, texture_info)),
        ],
    );
    for source in [gbuffer::SHADER, raster::SHADER] {
        assert_layout(
            source,
            "Instance",
            size_of::<GpuInstance>(),
            &[
                ("world_from_object", offset_of!(GpuInstance, world_from_object)),
                ("normal_from_object", offset_of!(GpuInstance, normal_from_object)),
                ("previous_world_from_object", offset_of!(GpuInstance, previous_world_from_object)),
                ("info", offset_of!(GpuInstance, info)),
            ],
        );
    }
}

#[test]
fn flag_constants_match_the_core_crate() {
    use mrshade_core::flags::{SURFACE_COVERED, SURFACE_MATERIAL_SHIFT, SURFACE_REAL};
    let source = gbuffer::SHADER;
    for (name, value) in [
        ("SURFACE_COVERED", SURFACE_COVERED),
        ("SURFACE_REAL", SURFACE_REAL),
        ("SURFACE_MATERIAL_SHIFT", SURFACE_MATERIAL_SHIFT),
    ] {
        assert!(source.contains(&format!("const {name}: u32 = {value}u;")), "{name} differs");
    }
}

#[test]
fn deformation_and_follow_structs_match() {
    assert_layout(
        deform::SHADER,
        "Range",
        size_of::<GpuRange>(),
        &[
            ("first", offset_of!(GpuRange, first)),
            ("count", offset_of!(GpuRange, count)),
            ("destination", offset_of!(GpuRange, destination)),
            ("joint_base", offset_of!(GpuRange, joint_base)),
            ("weight_base", offset_of!(GpuRange, weight_base)),
            ("target_count", offset_of!(GpuRange, target_count)),
            ("delta_base", offset_of!(GpuRange, delta_base)),
            ("_pad", offset_of!(GpuRange, delta_base) + 4),
        ],
    );
    // The shader reads the corners one by one and ignores the instance (made the corners'
    // base when uploaded), which it sees as padding.
    let corners = offset_of!(PointAnchor, corners);
    assert_layout(
        ism::FOLLOW_SHADER,
        "Anchor",
        size_of::<PointAnchor>(),
        &[
            ("point", offset_of!(PointAnchor, point)),
            ("a", corners),
            ("b", corners + 4),
            ("c", corners + 8),
            ("weights", offset_of!(PointAnchor, weights)),
            ("_pad", offset_of!(PointAnchor, instance)),
        ],
    );
}

#[test]
fn impostors_match() {
    assert_layout(
        specular::TRACE_SHADER,
        "Impostor",
        size_of::<GpuImpostor>(),
        &[
            ("clip_from_world", offset_of!(GpuImpostor, clip_from_world)),
            ("info", offset_of!(GpuImpostor, info)),
            ("eye", offset_of!(GpuImpostor, eye)),
            ("seen_min", offset_of!(GpuImpostor, seen_min)),
            ("seen_max", offset_of!(GpuImpostor, seen_max)),
        ],
    );
}

#[test]
fn interiors_match() {
    assert_layout(
        specular::TRACE_SHADER,
        "BvhNode",
        size_of::<GpuBvhNode>(),
        &[
            ("min", offset_of!(GpuBvhNode, min)),
            ("count", offset_of!(GpuBvhNode, count)),
            ("max", offset_of!(GpuBvhNode, max)),
            ("first", offset_of!(GpuBvhNode, first)),
        ],
    );
    assert_layout(
        specular::TRACE_SHADER,
        "Interior",
        size_of::<GpuInterior>(),
        &[("object_from_world", offset_of!(GpuInterior, object_from_world)), ("info", offset_of!(GpuInterior, info))],
    );
}

#[test]
fn caustic_structs_match() {
    use mrshade_render::specular::caustics::{
        COARSE_LEVEL_FACTOR, CausticParams, GRID_BOX_MIN_WORD, GRID_CELLS_PER_PHOTON, GRID_EPSILON_WORD,
        GRID_HEADER_WORDS, GRID_PHOTON_BYTES, GRID_RANGES_WORKGROUP, GRID_SPLAT_MIN_WORD, GRID_TOTAL_WORD,
        PHOTON_BYTES, PHOTONS_SHADER, SPLAT_GROUPS, SPLAT_SHADER, SUM_WORDS,
    };
    assert_layout(
        PHOTONS_SHADER,
        "CausticParams",
        size_of::<CausticParams>(),
        &[
            ("info", offset_of!(CausticParams, info)),
            ("casters", offset_of!(CausticParams, casters)),
            ("splat", offset_of!(CausticParams, splat)),
        ],
    );
    assert_eq!(wgsl_layout(PHOTONS_SHADER, "Photon").0 as u64, PHOTON_BYTES);
    assert_eq!(wgsl_layout(PHOTONS_SHADER, "GridPhoton").0 as u64, GRID_PHOTON_BYTES);
    for (name, word) in [
        ("GRID_HEADER", GRID_HEADER_WORDS),
        ("GRID_SPLAT_MIN_WORD", GRID_SPLAT_MIN_WORD),
        ("GRID_EPSILON_WORD", GRID_EPSILON_WORD),
        ("GRID_BOX_MIN_WORD", GRID_BOX_MIN_WORD),
        ("GRID_TOTAL_WORD", GRID_TOTAL_WORD),
    ] {
        assert!(PHOTONS_SHADER.contains(&format!("const {name}: u32 = {word}u;")), "{name} = {word}");
    }
    assert!(SPLAT_SHADER.contains(&format!("const COARSE_LEVEL_FACTOR: u32 = {COARSE_LEVEL_FACTOR}u;")));
    assert!(SPLAT_SHADER.contains(&format!("const SPLAT_GROUPS: u32 = {SPLAT_GROUPS}u;")));
    assert!(ism::CLEAR_SHADER.contains(&format!("const CLEAR_GROUPS: u32 = {}u;", ism::CLEAR_GROUPS)));
    assert!(SPLAT_SHADER.contains(&format!("const SUM_WORDS: u32 = {SUM_WORDS}u;")));
    assert!(PHOTONS_SHADER.contains(&format!("@compute @workgroup_size({GRID_RANGES_WORKGROUP})\nfn cs_grid_ranges")));
    let per_axis = (GRID_CELLS_PER_PHOTON as f64).cbrt().round() as u64;
    assert_eq!(per_axis.pow(3), GRID_CELLS_PER_PHOTON);
    assert!(PHOTONS_SHADER.contains(&format!("const GRID_CELLS_PER_AXIS: i32 = {per_axis};")));
    // The largest quads the settings allow fit the grid's levels, √2 apart.
    let levels: i32 = PHOTONS_SHADER
        .split("const GRID_LEVELS: u32 = ")
        .nth(1)
        .and_then(|s| s.split('u').next())
        .and_then(|s| s.parse().ok())
        .expect("GRID_LEVELS");
    assert!(mrshade_core::settings::MAX_SPLAT_RATIO <= 2f32.sqrt().powi(levels - 1));
}

#[test]
fn the_cube_face_side_matches_the_cube_views() {
    let fov = std::f32::consts::FRAC_PI_2 + mrshade_render::scene_gpu::FOV_MARGIN;
    let source = mrshade_render::specular::caustics::PHOTONS_SHADER;
    let value = source.split("const CUBE_FACE_SIDE: f32 = ").nth(1).and_then(|s| s.split(';').next()).unwrap();
    let side: f32 = value.parse().unwrap();
    assert!((side - 2.0 * (fov / 2.0).tan()).abs() < 1e-4, "CUBE_FACE_SIDE {side} for a {fov} rad face");
}

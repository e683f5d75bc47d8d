//! Known answers of the `dir` method's passes on lavapipe against CPU math: a 4×4 reflective
//! shadow map gives the expected VPLs (Knecht §2.8), one VPL splats the expected ISM depths
//! (§2.9), and the flag rules route a hand-built path table to the right buffers (§2.7).

mod common;

use common::{Setup, rel};
use glam::Vec3;
use mrshade_render::methods::dir::vpl::{GpuVpl, kind};
use mrshade_render::methods::dir::{DirMethod, IsmDepths};
use mrshade_render::scene_gpu::FOV_MARGIN;
use serde_json::json;

#[test]
fn a_still_is_lit_by_every_vpl_at_every_pixel() {
    // Frames interleave 4 × 4 (the thesis's); a still renderer takes `dir.still_interleave`,
    // and its ISM splats `dir.still_splat_scale` (1) where frames' are `dir.splat_scale` (1.5).
    let mut s = Setup::top_down(16);
    s.top_toml = "method = \"dir\"\n".into();
    s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.1, 0.0], 0.1, false);
    let (_dir, session) = s.session();
    let ctx = mrshade_testkit::gpu();
    let frames = mrshade_render::Renderer::new(&ctx, &session).unwrap();
    let still = mrshade_render::Renderer::for_still(&ctx, &session).unwrap();
    let interleave = |r: &mrshade_render::Renderer| r.method_as::<DirMethod>().unwrap().interleave();
    assert_eq!((interleave(&frames), interleave(&still)), (4, 1));
    let splat = |r: &mrshade_render::Renderer| r.method_as::<DirMethod>().unwrap().ism_resources.params.splat;
    assert!((splat(&still).x * 1.5 - splat(&frames).x).abs() < 1e-6 * splat(&frames).x);
    assert!((splat(&still).y * 1.5 - splat(&frames).y).abs() < 1e-6 * splat(&frames).y);
}

/// VPL flag bits (vpl.wgsl).
const REAL: u32 = 1;
const IR: u32 = 2;
const PATH_REAL: u32 = 4;
const BOUNCED: u32 = 8;

/// A virtual spot (straight down from `height`) over a real floor of albedo 0.5, with
/// `extra` session tables, rendered for one frame.
fn spot_over_floor(height: f32, outer: f32, inner: f32, intensity: f32, extra: &str) -> (Setup, common::Rendered) {
    let mut s = Setup::top_down(16);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = format!("[output]\nframes = 1\n{extra}");
    s.plane(2.0, 0.0, 0.5, true);
    s.light(
        json!({"type": "spot", "intensity": intensity, "spot": {"innerConeAngle": inner, "outerConeAngle": outer}}),
        [0.0, height, 0.0],
        false,
    );
    let r = s.render();
    (s, r)
}

fn surface_vpls(vpls: &[GpuVpl]) -> Vec<&GpuVpl> {
    vpls.iter().filter(|v| v.info.z == kind::SURFACE).collect()
}

/// The spot's 4×4 RSM on the CPU: every texel's centre ray meets the floor at `x·h`, and the
/// power through the texel is I · spot(θ) · (texel extent)² · cos³θ (a perspective texel's
/// solid angle), with the glTF smooth cone falloff.
#[test]
fn a_4x4_rsm_gives_the_expected_vpls() {
    let (h, outer, inner, intensity) = (0.8f32, 0.6f32, 0.4f32, 2.0f32);
    let (_, r) =
        spot_over_floor(h, outer, inner, intensity, "[dir]\nrsm_resolution = 4\nvpl_count = 16\nbounce = \"off\"\n");
    let t = (outer + 0.5 * FOV_MARGIN).tan();
    let extent = 2.0 * t / 4.0;
    let (cos_outer, cos_inner) = (outer.cos(), inner.cos());
    let mut texels = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            let (x, z) = (((i as f32 + 0.5) / 2.0 - 1.0) * t, ((j as f32 + 0.5) / 2.0 - 1.0) * t);
            let c = 1.0 / (1.0 + x * x + z * z).sqrt();
            let falloff = ((c - cos_outer) / (cos_inner - cos_outer)).clamp(0.0, 1.0).powi(2);
            texels.push((Vec3::new(x * h, 0.0, z * h), intensity * falloff * extent * extent * c * c * c));
        }
    }
    let total: f32 = texels.iter().map(|t| t.1).sum();
    let lit: Vec<_> = texels.iter().filter(|t| t.1 > 0.0).collect();
    assert_eq!(lit.len(), 12, "the corner texels lie outside the cone");
    let vpls = r.renderer.method_as::<DirMethod>().expect("dir method").read_vpls(&r.ctx).unwrap();
    let surface = surface_vpls(&vpls);
    assert_eq!(surface.len(), 16, "every slot holds a VPL");
    for v in surface {
        let p = v.position.truncate();
        let nearest = lit.iter().map(|t| t.0.distance(p)).fold(f32::MAX, f32::min);
        assert!(nearest < 1e-3, "VPL at {p} is at no lit texel's centre ({nearest} m away)");
        // Texels are drawn ∝ their reflected power, so each VPL carries Φ_total / 16.
        assert!(rel(v.power.x, total / 16.0) < 2e-3, "power {} vs {}", v.power.x, total / 16.0);
        assert!((v.normal.truncate() - Vec3::Y).length() < 1e-4);
        assert_eq!(v.info.x, REAL, "a virtual light's VPL on a real surface: r, not x̄");
        assert_eq!(v.info.w, 1, "one reflection");
    }
}

/// Duff et al.'s orthonormal basis, as `tangent_frame` in sampling.wgsl.
fn tangent_frame(n: Vec3) -> [Vec3; 2] {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x), Vec3::new(b, s + n.y * n.y * a, -n.y)]
}

/// One VPL on the floor under a virtual square (half size 0.1 m) 0.15 m above it: every
/// texel of the VPL's virtual-only map whose direction (hemispherical mapping) meets the
/// square holds the distance to it, texels whose direction misses it by more than a splat
/// hold nothing, and the square's interior has no holes.
#[test]
fn one_vpl_splats_the_expected_ism_depths() {
    let (height, half) = (0.15f32, 0.1f32);
    let centre = Vec3::new(0.05, height, 0.0);
    let mut s = Setup::top_down(16);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = "[output]\nframes = 1\n[dir]\nrsm_resolution = 4\nvpl_count = 1\nbounce = \"off\"\nism_resolution = 64\ninterleave = 1\n".into();
    s.plane(2.0, 0.0, 0.5, true);
    s.light(
        json!({"type": "spot", "intensity": 1.0, "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.2}}),
        [0.0, 0.8, 0.0],
        true,
    );
    let m = s.gltf.material(mrshade_testkit::gltf::lambert("square", [0.5; 3]));
    let mesh = s.gltf.mesh(&mrshade_testkit::gltf::quad(half), Some(m), true);
    s.gltf.node(json!({"name": "square", "mesh": mesh, "translation": centre.to_array(), "extras": {"real": false}}));
    let r = s.render();
    let vpls = r.renderer.method_as::<DirMethod>().expect("dir method").read_vpls(&r.ctx).unwrap();
    let v = surface_vpls(&vpls)[0];
    let (origin, n) = (v.position.truncate(), v.normal.truncate());
    let IsmDepths { side, tile, depths } =
        r.renderer.method_as::<DirMethod>().expect("dir method").read_ism_depths(&r.ctx).unwrap();
    assert_eq!(tile, 64);
    let frame = tangent_frame(n);
    let (mut inside, mut filled) = (0, 0);
    // The splats' half size (m): up to this far outside the square a texel may be covered.
    let margin = 0.03;
    for y in 0..tile {
        for x in 0..tile {
            let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5) / tile as f32 * 2.0 - 1.0;
            let z2 = 1.0 - uv.length_squared();
            let stored = depths.rv[(y * side + x) as usize];
            if z2 <= 0.0 {
                assert!(stored.is_infinite(), "texel ({x},{y}) is outside the hemisphere");
                continue;
            }
            let dir = frame[0] * uv.x + frame[1] * uv.y + n * z2.sqrt();
            let t = (height - origin.y) / dir.y;
            let hit = origin + dir * t;
            let off = (hit - centre).abs().max_element();
            if dir.y > 0.0 && off < half - margin {
                inside += 1;
                if stored.is_finite() {
                    filled += 1;
                    assert!(
                        (stored - t).abs() < 1e-3 * t + 1e-4,
                        "texel ({x},{y}): stored {stored} m, the square is at {t} m"
                    );
                }
            } else if dir.y <= 0.0 || off > half + margin {
                assert!(stored.is_infinite(), "texel ({x},{y}) misses the square but holds {stored} m");
            }
        }
    }
    assert!(inside > 50, "the square covers {inside} texels");
    assert!(filled as f32 >= 0.95 * inside as f32, "holes: {filled} of {inside} texels filled");
}

/// A path-table row: what it is, VPL flags, receiver real, V_r, V_v → weights in
/// (L_rv, L_r, VPL3 in L_r).
type Row = (&'static str, u32, bool, f32, f32, [f32; 3]);

/// A hand-built path table: for each VPL (its flags) and receiver (real or virtual, V_r,
/// V_v), the weights of its light in L_rv and L_r and of its co-located VPL3 in L_r, by the
/// thesis's rules, against `vpl_routing` run on the GPU.
#[test]
fn the_flag_rules_route_a_path_table_to_the_right_buffers() {
    // (what it is, VPL flags, receiver real, V_r, V_v) → (L_rv, L_r, VPL3 in L_r)
    #[rustfmt::skip]
    let table: &[Row] = &[
        ("real light off the real floor onto a real wall", REAL | PATH_REAL, true, 1.0, 1.0, [1.0, 1.0, 1.0]),
        ("… a virtual object in between: shadow in L_rv only", REAL | PATH_REAL, true, 1.0, 0.0, [0.0, 1.0, 1.0]),
        ("… a real object in between: shadow in both", REAL | PATH_REAL, true, 0.0, 1.0, [0.0, 0.0, 0.0]),
        ("… onto a virtual object: L_rv only", REAL | PATH_REAL, false, 1.0, 1.0, [1.0, 0.0, 0.0]),
        ("virtual light off the real floor: L_rv only", REAL, true, 1.0, 1.0, [1.0, 0.0, 1.0]),
        ("real light off a virtual object: L_rv only", 0, true, 1.0, 1.0, [1.0, 0.0, 1.0]),
        ("VPL3: real bleeding a virtual object blocks, real receiver", REAL | IR | PATH_REAL, true, 1.0, 1.0, [0.0, 1.0, 1.0]),
        ("VPL3 with a real occluder", REAL | IR | PATH_REAL, true, 0.0, 1.0, [0.0, 0.0, 0.0]),
        ("VPL3 onto a virtual object", REAL | IR | PATH_REAL, false, 1.0, 1.0, [0.0, 0.0, 0.0]),
        ("second bounce of a virtual light's path on real walls", REAL, true, 1.0, 0.0, [0.0, 0.0, 1.0]),
    ];
    let cases: Vec<[u32; 4]> =
        table.iter().map(|&(_, f, real, vr, vv, _)| [f, real as u32, vr.to_bits(), vv.to_bits()]).collect();
    let got = mrshade_testkit::run_kernel(
        &mrshade_testkit::gpu(),
        concat!(
            include_str!("../shaders/lib/frame.wgsl"),
            include_str!("../shaders/lib/brdf.wgsl"),
            include_str!("../shaders/lib/vpl.wgsl"),
            "
            struct Case { flags: u32, receiver_real: u32, v_r: f32, v_v: f32 }
            @group(0) @binding(0) var<storage, read> cases: array<Case>;
            @group(0) @binding(1) var<storage, read_write> out: array<vec4f>;
            @compute @workgroup_size(1)
            fn cs_main(@builtin(global_invocation_id) id: vec3u) {
                let c = cases[id.x];
                out[id.x] = vec4f(vpl_routing(c.flags, f32(c.receiver_real), vec2f(c.v_r, c.v_v)), 0.0);
            }"
        ),
        bytemuck::cast_slice(&cases),
        cases.len() as u32,
    );
    for (row, out) in table.iter().zip(got.chunks(4)) {
        assert_eq!(&out[..3], &row.5, "{}", row.0);
    }
}

/// The multiple-bounce source (§2.8) in the real-only world: a real lamp lights a real floor
/// under a real ceiling, and a virtual box floats in between. Bounce rays from the floor that
/// meet the box first become, half of them, a virtual VPL on the box (L_rv), the other half a
/// VPL3 on the ceiling behind it (ir: L_r only), where the real-only path goes on; rays that
/// miss the box reach the ceiling as ordinary real VPLs. (A VPL3 bounces on as ir, through
/// the box, on real surfaces only.)
#[test]
fn a_bounce_ray_that_meets_virtual_geometry_first_goes_on_to_a_real_surface_as_a_vpl3() {
    let (ceiling, box_half) = (1.0f32, 0.3f32);
    let mut s = Setup::top_down(16);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = "[output]\nframes = 3\n[dir]\nvpl_count = 256\n".into();
    s.plane(2.0, 0.0, 0.5, true).plane(2.0, ceiling, 0.5, true).cube([0.0, 0.5, 0.0], box_half, false);
    s.light(
        json!({"type": "spot", "intensity": 2.0, "spot": {"innerConeAngle": 0.9, "outerConeAngle": 1.2}}),
        [0.0, 0.1, 0.0],
        true,
    );
    let r = s.render();
    let vpls = r.renderer.method_as::<DirMethod>().expect("dir method").read_vpls(&r.ctx).unwrap();
    // Sources: the lamp (0), then the multiple-bounce source (1).
    let bounce: Vec<&GpuVpl> = surface_vpls(&vpls).into_iter().filter(|v| v.info.y == 1).collect();
    // The first bounce off the floor: lamp → floor → here.
    let first: Vec<&GpuVpl> = bounce.iter().copied().filter(|v| v.info.w == 2).collect();
    let on_box = |v: &GpuVpl| (v.position.truncate() - Vec3::new(0.0, 0.5, 0.0)).abs().max_element() <= box_half + 1e-3;
    let on_ceiling = |v: &GpuVpl| (v.position.y - ceiling).abs() < 1e-3;
    let virtual_hits = first.iter().filter(|v| on_box(v)).count();
    // Every multiple-bounce VPL says so (its near field is the screen's, vpl.wgsl).
    assert!(bounce.iter().all(|v| v.info.x & BOUNCED != 0), "multiple-bounce VPLs are flagged");
    let vpl3 = first.iter().filter(|v| on_ceiling(v) && v.info.x == REAL | IR | PATH_REAL | BOUNCED).count();
    let plain = first.iter().filter(|v| on_ceiling(v) && v.info.x == REAL | PATH_REAL | BOUNCED).count();
    assert!(first.iter().filter(|v| on_box(v)).all(|v| v.info.x == BOUNCED), "a VPL on the box is virtual, x̄ = 0");
    for v in bounce.iter().filter(|v| v.info.x & IR != 0) {
        assert!(!on_box(v) && v.info.x & REAL != 0, "a VPL3 lies on a real surface: {v:?}");
    }
    assert!(virtual_hits >= 5 && vpl3 >= 5 && plain >= 5, "box {virtual_hits}, VPL3 {vpl3}, ceiling {plain}");
    // Each blocked ray chooses one of its two VPLs with probability ½.
    let share = vpl3 as f32 / (vpl3 + virtual_hits) as f32;
    assert!((0.25..=0.75).contains(&share), "VPL3 share of the blocked rays {share}");
}

/// Caustic VPLs (reflections spec §2.18): a real spot aimed at a virtual mirror on the floor
/// sends its whole cone up onto a real wall. The RSM places no VPL on the mirror; the caustic
/// source's VPLs lie where the reflected beam meets the wall (mirror image of the spot
/// through the floor plane, on to the wall), face the room, route to `L_rv` only (the mirror
/// is virtual: r, not x̄) and together carry the cone's power (white metal: F = 1).
#[test]
fn caustic_vpls_sit_where_a_mirror_sends_a_spot_with_its_power() {
    let (spot, mirror, wall_x) = (Vec3::new(1.0, 0.3, 0.0), Vec3::new(0.3, 0.002, 0.0), -0.5f32);
    let (outer, inner, intensity) = (0.05f32, 0.04f32, 20.0f32);
    let mut s = Setup::top_down(16);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = "[output]\nframes = 3\n[dir]\nvpl_count = 64\nbounce = \"off\"\ndistribution = \"equal\"\n\
                    [caustics]\nphoton_resolution = 64\n"
        .into();
    s.plane(2.0, 0.0, 0.5, true);
    let wall_material = s.gltf.material(mrshade_testkit::gltf::lambert("wall", [0.5; 3]));
    let wall = s.gltf.mesh(&mrshade_testkit::gltf::quad(0.6), Some(wall_material), true);
    s.gltf.node(json!({"name": "wall", "mesh": wall, "translation": [wall_x, 0.6, 0.0],
        "rotation": mrshade_testkit::gltf::quat([0.0, 0.0, 1.0], -std::f32::consts::FRAC_PI_2), "extras": {"real": true}}));
    let chrome = s.gltf.material(json!({"name": "mirror",
        "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1.0, "roughnessFactor": 0.0}}));
    let m = s.gltf.mesh(&mrshade_testkit::gltf::quad(0.15), Some(chrome), true);
    s.gltf.node(json!({"name": "mirror", "mesh": m, "translation": mirror.to_array(), "extras": {"real": false}}));
    let aim = (mirror - spot).normalize();
    let l = s.gltf.light(json!({"type": "spot", "intensity": intensity,
        "spot": {"innerConeAngle": inner, "outerConeAngle": outer}}));
    s.gltf.node(json!({"name": "lamp", "translation": spot.to_array(),
        "rotation": glam::Quat::from_rotation_arc(Vec3::NEG_Z, aim).to_array(),
        "extensions": {"KHR_lights_punctual": {"light": l}}, "extras": {"real": true}}));
    let r = s.render();
    let vpls = r.renderer.method_as::<DirMethod>().expect("dir method").read_vpls(&r.ctx).unwrap();
    // Sources: the lamp (0), then the caustics (1).
    let on_mirror = |v: &&GpuVpl| (v.position.y - mirror.y).abs() < 1e-3 && (v.position.x - mirror.x).abs() < 0.15;
    assert!(
        !surface_vpls(&vpls).iter().filter(|v| v.info.y == 0).any(on_mirror),
        "the RSM places no VPL on the mirror"
    );
    let caustic: Vec<&GpuVpl> = surface_vpls(&vpls).into_iter().filter(|v| v.info.y == 1).collect();
    assert!(caustic.len() >= 24, "{} of the 32 caustic slots hold a VPL", caustic.len());
    // The beam's axis, reflected at the floor plane of the mirror, meets the wall here.
    let reflected = Vec3::new(aim.x, -aim.y, aim.z);
    let hit = mirror + reflected * ((wall_x - mirror.x) / reflected.x);
    // The cone's footprint there: its radius over the whole path, stretched by the incidence.
    let footprint = outer.tan() * (spot.distance(mirror) + mirror.distance(hit)) / reflected.x.abs() + 0.01;
    for v in &caustic {
        let p = v.position.truncate();
        assert!((p.x - wall_x).abs() < 1e-3 && p.distance(hit) < footprint, "caustic VPL at {p}, beam at {hit}");
        assert!((v.normal.truncate() - Vec3::X).length() < 1e-3, "it faces the room: {:?}", v.normal);
        assert_eq!(v.info.x, REAL, "on the real wall via the virtual mirror: r, not x̄");
        assert_eq!(v.info.w, 2, "light → mirror → wall");
    }
    // The cone's power: I · 2π ∫ falloff(θ) sin θ dθ, glTF's smooth falloff.
    let (cos_outer, cos_inner) = (outer.cos(), inner.cos());
    let steps = 4000;
    let power: f32 = (0..steps)
        .map(|k| {
            let theta = (k as f32 + 0.5) / steps as f32 * outer;
            let falloff = ((theta.cos() - cos_outer) / (cos_inner - cos_outer)).clamp(0.0, 1.0).powi(2);
            intensity * 2.0 * std::f32::consts::PI * falloff * theta.sin() * outer / steps as f32
        })
        .sum();
    let carried: f32 = caustic.iter().map(|v| v.power.y).sum::<f32>() * 32.0 / caustic.len() as f32;
    assert!(rel(carried, power) < 0.2, "the caustic VPLs carry {carried} W of the cone's {power} W");
}

/// `dir.seed` picks which VPLs the sequences draw: the same seed draws the same VPLs, another
/// seed other ones (of the same light: the totals agree), so that settings can be scored over
/// independent runs.
#[test]
fn a_seed_draws_other_vpls_and_the_same_seed_the_same() {
    let vpls = |seed: u32| -> Vec<GpuVpl> {
        let (_s, r) = spot_over_floor(1.0, 0.6, 0.4, 2.0, &format!("[dir]\nseed = {seed}\nvpl_count = 64\n"));
        r.renderer.method_as::<DirMethod>().expect("dir method").read_vpls(&r.ctx).unwrap()
    };
    let positions =
        |v: &[GpuVpl]| -> Vec<[f32; 3]> { surface_vpls(v).iter().map(|v| v.position.truncate().to_array()).collect() };
    let (a, again, b) = (vpls(0), vpls(0), vpls(7));
    assert_eq!(positions(&a), positions(&again), "the same seed drew other VPLs");
    assert_ne!(positions(&a), positions(&b), "another seed drew the same VPLs");
    let power = |v: &[GpuVpl]| -> f32 { surface_vpls(v).iter().map(|v| v.power.x).sum() };
    assert!(rel(power(&a), power(&b)) < 0.1, "total power {} vs {}", power(&a), power(&b));
}

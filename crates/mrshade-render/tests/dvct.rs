//! Known answers of the `dvct` method's volumes (Franke §2.13): voxelisation, the light in
//! the voxels and their anisotropic mipmaps, on the test GPU. What the cones see of them:
//! tests/dvct_cones.rs.

mod common;

use common::Setup;
use common::dvct::{dvct, dvct_method};
use glam::{UVec3, Vec3};

/// Every voxel of the inner volume of a `dvct` render: its centre and its real and virtual
/// words (volume.wgsl: the kept triangle + 1, 0 when it holds none).
fn voxel_words(r: &common::Rendered) -> Vec<(Vec3, u32, u32)> {
    let method = dvct_method(r);
    let params = method.params();
    let (origin, voxel, res) = (params.origin.truncate(), params.origin.w, params.info.x);
    let bytes = mrshade_gpu::readback::read_buffer(&r.ctx, method.voxels()).unwrap();
    let words: &[u32] = bytemuck::cast_slice(&bytes);
    (0..res * res * res)
        .map(|i| {
            let v = UVec3::new(i % res, (i / res) % res, i / (res * res));
            (origin + (v.as_vec3() + 0.5) * voxel, words[2 * i as usize], words[2 * i as usize + 1])
        })
        .collect()
}

/// Distance from `p` to the surface of the axis-aligned cube at `c` of half side `h`.
fn cube_surface_distance(p: Vec3, c: Vec3, h: f32) -> f32 {
    let q = (p - c).abs() - Vec3::splat(h);
    let outside = q.max(Vec3::ZERO).length();
    let inside = q.max_element().min(0.0);
    (outside + inside).abs()
}

#[test]
fn a_voxelised_cube_is_a_closed_shell_one_voxel_thick() {
    let mut s = Setup::top_down(32);
    let (centre, half) = (Vec3::new(0.013, 0.1, -0.021), 0.1);
    s.cube(centre.to_array(), half, false);
    dvct(&mut s, 32);
    let r = s.render();
    let params = dvct_method(&r).params();
    let (voxel, res) = (params.origin.w, params.info.x);
    // Twice the cube's edge, centred on it (spec §2.13.1).
    assert!((voxel * res as f32 - 4.0 * half).abs() < 1e-4, "side {}", voxel * res as f32);
    let (mut holes, mut strays, mut occupied) = (0, 0, 0);
    for (p, real, virt) in voxel_words(&r) {
        let d = cube_surface_distance(p, centre, half) / voxel;
        assert_eq!(real, 0, "no real surface in this scene");
        occupied += (virt != 0) as u32;
        // A surface passing nearer a voxel's centre than half its side must mark it (a face
        // on a boundary between two voxels marks one of them: 0.45); none may mark a voxel it
        // does not come near.
        holes += (d < 0.45 && virt == 0) as u32;
        strays += (d > 0.5 * 3f32.sqrt() + 0.01 && virt != 0) as u32;
    }
    assert_eq!((holes, strays), (0, 0), "{occupied} voxels occupied");
    // The shell of a cube 16 voxels wide: between 16³ − 14³ and 18³ − 14³ voxels.
    assert!((1352..=3088).contains(&occupied), "{occupied} voxels occupied");
}

#[test]
fn a_voxel_that_holds_both_faces_of_a_thin_real_wall_keeps_the_one_facing_the_content() {
    // A real wall 8 mm thick in voxels of 12.5 mm beside a virtual cube: where a voxel holds
    // its inner face, it keeps that face (the side the content sees, lit and in the photo),
    // not the outer one, which the highest triangle number picked here (the cuboid's −x face
    // comes after its +x face): cornell's walls gathered dark.
    let mut s = Setup::top_down(32);
    s.cube([0.0, 0.1, 0.0], 0.1, false);
    let m = s.gltf.material(mrshade_testkit::gltf::lambert("wall", [0.7; 3]));
    let wall = s.gltf.mesh(&mrshade_testkit::gltf::cuboid([0.004, 0.08, 0.08]), Some(m), true);
    s.gltf.node(
        serde_json::json!({"name": "wall", "mesh": wall, "translation": [-0.15, 0.1, 0.0], "extras": {"real": true}}),
    );
    dvct(&mut s, 32);
    let r = s.render();
    let voxel = dvct_method(&r).params().origin.w;
    let inner_face = -0.146;
    let (mut checked, mut outer_kept) = (0, 0);
    for (p, real, _) in voxel_words(&r) {
        let holds_inner = (p.x - inner_face).abs() < 0.5 * voxel && (p.y - 0.1).abs() < 0.07 && p.z.abs() < 0.07;
        if !holds_inner {
            continue;
        }
        assert_ne!(real, 0, "the wall's voxel at {p} is empty");
        checked += 1;
        outer_kept += (real & 0x8000_0000 == 0) as u32;
    }
    assert!(checked >= 50, "{checked} voxels hold the inner face");
    assert_eq!(outer_kept, 0, "{outer_kept} of {checked} voxels kept a face turned away from the content");
}

/// A level of a volume read back as f32 texels (rgba).
fn volume_level(r: &common::Rendered, texture: &wgpu::Texture, level: u32) -> Vec<[f32; 4]> {
    let bytes = mrshade_gpu::readback::read_volume_level(&r.ctx, texture, level).unwrap();
    let texels: &[[half::f16; 4]] = bytemuck::cast_slice(&bytes);
    texels.iter().map(|t| t.map(|c| c.to_f32())).collect()
}

/// A level of one way of a volume's chain (Volume::chains: both ways side by side along x,
/// towards + first), `side`³ texels indexed (z · side + y) · side + x.
fn chain_way(r: &common::Rendered, chain: &wgpu::Texture, level: u32, towards_low: bool) -> Vec<[f32; 4]> {
    let texels = volume_level(r, chain, level - 1);
    let side = (chain.height() >> (level - 1)).max(1) as usize;
    let offset = if towards_low { side } else { 0 };
    (0..side * side * side).map(|i| texels[(i / side) * 2 * side + offset + i % side]).collect()
}

#[test]
fn a_wall_one_voxel_thick_stays_opaque_along_its_normal_at_every_level() {
    // A real floor, one voxel thick in the volume: the chains seen along its normal (±y) keep
    // it opaque at every level, the chains seen edge-on (±x, ±z) thin it by half a level (one
    // mean of the three axes made it half as opaque per level: wide cones saw the probe
    // through the cornell walls).
    let mut s = Setup::top_down(16);
    s.plane(2.0, 0.0, 0.8, true).cube([0.0, 0.1, 0.0], 0.1, false);
    dvct(&mut s, 32);
    let r = s.render();
    let method = dvct_method(&r);
    let res = method.params().info.x;
    for level in 1..mrshade_render::methods::dvct::levels(res) {
        let side = (res >> level) as usize;
        for towards_low in [false, true] {
            // Per axis chain, the most opaque cell of the column through the volume's centre.
            let max_alpha: Vec<f32> = method
                .volumes()
                .r
                .chains
                .iter()
                .map(|chain| {
                    let texels = chain_way(&r, chain, level, towards_low);
                    let centre = side / 2;
                    (0..side).map(|y| texels[(centre * side + y) * side + centre][3]).fold(0.0, f32::max)
                })
                .collect();
            assert!(max_alpha[1] > 0.99, "level {level}: the floor seen along y has opacity {}", max_alpha[1]);
            for a in [0, 2] {
                assert!(max_alpha[a] < 0.6, "level {level}: the floor seen edge-on has opacity {}", max_alpha[a]);
            }
        }
    }
}

/// The voxels' normals of a render (VoxelNormals), decoded as mips.wgsl reads them.
fn voxel_normals(r: &common::Rendered, texture: &wgpu::Texture) -> Vec<Vec3> {
    let bytes = mrshade_gpu::readback::read_volume_level(&r.ctx, texture, 0).unwrap();
    let snorm = |b: u8| (b as i8 as f32 / 127.0).max(-1.0);
    bytes.chunks_exact(4).map(|t| Vec3::new(snorm(t[0]), snorm(t[1]), snorm(t[2]))).collect()
}

#[test]
fn a_lit_floor_shows_its_light_to_cones_from_above_not_from_below() {
    // The coarse levels hold each voxel's light as the cones travelling along their chain
    // see it: the sunlit real floor's from above (the y chain's way towards −), none from
    // below (towards +), through the floor. Isotropic voxels showed the lit top of a block to
    // the floor beside it, and a lit face behind a dim one to the floor in front.
    let mut s = Setup::sun_over_floor();
    s.cube([0.0, 0.1, 0.0], 0.1, false);
    dvct(&mut s, 32);
    let r = s.render();
    let method = dvct_method(&r);
    let chain_y = &method.volumes().r.chains[1];
    for level in 1..mrshade_render::methods::dvct::levels(method.params().info.x) {
        let brightest = |towards_low| {
            let texels = chain_way(&r, chain_y, level, towards_low);
            texels.iter().map(|t| t[0].max(t[1]).max(t[2])).fold(0.0, f32::max)
        };
        let (from_above, from_below) = (brightest(true), brightest(false));
        assert!(from_above > 1e-3, "level {level}: the floor seen from above is dark ({from_above})");
        assert!(from_below <= 1e-3 * from_above, "level {level}: the floor seen from below shows {from_below}");
    }
}

/// mips.wgsl's parent on the CPU: along `axis`, each pair of children composited front to
/// back as a cone travelling towards + meets them (towards −, the high one in front, when
/// `towards_low`), the four columns averaged.
fn parent_along(children: [[f32; 4]; 8], axis: usize, towards_low: bool) -> [f32; 4] {
    let over = |f: [f32; 4], b: [f32; 4]| std::array::from_fn::<f32, 4, _>(|c| f[c] + (1.0 - f[3]) * b[c]);
    let bit = 1 << axis;
    let mut sum = [0.0; 4];
    for k in (0..8).filter(|k| k & bit == 0) {
        let (low, high) = (children[k], children[k | bit]);
        let p = if towards_low { over(high, low) } else { over(low, high) };
        (0..4).for_each(|c| sum[c] += 0.25 * p[c]);
    }
    sum
}

#[test]
fn every_level_of_the_anisotropic_chains_is_its_finer_levels_parents() {
    // Each level read back must be the CPU's parents of the finer one read back, to the
    // volumes' half-float precision, down to the last 1³, for both ways of each axis: the
    // first from the voxels (read once for the three chains of a way, as the cones
    // travelling that way see them: mips.wgsl `cs_base`, `facing`), the others from their own
    // chain.
    let mut s = Setup::top_down(16);
    s.plane(2.0, 0.0, 0.8, true).cube([0.05, 0.1, -0.03], 0.1, false).cube([-0.12, 0.05, 0.1], 0.05, true);
    dvct(&mut s, 32);
    let r = s.render();
    let method = dvct_method(&r);
    let res = method.params().info.x as usize;
    let volumes = method.volumes();
    for (volume, normals) in [&volumes.rv, &volumes.r].into_iter().zip(&method.normals().textures) {
        let base = volume_level(&r, &volume.base, 0);
        let normals = voxel_normals(&r, normals);
        let mut lit = 0;
        for (axis, chain) in volume.chains.iter().enumerate() {
            for towards_low in [false, true] {
                // The first level sees each voxel's light as its cones do.
                let e = Vec3::AXES[axis] * if towards_low { -1.0 } else { 1.0 };
                let seen = |(t, n): (&[f32; 4], &Vec3)| {
                    let f = (1.0 - 2.0 * n.dot(e)).clamp(0.0, 1.0);
                    [t[0] * f, t[1] * f, t[2] * f, t[3]]
                };
                let mut finer: Vec<[f32; 4]> = base.iter().zip(&normals).map(seen).collect();
                for level in 1..mrshade_render::methods::dvct::levels(res as u32) {
                    let side = res >> level;
                    let gpu = chain_way(&r, chain, level, towards_low);
                    for (i, texel) in gpu.iter().enumerate() {
                        let id = [i % side, (i / side) % side, i / (side * side)];
                        let children = std::array::from_fn(|k| {
                            let c = [0, 1, 2].map(|a| 2 * id[a] + ((k >> a) & 1));
                            finer[(c[2] * 2 * side + c[1]) * 2 * side + c[0]]
                        });
                        let want = parent_along(children, axis, towards_low);
                        for c in 0..4 {
                            let tolerance = 2e-3 * want[c].abs() + 1e-4;
                            assert!(
                                (texel[c] - want[c]).abs() <= tolerance,
                                "level {level} axis {axis} towards − {towards_low} texel {id:?}: {texel:?}, \
                                 the CPU's {want:?}"
                            );
                        }
                        lit += (want[3] > 0.0) as usize;
                    }
                    finer = gpu;
                }
            }
        }
        assert!(lit > 20, "the chains hold almost nothing ({lit} texels)");
    }
}

#[test]
fn real_voxels_the_camera_sees_take_the_photos_light_and_hidden_ones_their_own() {
    // A real floor under a virtual cube, seen from above, with a photo of one colour: the floor's
    // voxels the camera sees hold the photo's radiance in the real-only volume (photo / exposure,
    // spec §2.11's (T_μ² + T_μ)·L_e ≈ B); those under the cube, which the camera does not see,
    // keep their own light (the lamp's, far from the photo's colour); a stream's next photo is
    // in them after its frame (the photo pass alone); with `dvct.photo_voxels = false` every
    // voxel keeps its own.
    let photo_a = [200, 150, 100];
    let photo_b = [60, 120, 220];
    let floor_voxels = |photo_voxels: bool, next_photo: Option<[u8; 3]>| {
        let mut s = Setup::top_down(32);
        s.photo = Box::new(move |_, _| photo_a);
        s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.1, 0.0], 0.1, false);
        s.light(serde_json::json!({"type": "point", "intensity": 0.3}), [0.25, 0.6, 0.0], true);
        dvct(&mut s, 32);
        s.extra_toml += &format!("photo_voxels = {photo_voxels}\n");
        let mut r = s.render();
        if let Some(rgb) = next_photo {
            r.render_with_photo(&|_, _| rgb);
        }
        let method = dvct_method(&r);
        let params = method.params();
        let (origin, voxel, res) = (params.origin.truncate(), params.origin.w, params.info.x);
        let bytes = mrshade_gpu::readback::read_volume_level(&r.ctx, &method.volumes().r.base, 0).unwrap();
        let texels: &[[half::f16; 4]] = bytemuck::cast_slice(&bytes);
        // (seen, hidden): the floor's occupied voxels beside the cube's silhouette as the camera
        // sees it (at 1 m, the cube's top hides the floor out to 0.125 m), and under it.
        let (mut seen, mut hidden) = (Vec::new(), Vec::new());
        for i in 0..res * res * res {
            let v = UVec3::new(i % res, (i / res) % res, i / (res * res));
            let p = origin + (v.as_vec3() + 0.5) * voxel;
            let t = texels[i as usize].map(|c| c.to_f32());
            if p.y.abs() > voxel || t[3] < 0.5 {
                continue;
            }
            let reach = p.x.abs().max(p.z.abs());
            if reach > 0.15 {
                seen.push(Vec3::new(t[0], t[1], t[2]));
            } else if reach < 0.08 {
                hidden.push(Vec3::new(t[0], t[1], t[2]));
            }
        }
        assert!(seen.len() > 100 && hidden.len() > 50, "{} seen, {} hidden floor voxels", seen.len(), hidden.len());
        (seen, hidden)
    };
    let linear = |rgb: [u8; 3]| Vec3::from(rgb.map(|c| mrshade_core::color::srgb_to_linear(c as f32 / 255.0)));
    let holds = |voxels: &[Vec3], photo: Vec3| {
        for l in voxels {
            assert!(
                (*l - photo).abs().max_element() < 2e-3 * photo.max_element(),
                "a seen voxel holds {l}, the photo {photo}"
            );
        }
    };
    let (seen, hidden) = floor_voxels(true, None);
    holds(&seen, linear(photo_a));
    let mean_hidden = hidden.iter().sum::<Vec3>() / hidden.len() as f32;
    // The lamp's light on a grey floor is grey: nothing like the photo's orange.
    assert!((mean_hidden.x - mean_hidden.z).abs() < 0.05 * mean_hidden.x, "hidden voxels hold {mean_hidden}");
    let (seen, _) = floor_voxels(true, Some(photo_b));
    holds(&seen, linear(photo_b));
    let (own, _) = floor_voxels(false, None);
    let mean_own = own.iter().sum::<Vec3>() / own.len() as f32;
    assert!((mean_own.x - mean_own.z).abs() < 0.05 * mean_own.x, "without the photo the voxels hold {mean_own}");
}

#[test]
fn a_real_surface_sends_its_light_from_its_front_and_a_double_sided_one_towards_the_content() {
    // A real floor quad under a virtual cube, turned over (its front faces down, its back the
    // cube). Single-sided (glTF culls its back: the inside of a closed object, the face of a
    // box that looks away from the content), its voxels send out their light from its front;
    // double-sided, from the side that faces the content (voxel_surface.wgsl `sending_side`).
    // Every real surface was turned towards the content before: a real box's faces that look
    // away from it shone into the box.
    let sending_side = |double_sided: bool| {
        let mut s = Setup::top_down(16);
        let mut material = mrshade_testkit::gltf::lambert("floor", [0.5; 3]);
        material["doubleSided"] = serde_json::json!(double_sided);
        let material = s.gltf.material(material);
        let mesh = s.gltf.mesh(&mrshade_testkit::gltf::quad(1.0), Some(material), true);
        let over = mrshade_testkit::gltf::quat([1.0, 0.0, 0.0], std::f32::consts::PI);
        s.gltf.node(serde_json::json!({"name": "floor", "mesh": mesh, "rotation": over, "extras": {"real": true}}));
        s.cube([0.0, 0.1, 0.0], 0.1, false);
        s.light(serde_json::json!({"type": "point", "intensity": 0.3}), [0.1, 0.6, 0.0], true);
        dvct(&mut s, 32);
        let r = s.render();
        let method = dvct_method(&r);
        let normals = voxel_normals(&r, &method.normals().textures[1]);
        let (sum, count) = voxel_words(&r)
            .iter()
            .zip(&normals)
            .filter(|((_, real, _), _)| *real != 0)
            .fold((Vec3::ZERO, 0), |(s, n), (_, normal)| (s + *normal, n + 1));
        assert!(count > 100, "{count} real voxels");
        sum / count as f32
    };
    let (single, double) = (sending_side(false), sending_side(true));
    assert!(single.y < -0.9, "a single-sided floor facing down sends its light {single:?}");
    assert!(double.y > 0.9, "a double-sided one sends it {double:?}, towards the cube above");
}

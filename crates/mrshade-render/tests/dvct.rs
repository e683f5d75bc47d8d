//! Known answers of the `dvct` method's passes (Franke §2.13) on the test GPU.

mod common;

use common::Setup;
use glam::{UVec3, Vec3};
use mrshade_core::Differential;
use mrshade_render::methods::dvct::DvctMethod;

fn dvct(s: &mut Setup, resolution: u32) {
    s.top_toml = "method = \"dvct\"\n".into();
    s.extra_toml += &format!("[dvct]\nresolution = {resolution}\n");
}

/// The `dvct` method of a render.
fn dvct_method(r: &common::Rendered) -> &DvctMethod {
    r.renderer.method_as::<DvctMethod>().expect("the dvct method")
}

/// The probe's visibility per pixel of a `dvct` render (its AOVs), both solutions.
fn probe_visibility(r: &common::Rendered) -> Differential<Vec<[f32; 3]>> {
    dvct_method(r).indirect.read_probe_visibility(&r.ctx).unwrap()
}

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

#[test]
fn a_virtual_cube_shadows_the_probe_near_it_and_changes_nothing_far_away() {
    let mut s = Setup::top_down(48);
    s.probe = Some([0.8, 0.8, 0.8]);
    s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.1, 0.0], 0.1, false);
    s.light(serde_json::json!({"type": "point", "intensity": 0.3}), [0.25, 0.6, 0.0], true);
    dvct(&mut s, 32);
    let r = s.render();
    // Beside the cube (x ≈ −0.22 m, 0.12 m from its face) the cube hides part of the sky,
    // farther (x ≈ −0.35 m) less of it.
    let ratio = |x| r.l_rv(x, 24).x / r.l_r(x, 24).x;
    let (beside, farther) = (ratio(14), ratio(8));
    assert!(beside < 0.98 && beside < farther && farther < 1.0, "L_rv / L_r {beside} beside, {farther} farther");
    // Far outside the volume (a corner of the image, 0.5 m away): identical solutions.
    assert_eq!(r.l_rv(0, 0), r.l_r(0, 0));
}

#[test]
fn a_lit_floor_does_not_light_itself() {
    // In the real-only volume a lit floor is the only surface, and a plane reflects no light
    // onto itself: the cones of its pixels inside the volume, kept off its voxels
    // (cones.wgsl), gather nothing (wide cones at coarse levels gathered the floor's own
    // light before, up to a fifth of its direct light).
    use mrshade_render::outputs::AovImage;
    let mut s = Setup::top_down(48);
    s.plane(2.0, 0.0, 0.8, true).cube([0.0, 0.1, 0.0], 0.1, false);
    s.light(serde_json::json!({"type": "point", "intensity": 0.3}), [0.25, 0.6, 0.0], true);
    dvct(&mut s, 32);
    let r = s.render();
    let aovs = r.renderer.read_aovs(&r.ctx).unwrap();
    let linear = |name: &str| match aovs.iter().find(|a| a.name == name).map(|a| &a.image) {
        Some(AovImage::Linear(image)) => image.clone(),
        _ => panic!("no {name} AOV"),
    };
    let (indirect_r, indirect_rv) = (linear("indirect_r"), linear("indirect_rv"));
    // The volume: twice the cube's edge around it (x, z within ±0.2 m), a cell inside it.
    let mut inside = 0;
    for y in 0..48 {
        for x in 0..48 {
            let p = r.world_on_plane(x, y, 0.0);
            if p.x.abs().max(p.z.abs()) > 0.18 {
                continue;
            }
            let e = indirect_r.pixels[(y * 48 + x) as usize];
            assert!(e.iter().all(|&c| c.abs() < 1e-6), "({x}, {y}): the floor lights itself: {e:?}");
            inside += 1;
        }
    }
    assert!(inside > 100, "{inside} floor pixels in the volume");
    // The real+virtual solution does get the cube's bounce there.
    assert!(indirect_rv.pixels.iter().any(|p| p[0] > 1e-4), "no bounce from the cube");
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

/// Cosine-weighted fraction of the hemisphere above the floor point `p` that the
/// axis-aligned cube at `c` of half side `h` leaves open (a 64 × 64 stratified grid).
fn sky_left_by_cube(p: Vec3, c: Vec3, h: f32) -> f32 {
    let n = 64;
    let mut open = 0;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let (r, phi) = (u.sqrt(), std::f32::consts::TAU * v);
            let d = Vec3::new(r * phi.cos(), (1.0 - u).sqrt(), r * phi.sin());
            let (t0, t1) = ((c - Vec3::splat(h) - p) / d, (c + Vec3::splat(h) - p) / d);
            let (near, far) = (t0.min(t1).max_element(), t0.max(t1).min_element());
            open += (far < near.max(0.0)) as u32;
        }
    }
    open as f32 / (n * n) as f32
}

#[test]
fn the_probe_light_a_cube_leaves_on_the_floor_beside_it_matches_ray_casting() {
    // Under a uniform probe, the share of a real floor's probe light that its cones let through
    // beside a virtual cube (the probe_visibility AOVs) is the share of its sky that the cube
    // leaves open. Wide cones whose samples' opacities compound hid the cube's share several
    // times over (its side fills the same part of a cone sample after sample). Samples two and
    // three times as far apart (`dvct.sample_spacing`; 1.5 is the second bounce's), each
    // compounding its opacity over the length it stands for, must hide the same share.
    for spacing in [0.5, 1.0, 1.5] {
        let mut s = Setup::top_down(48);
        s.probe = Some([0.8, 0.8, 0.8]);
        let (centre, half) = (Vec3::new(0.0, 0.1, 0.0), 0.1);
        s.plane(2.0, 0.0, 0.5, true).cube(centre.to_array(), half, false);
        dvct(&mut s, 32);
        s.extra_toml += &format!("sample_spacing = {spacing}\n");
        let r = s.render();
        let visibility = probe_visibility(&r);
        let (mut error, mut count) = (0.0, 0);
        for x in 0..48 {
            let p = r.world_on_plane(x, 24, 0.0);
            // Beside the cube, inside the volume (±0.2 m).
            if p.x.abs() < half + 0.02 || p.x.abs() > 0.18 {
                continue;
            }
            let i = (24 * 48 + x) as usize;
            assert!(visibility.r[i][0] > 0.999, "the floor alone hides none of its own sky");
            let rendered = visibility.rv[i][0];
            let cast = sky_left_by_cube(p, centre, half);
            eprintln!("spacing {spacing}, x {:.3}: rendered {rendered:.3}, ray cast {cast:.3}", p.x);
            error += (rendered - cast).abs();
            count += 1;
        }
        assert!(count >= 6, "{count} pixels beside the cube");
        let mean = error / count as f32;
        assert!(mean < 0.06, "spacing {spacing}: the probe visibility is {mean:.3} away from ray casting on average");
    }
}

#[test]
fn real_surfaces_beyond_the_volume_hide_the_probe_through_the_outer_volume() {
    // A real box just outside the volume around a small virtual cube (twice its size), inside
    // the outer one (four times that): the floor beside the virtual cube loses the sky that the
    // real box hides, as ray casting says; with the thesis's single volume it lost none.
    let visibility_beside = |outer_scale: f32| {
        let mut s = Setup::top_down(48);
        s.probe = Some([0.8, 0.8, 0.8]);
        s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.05, 0.0], 0.05, false).cube([0.25, 0.1, 0.0], 0.1, true);
        dvct(&mut s, 32);
        // Every pixel traced: a block's light is not shared with the pixels beyond the inner
        // volume, whose cones see the inner volume only. The cones alone shadow the probe
        // (its lights' maps would take over where they cover the floor).
        s.extra_toml += &format!("outer_scale = {outer_scale}\ntrace_block = 1\nprobe_lights = 0\n");
        let r = s.render();
        let visibility = probe_visibility(&r);
        // The floor pixel nearest x = 0.08 m on the middle row: inside the inner volume (±0.1 m).
        let x = (0..48).min_by_key(|&x| ((r.world_on_plane(x, 24, 0.0).x - 0.08).abs() * 1e4) as u32).unwrap();
        let p = r.world_on_plane(x, 24, 0.0);
        (visibility.r[(24 * 48 + x) as usize][0], sky_left_by_cube(p, Vec3::new(0.25, 0.1, 0.0), 0.1))
    };
    let (outer, cast) = visibility_beside(4.0);
    eprintln!("beside the real box: {outer:.3} of the sky left, ray casting {cast:.3}");
    assert!((outer - cast).abs() < 0.1, "the real box leaves {outer:.3} of the sky, ray casting {cast:.3}");
    let (single, _) = visibility_beside(1.0);
    assert!(single > 0.99, "with one volume the real box beyond it hides nothing: {single:.3}");
}

#[test]
fn cones_traced_once_per_block_give_each_pixel_its_own_surfaces_light() {
    // A cube on a floor under a lamp and the probe, traced per pixel and once per block: each
    // pixel takes the blocks' light of its own surface only (nothing across the cube's edges)
    // under its own material, so they agree closely everywhere. What differs follows the
    // seams of the 32³ voxels, which single pixels show and blocks average (up to an eighth of
    // the brightest indirect light with blocks 3.2 cm wide: 2 × 2 pixels of a 64² image, 4 × 4
    // of a 128² one; cones that start one voxel off the surface see its seams more sharply
    // than the two voxels they started at before, 0.114 → 0.127 at the 99th percentile). The
    // cones turn by trace texel (cones.wgsl `cone_turn`), pixel by pixel when traced per pixel:
    // that interleaving differs between the two by design (visibility mean 0.009 → 0.011, 99th
    // percentile 0.047 → 0.051; light mean 0.026 → 0.029 at 4 × 4).
    let render = |size: u32, block: u32| {
        let mut s = Setup::top_down(size);
        s.probe = Some([0.8, 0.8, 0.8]);
        s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.1, 0.0], 0.1, false);
        s.light(serde_json::json!({"type": "point", "intensity": 0.3}), [0.25, 0.6, 0.0], true);
        dvct(&mut s, 32);
        s.extra_toml += &format!("trace_block = {block}\n");
        let r = s.render();
        let method = dvct_method(&r);
        let light = method.indirect.read_light(&r.ctx).unwrap().rv;
        let visibility = probe_visibility(&r).rv;
        (light, visibility)
    };
    for (size, block) in [(64, 2), (128, 4)] {
        let (full_light, full_vis) = render(size, 1);
        let light_scale = full_light.pixels.iter().map(|p| p[0]).fold(0.0, f32::max);
        let (block_light, block_vis) = render(size, block);
        let mut vis_errors: Vec<f32> = full_vis.iter().zip(&block_vis).map(|(a, b)| (a[0] - b[0]).abs()).collect();
        let mut light_errors: Vec<f32> =
            full_light.pixels.iter().zip(&block_light.pixels).map(|(a, b)| (a[0] - b[0]).abs() / light_scale).collect();
        for errors in [&mut vis_errors, &mut light_errors] {
            errors.sort_by(f32::total_cmp);
        }
        let stats = |e: &[f32]| (e.iter().sum::<f32>() / e.len() as f32, e[e.len() * 99 / 100], e[e.len() - 1]);
        let (vis, light) = (stats(&vis_errors), stats(&light_errors));
        eprintln!(
            "{block} × {block}: probe visibility: mean, 99th percentile, max |Δ| {vis:.3?}; indirect light {light:.3?}"
        );
        assert!(vis.0 < 0.015 && vis.1 < 0.06, "{block} × {block}: probe visibility: {vis:?}");
        assert!(
            light.0 < 0.035 && light.1 < 0.14,
            "{block} × {block}: indirect light (share of its largest value): {light:?}"
        );
    }
}

#[test]
fn a_sun_in_the_probe_casts_the_real_scenes_sharp_shadow_through_the_maps() {
    // A dim sky with a small bright sun 45° up toward −z, a real cube on a real floor, a virtual
    // cube beside it (the volume and the maps lie around it): the floor in the real cube's sun
    // shadow keeps only the sky's share of the probe, the floor beyond it nearly all. The
    // nine 60° cones alone (`probe_lights = 0`) blur the sun's shadow away.
    let floor_visibility = |probe_lights: u32| {
        let mut s = Setup::sun_over_floor();
        s.cube([0.0, 0.05, -0.1], 0.05, true).cube([0.1, 0.04, 0.05], 0.04, false);
        dvct(&mut s, 32);
        s.extra_toml += &format!("probe_lights = {probe_lights}\ntrace_block = 1\n");
        let r = s.render();
        let visibility = probe_visibility(&r);
        let at = |target: Vec3| visibility.r[r.floor_pixel(target)][0];
        // The shadow reaches from z = −0.05 to +0.05 (the cube is 0.1 high).
        (at(Vec3::new(0.03, 0.0, 0.0)), at(Vec3::new(0.03, 0.0, 0.1)))
    };
    let (shadow, lit) = floor_visibility(32);
    eprintln!("maps: in the sun shadow {shadow:.3}, beyond it {lit:.3}");
    assert!(shadow < 0.15 && lit > 0.8, "in the shadow {shadow:.3}, beyond it {lit:.3}");
    let (cones_shadow, _) = floor_visibility(0);
    eprintln!("cones alone: in the sun shadow {cones_shadow:.3}");
    assert!(cones_shadow > shadow + 0.2, "the cones alone keep the shadow: {cones_shadow:.3}");
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
            let (w, h) = (r.session.output.width, r.session.output.height);
            let texels: Vec<u8> = (0..w * h).flat_map(|_| rgb).collect();
            let packed = mrshade_render::passes::upload::PackedPhoto::from_srgb8(&texels, (w, h));
            let inputs = mrshade_render::FrameInputs {
                photo: Some(&packed),
                ..mrshade_render::FrameInputs::camera(r.renderer.session_camera())
            };
            let mut profiler = mrshade_gpu::timing::profiler(&r.ctx, false).unwrap();
            r.renderer.render_untimed(&r.ctx, &mut profiler, &inputs).unwrap();
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
fn a_sun_in_the_probe_casts_the_virtual_objects_sharp_shadow_on_the_real_floor_through_the_maps() {
    // The same sun over a real floor, the cube now virtual: the floor in its sun shadow keeps
    // only the sky's share of the probe in L_rv (the answer's sharp shadow; the nine cones alone
    // leave a faint one), the floor beyond it nearly all.
    let floor_visibility = |probe_lights: u32| {
        let mut s = Setup::sun_over_floor();
        s.cube([0.0, 0.05, -0.1], 0.05, false);
        dvct(&mut s, 32);
        s.extra_toml += &format!("extent = 4.0\nprobe_lights = {probe_lights}\ntrace_block = 1\n");
        let r = s.render();
        let visibility = probe_visibility(&r);
        let at = |target: Vec3| {
            let i = r.floor_pixel(target);
            (visibility.rv[i][0], visibility.r[i][0])
        };
        (at(Vec3::new(0.03, 0.0, 0.0)), at(Vec3::new(0.03, 0.0, 0.09)))
    };
    let ((shadow_rv, shadow_r), (lit_rv, _)) = floor_visibility(32);
    eprintln!("maps: in the sun shadow {shadow_rv:.3} (real-only {shadow_r:.3}), beyond it {lit_rv:.3}");
    assert!(shadow_r > 0.8, "nothing real shadows the floor: {shadow_r:.3}");
    assert!(shadow_rv < 0.2 && lit_rv > 0.8, "in the shadow {shadow_rv:.3}, beyond it {lit_rv:.3}");
    let ((cones_shadow, _), _) = floor_visibility(0);
    eprintln!("cones alone: in the sun shadow {cones_shadow:.3}");
    assert!(cones_shadow > shadow_rv + 0.2, "the cones alone keep the shadow: {cones_shadow:.3}");
}

#[test]
fn a_small_balls_bounce_onto_the_floor_around_it_matches_the_path_tracer() {
    // A white virtual ball (5 cm) on a real grey floor, lit by a real lamp to its −x side, no
    // probe, no photo: the light it reflects onto the floor around it on the lamp's side and
    // beside it, 3–15 cm from its surface, against the reference path tracer. A cone passing
    // the ball meets it sample after sample in the same part of the cone; compositing those
    // samples as independent layers counted its light 1.5 times here (2–3 times farther out,
    // 7–15 cm from it: cones.wgsl `cone_seen`).
    let mut s = Setup::top_down(64);
    // 35 cm above the floor: 7 mm pixels.
    s.gltf.patch_node(0, |n| n["translation"] = serde_json::json!([0.0, 0.35, 0.0]));
    s.plane(2.0, 0.0, 0.5, true);
    let white = s.gltf.material(mrshade_testkit::gltf::lambert("ball", [0.8; 3]));
    let ball = s.gltf.mesh(&mrshade_testkit::gltf::sphere(0.05, 24), Some(white), true);
    s.gltf.node(
        serde_json::json!({"name": "ball", "mesh": ball, "translation": [0.0, 0.05, 0.0], "extras": {"real": false}}),
    );
    s.light(serde_json::json!({"type": "point", "intensity": 0.25}), [-0.15, 0.35, 0.0], true);
    dvct(&mut s, 128);
    s.extra_toml += "photo_voxels = false\n[reference]\nspp = 128\n";
    let r = s.render();
    let caustics = mrshade_reference::CausticSettings { photons_per_light: Some(0) };
    let reference = mrshade_reference::render_with(&r.session, None, &caustics, &|_, _| {});
    let (mut ours, mut theirs) = (0.0, 0.0);
    for y in 0..64 {
        for x in 0..64 {
            let p = r.world_on_plane(x, y, 0.0);
            let d = (p.x * p.x + p.z * p.z).sqrt();
            // Around the ball out of its shadow (the lamp is at −x).
            if !(0.08..0.2).contains(&d) || p.x > 0.0 {
                continue;
            }
            ours += r.l_rv(x, y).x - r.l_r(x, y).x;
            theirs += reference.l_rv.get(x, y)[0] - reference.l_r.get(x, y)[0];
        }
    }
    eprintln!("the ball's light on the floor around it: ours {ours:.4}, the path tracer's {theirs:.4}");
    assert!(theirs > 0.0, "the reference sees the ball's light: {theirs}");
    let ratio = ours / theirs;
    // Independent layers: 1.49 here; the mean of the two bounds 1.23.
    assert!((0.7..1.35).contains(&ratio), "the ball sends {ratio:.2} times the path tracer's light onto the floor");
}

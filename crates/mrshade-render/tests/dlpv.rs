//! Known answers of the `dlpv` method's passes (Franke §2.12): a propagation step conserves
//! flux in free space and moves it along its lobe; injection into the cell a VPL lies in
//! (the thesis's) and trilinear injection put the same light at the same place; the probe's
//! shadows through its lights' maps. The gathered volumes' known answers: dlpv_gather.rs.

mod common;

use bytemuck::cast_slice;
use common::Setup;
use glam::Vec3;
use glam::{UVec4, Vec4};
use mrshade_gpu::{bind, readback::read_buffer};
use mrshade_render::Renderer;
use mrshade_render::methods::dlpv::{
    DlpvMethod, DlpvParams, PROPAGATE_SHADER, SCRATCH_CELL_BYTES, propagate_layout, sum_updates,
};
use serde_json::json;
use wgpu::util::DeviceExt;

const RES: u32 = 8;
const CELLS: u32 = RES * RES * RES;
const SCALE: f32 = 1_048_576.0;

/// Seeds cell `at` with the red-channel coefficients `c` (source 1, the indirect change),
/// runs `n` propagation steps as the method does (the sums added to by every second dispatch
/// and the last, `sum_updates`), and returns (after seeding, after each step, the sums after
/// the last), red channel per cell.
fn propagate(at: [u32; 3], c: [f32; 4], n: u32) -> (Vec<Vec4>, Vec<Vec<Vec4>>, Vec<Vec4>) {
    let ctx = mrshade_testkit::gpu();
    let device = &ctx.device;
    let params = |step: u32| DlpvParams {
        origin: Vec4::new(0.0, 0.0, 0.0, 0.1),
        info: UVec4::new(RES, CELLS, step, 0),
        scale: Vec4::new(SCALE, 0.0, 0.0, 0.0),
        steps: UVec4::new(n, n, 0, n),
        gathered: UVec4::ZERO,
    };
    let mut injected = vec![0i32; (4 * 3 * CELLS * 4) as usize];
    let cell = (at[2] * RES + at[1]) * RES + at[0];
    for (k, v) in c.iter().enumerate() {
        injected[((3 * CELLS + cell) * 4) as usize + k] = (v * SCALE).round() as i32;
    }
    let init = |label: &str, bytes: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
    };
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let injected = init("test/injected", cast_slice(&injected), storage);
    // Four sources' volumes per scratch buffer, three accumulated volumes per sum buffer.
    let scratch =
        ["test/a", "test/b"].map(|l| init(l, &vec![0u8; (4 * CELLS as u64 * SCRATCH_CELL_BYTES) as usize], storage));
    let sums = ["test/sum_0", "test/sum_1"].map(|l| init(l, &vec![0u8; (3 * CELLS * 48) as usize], storage));
    let layout = propagate_layout(device);
    let pipeline =
        |entry| mrshade_gpu::shader::compute_pipeline_entry(device, entry, PROPAGATE_SHADER, entry, &[&layout]);
    let updates = sum_updates(n);
    // Source 1's red channel (after source 0's three channels) after each dispatch.
    let copies: Vec<wgpu::Buffer> = (0..=n)
        .map(|k| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("test/step{k}")),
                size: CELLS as u64 * 8,
                usage: storage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })
        .collect();
    let mut encoder = device.create_command_encoder(&Default::default());
    for k in 0..=n {
        let params = init("test/params", bytemuck::bytes_of(&params(k)), wgpu::BufferUsages::UNIFORM);
        let (read, write) = (k as usize % 2, 1 - k as usize % 2);
        let sums_read = updates[k as usize] % 2;
        let group = bind::group(
            device,
            "test/group",
            &layout,
            &[
                params.as_entire_binding(),
                injected.as_entire_binding(),
                scratch[read].as_entire_binding(),
                scratch[write].as_entire_binding(),
                sums[sums_read].as_entire_binding(),
                sums[1 - sums_read].as_entire_binding(),
            ],
        );
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline(if k == 0 { "seed" } else { "propagate" }));
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(RES / 4, RES / 4, RES / 4 * 9);
        }
        encoder.copy_buffer_to_buffer(&scratch[write], 3 * CELLS as u64 * 8, &copies[k as usize], 0, CELLS as u64 * 8);
    }
    ctx.queue.submit([encoder.finish()]);
    let vec4s =
        |buffer: &wgpu::Buffer| -> Vec<Vec4> { cast_slice::<u8, Vec4>(&read_buffer(&ctx, buffer).unwrap()).to_vec() };
    // Scratch holds halves in units of 2¹⁶ fixed-point units (propagate.wgsl SCRATCH_UNITS).
    let halves = |buffer: &wgpu::Buffer| -> Vec<Vec4> {
        let h = read_buffer(&ctx, buffer).unwrap();
        let h = cast_slice::<u8, half::f16>(&h);
        h.chunks(4).map(|c| Vec4::from_array([0, 1, 2, 3].map(|i| c[i].to_f32() * (65536.0 / SCALE)))).collect()
    };
    let stepped: Vec<Vec<Vec4>> = copies.iter().map(halves).collect();
    // The red channel of V_Δ (volume 1).
    let n_cells = CELLS as usize;
    let accumulated = vec4s(&sums[updates[n as usize + 1] % 2])[3 * n_cells..4 * n_cells].to_vec();
    (stepped[0].clone(), stepped[1..].to_vec(), accumulated)
}

/// One propagation step of `propagate`: after seeding, after the step, the sums.
fn one_step(at: [u32; 3], c: [f32; 4]) -> (Vec<Vec4>, Vec<Vec4>, Vec<Vec4>) {
    let (seeded, mut stepped, accumulated) = propagate(at, c, 1);
    (seeded, stepped.remove(0), accumulated)
}

fn index(x: u32, y: u32, z: u32) -> usize {
    ((z * RES + y) * RES + x) as usize
}

#[test]
fn a_propagation_step_conserves_flux_in_free_space() {
    // An isotropic cell (only c0) in the middle: its flux ∝ c0 (∫I = c0·Y0·4π) all reaches
    // the six neighbours, equally, and none stays.
    let (seeded, stepped, accumulated) = one_step([4, 4, 4], [1.0, 0.0, 0.0, 0.0]);
    assert!((seeded[index(4, 4, 4)].x - 1.0).abs() < 1e-5);
    // Scratch keeps half floats: each value within 2⁻¹¹ of itself.
    let total: f32 = stepped.iter().map(|c| c.x).sum();
    assert!((total - 1.0).abs() < 5e-4, "flux after one step {total}");
    assert_eq!(stepped[index(4, 4, 4)], Vec4::ZERO);
    let neighbours = [index(5, 4, 4), index(3, 4, 4), index(4, 5, 4), index(4, 3, 4), index(4, 4, 5), index(4, 4, 3)];
    for n in neighbours {
        assert!((stepped[n].x - 1.0 / 6.0).abs() < 1e-4 + 1.0 / 6.0 / 2048.0, "{}", stepped[n].x);
    }
    // Bounce light (source 1) is read from the first step on: the seed is not accumulated.
    assert_eq!(accumulated[index(4, 4, 4)], Vec4::ZERO);
    assert_eq!(accumulated[index(5, 4, 4)], stepped[index(5, 4, 4)]);
}

#[test]
fn a_lobe_propagates_along_its_direction() {
    // A clamped-cosine lobe toward +x (c = (π·Y0, 0, 0, 2π/3·Y1)/π): more flux to +x than
    // to −x (which gets the L1 lobe's negative ringing), the total still kept, and the cell
    // ahead's lobe points on along +x.
    let y0 = mrshade_core::sh::Y0;
    let y1 = mrshade_core::sh::Y1;
    let (_, stepped, _) = one_step([4, 4, 4], [y0, 0.0, 0.0, 2.0 / 3.0 * y1]);
    let total: f32 = stepped.iter().map(|c| c.x).sum();
    assert!((total - y0).abs() < 5e-4 * y0.max(1.0), "{total}");
    let ahead = stepped[index(5, 4, 4)];
    let behind = stepped[index(3, 4, 4)];
    assert!(ahead.x > 2.0 * behind.x.abs(), "{ahead} vs {behind}");
    assert!(ahead.w > 0.0, "x coefficient {ahead}");
}

#[test]
fn the_sums_hold_every_step_when_every_second_dispatch_adds_them() {
    // Five steps (odd: the last dispatch adds alone) and four (even): the sums are each
    // step's result added up, the seed's bounce light not among them.
    for n in [4, 5] {
        let (_, stepped, accumulated) = propagate([3, 4, 4], [1.0, 0.2, 0.0, 0.5], n);
        let mut expected = vec![Vec4::ZERO; CELLS as usize];
        for step in &stepped {
            for (e, s) in expected.iter_mut().zip(step) {
                *e += *s;
            }
        }
        let worst = expected.iter().zip(&accumulated).map(|(e, a)| (*e - *a).abs().max_element()).fold(0.0, f32::max);
        assert!(worst < 1e-6, "{n} steps: sums differ by {worst}");
        assert!(expected.iter().map(|e| e.x.abs()).sum::<f32>() > 1.0, "{n} steps: nothing propagated");
    }
}

/// After one frame of a real floor (wholly inside the volume) under a real spot with a virtual
/// cube on it: per source
/// (V_ρ's difference, the indirect change, the direct change, V_μ), the red band-0 light
/// injected (fixed-point units), the number of cells it is in, and its centroid (in cells).
fn injected_red(splat: &str) -> Vec<(f64, usize, Vec3)> {
    let mut s = Setup::top_down(32);
    s.top_toml = "method = \"dlpv\"\n".into();
    // The bounce light propagated: gathered, neither V_μ nor the indirect change is injected.
    s.extra_toml +=
        &format!("[dlpv]\nsplat = \"{splat}\"\nrsm_resolution = 128\nextent = 4.0\nbounce_light = \"propagated\"\n");
    s.plane(0.3, 0.0, 0.6, true).cube([0.05, 0.1, 0.0], 0.1, false).light(
        json!({"type": "spot", "intensity": 3.0, "spot": {"innerConeAngle": 0.4, "outerConeAngle": 0.8}}),
        [0.3, 0.9, 0.1],
        true,
    );
    let (_dir, session) = s.session();
    let ctx = mrshade_testkit::gpu();
    let mut renderer = Renderer::new(&ctx, &session).unwrap();
    renderer.render_frames(&ctx, 1, |_| {}).unwrap();
    let method: &DlpvMethod = renderer.method_as().unwrap();
    let res = method.params().info.x as usize;
    let cells = res * res * res;
    let words = read_buffer(&ctx, &method.injected).unwrap();
    let words = cast_slice::<u8, i32>(&words);
    (0..4)
        .map(|source| {
            let red = &words[source * 3 * cells * 4..][..cells * 4];
            let (mut total, mut count, mut moment) = (0.0f64, 0, Vec3::ZERO);
            for cell in 0..cells {
                let c0 = red[cell * 4] as f64;
                if c0 != 0.0 {
                    let at = Vec3::new((cell % res) as f32, ((cell / res) % res) as f32, (cell / (res * res)) as f32);
                    total += c0;
                    count += 1;
                    moment += (at + 0.5) * c0 as f32;
                }
            }
            (total, count, moment / total.max(1.0) as f32)
        })
        .collect()
}

#[test]
fn injecting_into_a_cell_and_trilinearly_put_the_same_light_at_the_same_place() {
    let cell = injected_red("cell");
    let trilinear = injected_red("trilinear");
    // Each VPL rounds once (cell) or eight times (trilinear): the same light, also where the
    // cube's VPLs and the desk's it hides nearly cancel (the indirect change).
    for (source, name) in [(1, "indirect change"), (3, "V_μ")] {
        let (a, b) = (cell[source].0, trilinear[source].0);
        assert!(b.abs() > 1e4, "{name}: nothing injected ({b})");
        assert!((a - b).abs() <= 1e-3 * b.abs(), "{name}: {a} against {b}");
    }
    // V_μ (all positive) in fewer cells (each VPL in one, not eight) about the same centroid:
    // a VPL's cell centre is on average where the trilinear weights put it.
    let ((_, in_cells, at_a), (_, in_trilinear, at_b)) = (cell[3], trilinear[3]);
    assert!(in_cells < in_trilinear, "{in_cells} cells against {in_trilinear}");
    assert!(at_a.distance(at_b) < 0.25, "centroid {at_a} against {at_b}");
}

#[test]
fn a_sun_in_the_probe_casts_the_virtual_objects_sharp_shadow_through_its_maps() {
    // A dim sky with a small bright sun 45° up toward −z over a real floor, a virtual cube
    // (10 cm) on it, in a volume of 8³ cells of 5 cm (as coarse, for the cube, as 32³ cells are
    // around a large object): with the sun's light shadowing real surfaces through its maps
    // (`sharp_probe_shadows_deg`, 8.4° here) the floor keeps only the sky's share of its
    // light (L_rv/L_r) in the cube's sun shadow and nearly all of it 1 cm beside the shadow;
    // left to the volume's direct change (0, the thesis's), the shadow is blurred over the
    // cells, too light inside and darkening the floor beside it. Either way the cube takes
    // about the same light from the floor in all (no share lost or counted twice).
    let render = |sharp_deg: f32| {
        let mut s = Setup::sun_over_floor();
        s.cube([0.0, 0.05, -0.1], 0.05, false);
        s.top_toml = "method = \"dlpv\"\n".into();
        // Maps of 128² (6 mm texels here; the default 64² draws the shadow's edge a texel wider).
        s.extra_toml += &format!(
            "[dlpv]\nextent = 4.0\nresolution = 8\nprobe_rsm_resolution = 128\nsharp_probe_shadows_deg = {sharp_deg}\n"
        );
        s.render()
    };
    let ratio = |r: &common::Rendered, i: usize| r.radiance.rv.pixels[i][1] / r.radiance.r.pixels[i][1];
    // In the shadow (it ends at z = 0.05), beside it (the cube ends at x = 0.05), beyond it;
    // and the light taken from the floor in all (Σ L_r − L_rv over the floor's pixels).
    let measure = |r: &common::Rendered| {
        let at = |target: Vec3| ratio(r, r.floor_pixel(target));
        let w = r.radiance.rv.width;
        let taken: f32 = (0..r.radiance.rv.pixels.len())
            .filter(|&i| {
                // The floor beside the cube (its footprint and a margin left out).
                let p = r.world_on_plane(i as u32 % w, i as u32 / w, 0.0);
                p.x.abs() > 0.06 || !(-0.16..=-0.04).contains(&p.z)
            })
            .map(|i| r.radiance.r.pixels[i][1] - r.radiance.rv.pixels[i][1])
            .sum();
        ([at(Vec3::new(0.03, 0.0, 0.03)), at(Vec3::new(0.06, 0.0, 0.0)), at(Vec3::new(0.03, 0.0, 0.09))], taken)
    };
    let ([shadow, beside, beyond], taken) = measure(&render(8.4));
    eprintln!("maps: in the sun shadow {shadow:.3}, beside it {beside:.3}, beyond it {beyond:.3}; taken {taken:.3}");
    assert!(shadow < 0.3 && beside > 0.85 && beyond > 0.9, "{shadow:.3} / {beside:.3} / {beyond:.3}");
    let ([volume_shadow, volume_beside, _], volume_taken) = measure(&render(0.0));
    eprintln!(
        "volume alone: in the sun shadow {volume_shadow:.3}, beside it {volume_beside:.3}; taken {volume_taken:.3}"
    );
    assert!(volume_shadow > shadow + 0.2, "the volume's shadow is as dark: {volume_shadow:.3}");
    assert!(volume_beside < beside - 0.15, "the volume's shadow stops as sharply: {volume_beside:.3}");
    let (lo, hi) = (taken.min(volume_taken), taken.max(volume_taken));
    assert!(lo > 0.8 * hi, "the light taken from the floor: maps {taken:.3}, volume {volume_taken:.3}");
}

#[test]
fn a_broad_light_in_the_probe_casts_the_soft_shadow_the_path_tracer_does() {
    // A dim sky with a broad bright patch 34° across, 45° up toward −z, over a real floor, and a
    // virtual 8 cm cube floating 8 cm above it: the floor under the cube's shadow against the
    // path tracer's L_rv / L_r, through the shadow's core and out across its wide penumbra
    // (soft maps 0.26 / 0.06 / 0.14 / 0.52 / 0.76 / 0.86 / 0.96 at z = 6–30 cm, the path
    // tracer 0.31 / 0.09 / 0.13 / 0.51 / 0.72 / 0.87 / 0.96). With `dlpv.soft_probe_shadows`
    // the maps' test is soft by each light's angular radius (shaders/lib/probe_maps_soft.wgsl);
    // hard (the default) it draws each light's shadow edge sharp. Left to the volume's direct
    // change (`sharp_probe_shadows_deg = 0`, the thesis's; before, every light broader than
    // 8.4°), the shadow ends with the volume, twice the cube's size: none of it reaches z = 6 cm.
    let setup = |sharp_deg: f32, soft: bool| {
        let mut s = Setup::sun_over_floor();
        s.gltf.patch_node(0, |n| n["translation"] = json!([0.0, 0.7, 0.0]));
        s.size = (64, 64);
        s.sun = Some([20.0; 3]);
        s.sun_texels = 6;
        s.cube([0.0, 0.12, 0.0], 0.04, false);
        s.top_toml = "method = \"dlpv\"\n".into();
        s.extra_toml += &format!(
            "[dlpv]\nsharp_probe_shadows_deg = {sharp_deg}\nsoft_probe_shadows = {soft}\n[reference]\nspp = 256\n"
        );
        s
    };
    let soft = setup(30.0, true).render();
    let hard = setup(30.0, false).render();
    let volume = setup(0.0, false).render();
    let caustics = mrshade_reference::CausticSettings { photons_per_light: Some(0) };
    let reference = mrshade_reference::render_with(&soft.session, None, &caustics, &|_, _| {});
    let w = soft.radiance.rv.width;
    let ratio = |r: &common::Rendered, x, y| r.l_rv(x, y).y / r.l_r(x, y).y;
    let mut worst = [0.0f32; 3];
    // From the cube's edge (z = 0.04 seen from above) across the shadow.
    for z in [0.06, 0.10, 0.14, 0.18, 0.22, 0.26, 0.30] {
        let i = soft.floor_pixel(Vec3::new(0.0, 0.0, z));
        let (x, y) = (i as u32 % w, i as u32 / w);
        let theirs = reference.l_rv.get(x, y)[1] / reference.l_r.get(x, y)[1];
        let ours = [ratio(&soft, x, y), ratio(&hard, x, y), ratio(&volume, x, y)];
        eprintln!(
            "z {z:.2}: L_rv / L_r soft maps {:.3}, hard maps {:.3}, volume {:.3}, the path tracer's {theirs:.3}",
            ours[0], ours[1], ours[2]
        );
        for (w, o) in worst.iter_mut().zip(ours) {
            *w = w.max((o - theirs).abs());
        }
    }
    let [soft, hard, volume] = worst;
    eprintln!("largest departure: soft maps {soft:.3}, hard maps {hard:.3}, volume {volume:.3}");
    assert!(soft < 0.1, "the soft maps' shadow departs from the path tracer's by {soft:.3}");
    assert!(hard > soft + 0.05, "the hard maps' shadow is as soft: {hard:.3}");
    assert!(volume > 0.5, "the volume's shadow reaches the path tracer's: {volume:.3}");
}

#[test]
fn a_broad_light_in_the_probe_casts_a_real_objects_soft_shadow_on_a_virtual_floor_as_the_path_tracer_does() {
    // The same broad patch of sky, now over a virtual floor with a real 8 cm cube floating 8 cm
    // above it: the virtual floor's light across the cube's shadow, as a share of its light
    // outside it, against the path tracer's. Each of the probe's lights stands for a patch of
    // the probe, and a virtual surface sees them through their maps: soft by each light's
    // angular radius (`dlpv.soft_virtual_probe_shadows`), the shadow follows the
    // path tracer's; hard (the default), each light's edge is drawn sharp (the stripes across cornell's
    // blocks). At z = 6–26 cm soft 0.26 / 0.04 / 0.12 / 0.54 / 0.73 / 0.85, hard 0.30 / 0.01 /
    // 0.01 / 0.58 / 0.72 / 0.91, the path tracer 0.31 / 0.09 / 0.13 / 0.50 / 0.71 / 0.86.
    let setup = |soft: bool| {
        let mut s = Setup::top_down(64);
        s.probe = Some([0.02, 0.02, 0.02]);
        s.sun = Some([20.0; 3]);
        s.sun_texels = 6;
        s.gltf.patch_node(0, |n| n["translation"] = json!([0.0, 0.7, 0.0]));
        s.plane(0.3, 0.0, 0.5, false);
        s.cube([0.0, 0.12, 0.0], 0.04, true);
        s.top_toml = "method = \"dlpv\"\n".into();
        s.extra_toml += &format!(
            "[dlpv]\nprobe_rsm_resolution = 256\nsoft_virtual_probe_shadows = {soft}\n[reference]\nspp = 256\n"
        );
        s
    };
    let soft = setup(true).render();
    let hard = setup(false).render();
    let caustics = mrshade_reference::CausticSettings { photons_per_light: Some(0) };
    let reference = mrshade_reference::render_with(&soft.session, None, &caustics, &|_, _| {});
    let w = soft.radiance.rv.width;
    let at = |z: f32| {
        let i = soft.floor_pixel(Vec3::new(0.0, 0.0, z));
        (i as u32 % w, i as u32 / w)
    };
    let (ox, oy) = at(-0.2);
    let ratio = |r: &common::Rendered, x, y| r.l_rv(x, y).y / r.l_rv(ox, oy).y;
    let mut worst = [0.0f32; 2];
    for z in [0.06, 0.10, 0.14, 0.18, 0.22, 0.26] {
        let (x, y) = at(z);
        let theirs = reference.l_rv.get(x, y)[1] / reference.l_rv.get(ox, oy)[1];
        let ours = [ratio(&soft, x, y), ratio(&hard, x, y)];
        eprintln!(
            "z {z:.2}: L_rv / unshadowed soft {:.3}, hard {:.3}, the path tracer's {theirs:.3}",
            ours[0], ours[1]
        );
        for (w, o) in worst.iter_mut().zip(ours) {
            *w = w.max((o - theirs).abs());
        }
    }
    let [soft, hard] = worst;
    eprintln!("largest departure: soft {soft:.3}, hard {hard:.3}");
    assert!(soft < 0.1, "the soft shadow on the virtual floor departs from the path tracer's by {soft:.3}");
    assert!(hard > soft + 0.05, "the hard shadow is as soft: {hard:.3}");
}

#[test]
fn the_model_of_the_photo_holds_the_real_scenes_shadow_of_the_probe() {
    // The same sun over a real floor, now with a real cube (10 cm) in its light and a small
    // virtual one beside it (for the volume and the maps): the floor in the real cube's sun
    // shadow has lost that light in the photo already, so the model of the photo the α-scaled
    // composite divides by (L_r) must have lost it too, and both solutions alike (the real
    // shadow is no change). Unshadowed, L_r was the same in the shadow as beside it (1.000);
    // shadowed 0.507: the sky and the volume's bounce light from the sunlit floor remain.
    let mut s = Setup::sun_over_floor();
    s.cube([0.0, 0.05, -0.1], 0.05, true);
    s.cube([0.2, 0.03, -0.1], 0.03, false);
    s.top_toml = "method = \"dlpv\"\n".into();
    s.extra_toml += "[dlpv]\nextent = 4.0\nresolution = 8\n";
    let r = s.render();
    let (shadow, beside) = (r.floor_pixel(Vec3::new(0.0, 0.0, 0.03)), r.floor_pixel(Vec3::new(-0.08, 0.0, 0.0)));
    let (l_r, l_rv) = (&r.radiance.r.pixels, &r.radiance.rv.pixels);
    let darker = l_r[shadow][1] / l_r[beside][1];
    let change = l_rv[shadow][1] / l_r[shadow][1];
    eprintln!("L_r in the real cube's sun shadow / beside it {darker:.3}; L_rv / L_r there {change:.3}");
    assert!(darker < 0.65, "the model of the photo keeps the sun in the real shadow: {darker:.3}");
    assert!((change - 1.0).abs() < 0.05, "the real shadow is taken as a change: {change:.3}");
}

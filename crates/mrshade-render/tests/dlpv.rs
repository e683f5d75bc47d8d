//! Known answers of the `dlpv` method's passes (Franke §2.12): a propagation step conserves
//! flux in free space and moves it along its lobe; the split injection cancels where the
//! virtual object changes nothing.

use bytemuck::cast_slice;
use glam::{UVec4, Vec4};
use mrshade_gpu::{bind, readback::read_buffer};
use mrshade_render::methods::dlpv::{
    DlpvParams, PROPAGATE_SHADER, propagate_layout, propagate_workgroups, seed_workgroups,
};
use wgpu::util::DeviceExt;

const RES: u32 = 8;
const CELLS: u32 = RES * RES * RES;
const SCALE: f32 = 1_048_576.0;

/// Seeds cell `at` with the red-channel coefficients `c` (source 1, the indirect change),
/// runs one propagation dispatch per entry (first step, steps of the sources) of
/// `dispatches` (a dispatch takes two steps, one where the step after its first is beyond
/// the steps), and returns (after seeding, after the last dispatch, the sum it writes), red
/// channel per cell.
fn propagated(at: [u32; 3], c: [f32; 4], dispatches: &[(u32, u32)]) -> (Vec<Vec4>, Vec<Vec4>, Vec<Vec4>) {
    let ctx = mrshade_testkit::gpu();
    let device = &ctx.device;
    let params = |step: u32, steps: u32| DlpvParams {
        origin: Vec4::new(0.0, 0.0, 0.0, 0.1),
        info: UVec4::new(RES, CELLS, step, 0),
        scale: Vec4::new(SCALE, 0.0, 0.0, 0.0),
        steps: UVec4::new(steps, steps, 0, steps),
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
    let scratch = ["test/a", "test/b"].map(|l| init(l, &vec![0u8; (4 * CELLS * 48) as usize], storage));
    let sums = ["test/sum_0", "test/sum_1"].map(|l| init(l, &vec![0u8; (3 * CELLS * 48) as usize], storage));
    let layout = propagate_layout(device);
    let pipeline =
        |entry| mrshade_gpu::shader::compute_pipeline_entry(device, entry, PROPAGATE_SHADER, entry, &[&layout]);
    // Dispatch k reads scratch and sums k mod 2 and writes the others, as the method does.
    let group = |k: usize, (step, steps): (u32, u32)| {
        let (read, write) = (k % 2, 1 - k % 2);
        let uniform = init("test/params", bytemuck::bytes_of(&params(step, steps)), wgpu::BufferUsages::UNIFORM);
        bind::group(
            device,
            "test/group",
            &layout,
            &[
                uniform.as_entire_binding(),
                injected.as_entire_binding(),
                scratch[read].as_entire_binding(),
                scratch[write].as_entire_binding(),
                sums[read].as_entire_binding(),
                sums[write].as_entire_binding(),
            ],
        )
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline("seed"));
        pass.set_bind_group(0, &group(0, (0, 0)), &[]);
        let [x, y, z] = seed_workgroups(CELLS);
        pass.dispatch_workgroups(x, y, z);
    }
    let seeded = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test/seeded"),
        size: CELLS as u64 * 48,
        usage: storage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    // Source 1's red channel: the volume after source 0's three channels.
    encoder.copy_buffer_to_buffer(&scratch[1], 3 * CELLS as u64 * 16, &seeded, 0, CELLS as u64 * 48);
    for (k, &dispatch) in dispatches.iter().enumerate() {
        // Separate passes: each dispatch sees the last one's writes, on every GPU.
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline("propagate"));
        pass.set_bind_group(0, &group(k + 1, dispatch), &[]);
        let [x, y, z] = propagate_workgroups(RES);
        pass.dispatch_workgroups(x, y, z);
    }
    ctx.queue.submit([encoder.finish()]);
    // Red channel of volume `k` (source 1 in the scratch buffers, V_Δ = 1 in the sums).
    let red = |buffer: &wgpu::Buffer, k: usize| -> Vec<Vec4> {
        let bytes = read_buffer(&ctx, buffer).unwrap();
        let n = CELLS as usize;
        cast_slice::<u8, Vec4>(&bytes)[3 * k * n..(3 * k + 1) * n].to_vec()
    };
    // The last dispatch, k = dispatches.len(), wrote scratch and sums 1 − k mod 2.
    let last = 1 - dispatches.len() % 2;
    (red(&seeded, 0), red(&scratch[last], 1), red(&sums[last], 1))
}

/// One propagation step (a dispatch whose second step is beyond the steps).
fn one_step(at: [u32; 3], c: [f32; 4]) -> (Vec<Vec4>, Vec<Vec4>, Vec<Vec4>) {
    propagated(at, c, &[(1, 1)])
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
    let total: f32 = stepped.iter().map(|c| c.x).sum();
    assert!((total - 1.0).abs() < 1e-4, "flux after one step {total}");
    assert_eq!(stepped[index(4, 4, 4)], Vec4::ZERO);
    let neighbours = [index(5, 4, 4), index(3, 4, 4), index(4, 5, 4), index(4, 3, 4), index(4, 4, 5), index(4, 4, 3)];
    for n in neighbours {
        assert!((stepped[n].x - 1.0 / 6.0).abs() < 1e-4, "{}", stepped[n].x);
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
    assert!((total - y0).abs() < 1e-4 * y0.max(1.0), "{total}");
    let ahead = stepped[index(5, 4, 4)];
    let behind = stepped[index(3, 4, 4)];
    assert!(ahead.x > 2.0 * behind.x.abs(), "{ahead} vs {behind}");
    assert!(ahead.w > 0.0, "x coefficient {ahead}");
}

#[test]
fn two_steps_in_one_dispatch_equal_two_dispatches() {
    // The dispatch's first step is gathered over its tile and a border in workgroup memory
    // (propagate.wgsl): a lobe seeded at a tile's corner crosses into the neighbouring tiles
    // in the second step, as it does in two separate dispatches.
    let y0 = mrshade_core::sh::Y0;
    let y1 = mrshade_core::sh::Y1;
    let lobe = [y0, 0.3 * y1, -0.2 * y1, 0.5 * y1];
    let (_, fused, fused_sum) = propagated([3, 4, 3], lobe, &[(1, 2)]);
    let (_, split, split_sum) = propagated([3, 4, 3], lobe, &[(1, 1), (2, 2)]);
    for (k, (a, b)) in fused.iter().zip(&split).enumerate() {
        assert!((*a - *b).abs().max_element() < 1e-6, "cell {k}: {a} vs {b}");
    }
    for (k, (a, b)) in fused_sum.iter().zip(&split_sum).enumerate() {
        assert!((*a - *b).abs().max_element() < 1e-6, "sum at cell {k}: {a} vs {b}");
    }
    // Two steps in free space keep the flux, and the sum holds both.
    let total: f32 = fused.iter().map(|c| c.x).sum();
    assert!((total - y0).abs() < 1e-4, "{total}");
    let summed: f32 = fused_sum.iter().map(|c| c.x).sum();
    assert!((summed - 2.0 * y0).abs() < 1e-4, "{summed}");
    assert!(fused[index(3, 4, 3)].x > 0.0, "the second step brings light back to the seed");
}

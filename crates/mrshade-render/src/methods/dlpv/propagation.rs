//! The plumbing of seeding and propagation (propagate.wgsl): its bind group layout and which
//! sum buffer each dispatch reads.

use mrshade_gpu::bind;

/// The layout of seeding and propagation (propagate.wgsl's group 0): the uniform, the
/// fixed-point injection, scratch in and out, sums in and out.
pub fn propagate_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let cs = wgpu::ShaderStages::COMPUTE;
    bind::layout(
        device,
        "dlpv/propagate_layout",
        &[
            bind::uniform(0, cs),
            bind::storage(1, cs),
            bind::storage(2, cs),
            bind::storage_rw(3, cs),
            bind::storage(4, cs),
            bind::storage_rw(5, cs),
        ],
    )
}

/// Per dispatch of seeding (0) and propagation (1 …= `max_steps`), how many dispatches
/// before it added to the sums (propagate.wgsl `adds_to_sums`: the seed, every even step, the
/// last), and at `max_steps + 1` how many did in all: the sum buffer a dispatch reads is
/// this count's parity.
pub fn sum_updates(max_steps: u32) -> Vec<usize> {
    let adds = |k: u32| k.is_multiple_of(2) || k == max_steps;
    let mut count = 0;
    let mut out = Vec::with_capacity(max_steps as usize + 2);
    for k in 0..=max_steps {
        out.push(count);
        count += adds(k) as usize;
    }
    out.push(count);
    out
}

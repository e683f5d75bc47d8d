//! V_ρ gathered from VPLs (`dlpv.virtual_light = "gathered"`, rho_vpl.wgsl): the lights'
//! maps summed block by block into VPLs, and every cell of V_ρ the sum of their light at its
//! centre, in place of V_ρ's propagation.

use super::DlpvParams;
use bytemuck::{Pod, Zeroable};
use glam::{IVec3, UVec3, UVec4, Vec3, Vec4};
use mrshade_gpu::shader::compute_pipeline_entry;
use mrshade_gpu::{bind, wgsl};
use wgpu::util::DeviceExt;

/// Mirrors `GatherVpl` in rho_vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GatherVpl {
    position: Vec4,
    normal: Vec4,
    flux: Vec4,
}

/// Mirrors `RhoGatherInfo` in rho_gather.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GatherInfo {
    /// x: VPLs in all; yzw: the first cell gathered.
    vpls_first: UVec4,
    /// xyz: cells gathered along each axis.
    size: UVec4,
}

/// The cells V_ρ is read from: those of the virtual content's box, two cells around it (the
/// merge reads half a cell off a surface, trilinearly), within the volume; all of it without
/// virtual content. Other cells are never read (virtual pixels only) and left at zero.
fn cells_read(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams) -> (UVec3, UVec3) {
    let res = params.info.x;
    let Some((lo, hi)) = virtual_box else { return (UVec3::ZERO, UVec3::splat(res)) };
    let origin = params.origin.truncate();
    let h = params.origin.w;
    let cell = |p: Vec3| ((p - origin) / h).floor().as_ivec3();
    let first = (cell(lo) - 2).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    let last = (cell(hi) + 2).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    (first, last + 1 - first)
}

/// One set of maps to sum into VPLs: its group and its workgroups (blocks per side, pairs).
struct AggregateSet {
    group: wgpu::BindGroup,
    blocks: u32,
    pairs: u32,
}

/// A set of maps as the injection binds it: lights, texels, pairs; pair count, map side.
pub(super) struct MapSet<'a> {
    pub buffers: [&'a wgpu::Buffer; 3],
    pub pairs: u32,
    pub resolution: u32,
}

/// The two passes and the VPLs between them.
pub(super) struct RhoGather {
    aggregate: wgpu::ComputePipeline,
    sets: Vec<AggregateSet>,
    gather: wgpu::ComputePipeline,
    gather_group: wgpu::BindGroup,
    info: wgpu::Buffer,
    vpl_count: u32,
    /// The cells gathered (`cells_read`): their size.
    size: UVec3,
}

impl RhoGather {
    /// GPU timing label of both passes.
    pub const LABEL: &'static str = "dlpv-rho-gather";

    /// `params`: the volumes' uniform; `volumes`: the accumulated volumes, V_ρ first;
    /// `block`: texels per VPL side (at most the maps' side); `virtual_box` and `values`:
    /// where the cells read lie.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        volumes: &wgpu::Buffer,
        sets: &[MapSet],
        block: u32,
        virtual_box: Option<(Vec3, Vec3)>,
        values: &DlpvParams,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let sides: Vec<u32> = sets.iter().map(|s| block.min(s.resolution)).collect();
        let counts: Vec<u32> =
            sets.iter().zip(&sides).map(|(s, side)| s.pairs * (s.resolution / side).pow(2)).collect();
        let total: u32 = counts.iter().sum();
        let vpls = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/rho_vpls"),
            size: (total.max(1) as usize * std::mem::size_of::<GatherVpl>()) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let aggregate_layout = bind::layout(
            device,
            "dlpv/rho_aggregate_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage_rw(4, cs),
                bind::uniform(5, cs),
            ],
        );
        let aggregate =
            compute_pipeline_entry(device, "dlpv/rho_aggregate", AGGREGATE_SHADER, "aggregate", &[&aggregate_layout]);
        let mut first = 0;
        let sets = sets
            .iter()
            .zip(sides.iter().zip(&counts))
            .enumerate()
            .map(|(k, (set, (&side, &count)))| {
                let [lights, texels, pairs] = set.buffers;
                let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("dlpv/rho_set{k}_info")),
                    contents: bytemuck::bytes_of(&UVec4::new(set.resolution, set.pairs, first, side)),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                first += count;
                let group = bind::group(
                    device,
                    &format!("dlpv/rho_set{k}_group"),
                    &aggregate_layout,
                    &[
                        params.as_entire_binding(),
                        texels.as_entire_binding(),
                        pairs.as_entire_binding(),
                        lights.as_entire_binding(),
                        vpls.as_entire_binding(),
                        info.as_entire_binding(),
                    ],
                );
                AggregateSet { group, blocks: set.resolution / side, pairs: set.pairs }
            })
            .collect();
        let gather_layout = bind::layout(
            device,
            "dlpv/rho_gather_layout",
            &[bind::uniform(0, cs), bind::storage(1, cs), bind::storage_rw(2, cs), bind::uniform(3, cs)],
        );
        let gather = compute_pipeline_entry(device, "dlpv/rho_gather", GATHER_SHADER, "gather", &[&gather_layout]);
        let (first, size) = cells_read(virtual_box, values);
        let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dlpv/rho_gather_info"),
            contents: bytemuck::bytes_of(&GatherInfo { vpls_first: UVec4::from((total, first)), size: size.extend(0) }),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let gather_group = bind::group(
            device,
            "dlpv/rho_gather_group",
            &gather_layout,
            &[
                params.as_entire_binding(),
                vpls.as_entire_binding(),
                volumes.as_entire_binding(),
                info.as_entire_binding(),
            ],
        );
        Self { aggregate, sets, gather, gather_group, info, vpl_count: total, size }
    }

    /// The cells read moved with the virtual content (`values`: the volumes' new place).
    pub fn follow(&mut self, queue: &wgpu::Queue, virtual_box: Option<(Vec3, Vec3)>, values: &DlpvParams) {
        let (first, size) = cells_read(virtual_box, values);
        self.size = size;
        let info = GatherInfo { vpls_first: UVec4::from((self.vpl_count, first)), size: size.extend(0) };
        queue.write_buffer(&self.info, 0, bytemuck::bytes_of(&info));
    }

    /// Sums the maps into VPLs, then writes V_ρ (after the propagation, which leaves it).
    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.aggregate);
        for set in self.sets.iter().filter(|s| s.pairs > 0) {
            pass.set_bind_group(0, &set.group, &[]);
            pass.dispatch_workgroups(set.blocks, set.blocks, set.pairs);
        }
        pass.set_pipeline(&self.gather);
        pass.set_bind_group(0, &self.gather_group, &[]);
        let groups = (self.size + 3) / 4;
        pass.dispatch_workgroups(groups.x, groups.y, groups.z);
    }
}

const AGGREGATE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "volume.wgsl",
    "rho_vpl.wgsl",
    "rho_aggregate.wgsl",
);

const GATHER_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "volume.wgsl",
    "rho_vpl.wgsl",
    "rho_gather.wgsl"
);

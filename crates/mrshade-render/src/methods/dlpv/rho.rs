//! V_ρ gathered from VPLs (`dlpv.virtual_light = "gathered"`, rho_vpl.wgsl): the lights'
//! maps summed block by block into VPLs (rho_aggregate.wgsl), with `dlpv.photo_bounce` the
//! camera's real pixels tile by tile into VPLs of the photo's light (rho_photo.wgsl), and
//! every cell of V_ρ around the virtual content the sum of their light at its centre
//! (rho_gather.wgsl), in place of V_ρ's propagation.

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

/// What the photo's light in V_ρ reads (rho_photo.wgsl): the frame, its G-buffer and photo.
pub(super) struct RhoPhoto<'a> {
    pub frame_uniforms: &'a wgpu::Buffer,
    pub gbuffer: &'a crate::passes::gbuffer::GBuffer,
    pub photo: &'a mrshade_gpu::Target,
    pub internal_size: (u32, u32),
}

/// Pixels per side of the photo's tiles (rho_photo.wgsl) at `internal_size`: a power of two
/// near a sixtieth of its height, 2 to 16 (so that a tile's footprint, not its pixel count,
/// stays alike: 16-pixel tiles of a 160 × 120 image are a seventh of it).
fn photo_tile(internal_size: (u32, u32)) -> u32 {
    let t = (internal_size.1 / 60).clamp(2, 16);
    1 << t.ilog2()
}

/// One set of maps to sum into VPLs: its group and its workgroups (blocks along x and y,
/// pairs); the photo's tiles last, with no pairs.
struct AggregateSet {
    group: wgpu::BindGroup,
    blocks: [u32; 2],
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
    photo_tiles: wgpu::ComputePipeline,
    camera_group: wgpu::BindGroup,
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
        photo: RhoPhoto,
        block: u32,
        virtual_box: Option<(Vec3, Vec3)>,
        values: &DlpvParams,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let sides: Vec<u32> = sets.iter().map(|s| block.min(s.resolution)).collect();
        let set_buffers: Vec<[&wgpu::Buffer; 3]> = sets.iter().map(|s| s.buffers).collect();
        let counts: Vec<u32> =
            sets.iter().zip(&sides).map(|(s, side)| s.pairs * (s.resolution / side).pow(2)).collect();
        let tile = photo_tile(photo.internal_size);
        let tiles = [photo.internal_size.0.div_ceil(tile), photo.internal_size.1.div_ceil(tile)];
        let map_vpls: u32 = counts.iter().sum();
        let total = map_vpls + tiles[0] * tiles[1];
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
        // The frame, the G-buffer's depth, normals and flags, the photo (rho_photo.wgsl).
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let camera_layout = bind::layout(
            device,
            "dlpv/rho_camera_layout",
            &[
                bind::uniform(0, cs),
                bind::texture(1, cs, unfilterable, d2),
                bind::texture(2, cs, unfilterable, d2),
                bind::texture(3, cs, wgpu::TextureSampleType::Uint, d2),
                bind::texture(4, cs, unfilterable, d2),
            ],
        );
        use wgpu::BindingResource::TextureView;
        let camera_group = bind::group(
            device,
            "dlpv/rho_camera_group",
            &camera_layout,
            &[
                photo.frame_uniforms.as_entire_binding(),
                TextureView(&photo.gbuffer.depth_motion.view),
                TextureView(&photo.gbuffer.normal_roughness.view),
                TextureView(&photo.gbuffer.flags.view),
                TextureView(&photo.photo.view),
            ],
        );
        let layouts = [&aggregate_layout, &camera_layout];
        let aggregate = compute_pipeline_entry(device, "dlpv/rho_aggregate", AGGREGATE_SHADER, "aggregate", &layouts);
        let photo_tiles =
            compute_pipeline_entry(device, "dlpv/rho_photo_tiles", AGGREGATE_SHADER, "photo_tiles", &layouts);
        let mut first = 0;
        let mut sets: Vec<AggregateSet> = sets
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
                AggregateSet { group, blocks: [set.resolution / side; 2], pairs: set.pairs }
            })
            .collect();
        let photo_set = values.gathered.y == 1;
        if photo_set {
            // The photo's tiles after the maps' VPLs (their group's maps unread).
            let [lights, texels, pairs] = set_buffers.first().copied().unwrap_or([&vpls; 3]);
            let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("dlpv/rho_photo_info"),
                contents: bytemuck::bytes_of(&UVec4::new(0, 0, map_vpls, tile)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let group = bind::group(
                device,
                "dlpv/rho_photo_group",
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
            sets.push(AggregateSet { group, blocks: tiles, pairs: 0 });
        }
        let total = if photo_set { total } else { map_vpls };
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
        Self { aggregate, photo_tiles, camera_group, sets, gather, gather_group, info, vpl_count: total, size }
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
        pass.set_bind_group(1, &self.camera_group, &[]);
        for set in &self.sets {
            pass.set_pipeline(if set.pairs > 0 { &self.aggregate } else { &self.photo_tiles });
            pass.set_bind_group(0, &set.group, &[]);
            pass.dispatch_workgroups(set.blocks[0], set.blocks[1], set.pairs.max(1));
        }
        pass.set_pipeline(&self.gather);
        pass.set_bind_group(0, &self.gather_group, &[]);
        let groups = (self.size + 3) / 4;
        pass.dispatch_workgroups(groups.x, groups.y, groups.z);
    }
}

const AGGREGATE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "volume.wgsl",
    "rho_vpl.wgsl",
    "rho_aggregate.wgsl",
    "rho_photo.wgsl",
);

const GATHER_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "volume.wgsl",
    "rho_vpl.wgsl",
    "rho_gather.wgsl"
);

//! V_ρ gathered from VPLs (`dlpv.virtual_light = "gathered"`, rho_vpl.wgsl): the lights'
//! maps summed block by block into VPLs (rho_aggregate.wgsl), with `dlpv.photo_bounce` the
//! camera's real pixels tile by tile into VPLs of the photo's light (rho_photo.wgsl), and
//! every cell of V_ρ around the virtual content the sum of their light at its centre
//! (rho_gather.wgsl), in place of V_ρ's propagation.

use super::DlpvParams;
use bytemuck::{Pod, Zeroable};
use glam::{IVec3, UVec3, UVec4, Vec3, Vec4};
use mrshade_gpu::shader::compute_pipeline_entry;
use mrshade_gpu::timing::Recorder;
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

/// Mirrors `RhoGatherInfo` in rho_vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GatherInfo {
    /// x: chunks of the VPLs; yzw: the first cell gathered.
    chunks_first: UVec4,
    /// xyz: cells gathered along each axis.
    size: UVec4,
}

/// The cells V_ρ is read from: those of the virtual content's box and one cell around it (the
/// merge reads half a cell off a surface, trilinearly: at most the next cell out), within the
/// volume; all of it without virtual content. Other cells are never read (virtual pixels only)
/// and left at zero.
fn cells_read(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams) -> (UVec3, UVec3) {
    let res = params.info.x;
    let Some((lo, hi)) = virtual_box else { return (UVec3::ZERO, UVec3::splat(res)) };
    let origin = params.origin.truncate();
    let h = params.origin.w;
    let cell = |p: Vec3| ((p - origin) / h).floor().as_ivec3();
    let first = (cell(lo) - 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    let last = (cell(hi) + 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    (first, last + 1 - first)
}

/// What the photo's light in V_ρ reads (rho_photo.wgsl): the frame, its G-buffer and photo.
pub(super) struct RhoPhoto<'a> {
    pub frame_uniforms: &'a wgpu::Buffer,
    pub gbuffer: &'a crate::passes::gbuffer::GBuffer,
    pub photo: &'a mrshade_gpu::Target,
    pub internal_size: (u32, u32),
}

/// Pixels per side of the photo's tiles (rho_photo.wgsl) at `internal_size`: 40 rows of tiles
/// whatever the size (2 to 64 pixels), so that a tile's footprint, not its pixel count, stays
/// alike — 16-pixel tiles are a seventh of a 160 × 120 image and 8 160 VPLs at 1080p. Region
/// FLIP on lavapipe at 640×480 with 60 / 40 / 30 rows: desk-spot-real 0.1619 / 0.1641 / 0.1693,
/// cornell 0.1748 / 0.1743 / 0.1745.
fn photo_tile(internal_size: (u32, u32)) -> u32 {
    internal_size.1.div_ceil(PHOTO_TILE_ROWS).clamp(2, 64)
}

/// Rows of the photo's tiles.
const PHOTO_TILE_ROWS: u32 = 40;

/// GPU bytes of the gathered V_ρ: its VPLs (`pairs_texels`: the maps' pairs × texels per map,
/// per set; the photo's tiles for images up to 4:1) and the gather's partial sums.
pub(super) fn bytes(pairs_texels: &[(u64, u64)], block: u64, cells: u64) -> u64 {
    let vpl = std::mem::size_of::<GatherVpl>() as u64;
    let map_vpls: u64 = pairs_texels.iter().map(|&(pairs, texels)| pairs * (texels / (block * block)).max(1)).sum();
    let photo_vpls = PHOTO_TILE_ROWS as u64 * 4 * PHOTO_TILE_ROWS as u64;
    (map_vpls + photo_vpls) * vpl + chunks(cells) as u64 * cells * PARTIAL_CELL_BYTES
}

/// Chunks the VPLs are gathered in: as many as `PARTIAL_BYTES` of partial sums hold, 1 to 16.
fn chunks(cells: u64) -> u32 {
    (PARTIAL_BYTES / (cells * PARTIAL_CELL_BYTES)).clamp(1, 16) as u32
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
    gather_sum: wgpu::ComputePipeline,
    gather_group: wgpu::BindGroup,
    info: wgpu::Buffer,
    /// The VPLs appended (cleared before the pass).
    count: wgpu::Buffer,
    /// Chunks the VPLs are gathered in (`rho_gather.wgsl`).
    chunks: u32,
    /// The cells gathered (`cells_read`): their size.
    size: UVec3,
}

/// Bytes of the gather's partial sums at most: the chunks are as many as fit (16 at most).
const PARTIAL_BYTES: u64 = 32 << 20;

/// Bytes of one cell's partial sum over one chunk (rho_gather.wgsl `partials`: a vec4f of SH
/// coefficients per channel).
const PARTIAL_CELL_BYTES: u64 = 3 * 16;

impl RhoGather {
    /// GPU timing label of the maps' and the photo's VPLs.
    pub const VPLS_LABEL: &'static str = "dlpv-rho-vpls";
    /// GPU timing label of the gather into V_ρ's cells.
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
        let counts: Vec<u32> =
            sets.iter().zip(&sides).map(|(s, side)| s.pairs * (s.resolution / side).pow(2)).collect();
        let tile = photo_tile(photo.internal_size);
        let tiles = [photo.internal_size.0.div_ceil(tile), photo.internal_size.1.div_ceil(tile)];
        let map_vpls: u32 = counts.iter().sum();
        let total = map_vpls + tiles[0] * tiles[1];
        let cells = (values.info.x as u64).pow(3);
        let chunks = chunks(cells);
        let (first, size) = cells_read(virtual_box, values);
        let gather_info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dlpv/rho_gather_info"),
            contents: bytemuck::bytes_of(&GatherInfo {
                chunks_first: UVec4::from((chunks, first)),
                size: size.extend(0),
            }),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let count = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/rho_vpl_count"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
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
                bind::storage_rw(6, cs),
                bind::uniform(7, cs),
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
        // One group per set of maps (its texels, pairs, lights, and (side, pairs, 0, block)),
        // and the photo's tiles with a set's maps bound unread.
        let aggregate_group = |label: &str, [lights, texels, pairs]: [&wgpu::Buffer; 3], set_info: UVec4| {
            let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}_info")),
                contents: bytemuck::bytes_of(&set_info),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            bind::group(
                device,
                &format!("{label}_group"),
                &aggregate_layout,
                &[
                    params.as_entire_binding(),
                    texels.as_entire_binding(),
                    pairs.as_entire_binding(),
                    lights.as_entire_binding(),
                    vpls.as_entire_binding(),
                    info.as_entire_binding(),
                    count.as_entire_binding(),
                    gather_info.as_entire_binding(),
                ],
            )
        };
        let mut aggregate_sets: Vec<AggregateSet> = sets
            .iter()
            .zip(&sides)
            .enumerate()
            .map(|(k, (set, &side))| AggregateSet {
                group: aggregate_group(
                    &format!("dlpv/rho_set{k}"),
                    set.buffers,
                    UVec4::new(set.resolution, set.pairs, 0, side),
                ),
                blocks: [set.resolution / side; 2],
                pairs: set.pairs,
            })
            .collect();
        if values.gathered.y == 1 {
            let maps = sets.first().map_or([&vpls; 3], |s| s.buffers);
            let group = aggregate_group("dlpv/rho_photo", maps, UVec4::new(0, 0, 0, tile));
            aggregate_sets.push(AggregateSet { group, blocks: tiles, pairs: 0 });
        }
        let gather_layout = bind::layout(
            device,
            "dlpv/rho_gather_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage_rw(2, cs),
                bind::uniform(3, cs),
                bind::storage(4, cs),
                bind::storage_rw(5, cs),
            ],
        );
        let gather = compute_pipeline_entry(device, "dlpv/rho_gather", GATHER_SHADER, "gather", &[&gather_layout]);
        let gather_sum =
            compute_pipeline_entry(device, "dlpv/rho_gather_sum", GATHER_SHADER, "gather_sum", &[&gather_layout]);
        let partials = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/rho_partials"),
            size: chunks as u64 * cells * PARTIAL_CELL_BYTES,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });

        let gather_group = bind::group(
            device,
            "dlpv/rho_gather_group",
            &gather_layout,
            &[
                params.as_entire_binding(),
                vpls.as_entire_binding(),
                volumes.as_entire_binding(),
                gather_info.as_entire_binding(),
                count.as_entire_binding(),
                partials.as_entire_binding(),
            ],
        );
        Self {
            aggregate,
            photo_tiles,
            camera_group,
            sets: aggregate_sets,
            gather,
            gather_sum,
            gather_group,
            info: gather_info,
            count,
            chunks,
            size,
        }
    }

    /// The cells read moved with the virtual content (`values`: the volumes' new place).
    pub fn follow(&mut self, queue: &wgpu::Queue, virtual_box: Option<(Vec3, Vec3)>, values: &DlpvParams) {
        let (first, size) = cells_read(virtual_box, values);
        self.size = size;
        let info = GatherInfo { chunks_first: UVec4::from((self.chunks, first)), size: size.extend(0) };
        queue.write_buffer(&self.info, 0, bytemuck::bytes_of(&info));
    }

    /// Sums the maps into VPLs, then writes V_ρ (after the propagation, which leaves it).
    pub fn record(&self, rec: &mut Recorder) {
        rec.encoder.clear_buffer(&self.count, 0, None);
        rec.compute(Self::VPLS_LABEL, |pass| {
            pass.set_bind_group(1, &self.camera_group, &[]);
            for set in &self.sets {
                pass.set_pipeline(if set.pairs > 0 { &self.aggregate } else { &self.photo_tiles });
                pass.set_bind_group(0, &set.group, &[]);
                pass.dispatch_workgroups(set.blocks[0], set.blocks[1], set.pairs.max(1));
            }
        });
        rec.compute(Self::LABEL, |pass| self.record_gather(pass));
    }

    fn record_gather(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.gather);
        pass.set_bind_group(0, &self.gather_group, &[]);
        let blocks = (self.size + 3) / 4;
        pass.dispatch_workgroups(blocks.x * blocks.y * blocks.z, self.chunks, 1);
        pass.set_pipeline(&self.gather_sum);
        pass.dispatch_workgroups(blocks.x, blocks.y, blocks.z);
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

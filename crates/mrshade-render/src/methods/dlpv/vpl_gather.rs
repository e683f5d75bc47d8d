//! The volumes gathered from VPLs (vpl.wgsl): V_ρ (`dlpv.virtual_light = "gathered"`)
//! and V_μ with V_Δ's indirect change (`dlpv.bounce_light = "gathered"`). The lights' maps
//! summed block by block into VPLs by what they light (vpl_aggregate.wgsl), with
//! `dlpv.photo_bounce` the camera's real pixels tile by tile into VPLs of the photo's light
//! (vpl_photo.wgsl), and every cell read the sum of their light at its centre
//! (vpl_gather.wgsl), in place of the propagation.

use super::DlpvParams;
use super::shaders::{VPL_AGGREGATE_SHADER, VPL_GATHER_SHADER, VPL_MARK_SHADER};
use super::visibility::{VisibilityMaps, VisibilityMapsView, map_room};
use bytemuck::{Pod, Zeroable};
use glam::{IVec3, UVec3, UVec4, Vec3, Vec4};
use mrshade_gpu::bind;
use mrshade_gpu::shader::compute_pipeline_entry;
use mrshade_gpu::timing::Recorder;
use wgpu::util::DeviceExt;

/// Mirrors `GatherVpl` in vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GatherVpl {
    position: Vec4,
    normal: Vec4,
    flux: Vec4,
}

/// Mirrors `GatherInfo` in vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GatherInfo {
    /// x: chunks of the VPLs; yzw: the first cell gathered.
    chunks_first: UVec4,
    /// xyz: cells gathered along each axis; w: parts with visibility maps at most along each
    /// axis (visibility.rs `map_room`).
    size: UVec4,
    /// xyz: the first cell of V_ρ's (`rho_cells`); w: the index of the first of the virtual
    /// surfaces' cells' VPLs (vpl_aggregate.wgsl `cell_vpls`).
    rho_first: UVec4,
    /// xyz: one past its last cell; w: unused.
    rho_end: UVec4,
}

impl GatherInfo {
    /// `room`: parts with visibility maps along each axis; `cell_base`: the first cell VPL.
    fn new(
        chunks: u32,
        virtual_box: Option<(Vec3, Vec3)>,
        params: &DlpvParams,
        gathered: u32,
        [room, cell_base]: [u32; 2],
    ) -> Self {
        let (first, size) = cells_read(virtual_box, params, gathered);
        let (rho_first, rho_size) = rho_cells(virtual_box, params);
        Self {
            chunks_first: UVec4::from((chunks, first)),
            size: size.extend(room),
            rho_first: rho_first.extend(cell_base),
            rho_end: (rho_first + rho_size).extend(0),
        }
    }
}

/// The volumes gathered (the shaders read them from `DlpvParams::gathered`): V_ρ; V_μ and
/// V_Δ's indirect change.
pub(super) const GATHERED_RHO: u32 = 1;
pub(super) const GATHERED_BOUNCE: u32 = 2;

/// Bytes of one cell's partial sums over one chunk (vpl_gather.wgsl `partials`): V_ρ's bands
/// 0–2 (seven vec4f), with the bounce light V_Δ's and V_μ's bands 0–1 (three each).
fn partial_cell_bytes(gathered: u32) -> u64 {
    16 * if gathered & GATHERED_BOUNCE != 0 { 13 } else { 7 }
}

/// The cells gathered: with the bounce light (real pixels read any) every one; for V_ρ alone
/// its cells (`rho_cells`).
fn cells_read(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams, gathered: u32) -> (UVec3, UVec3) {
    if gathered & GATHERED_BOUNCE != 0 {
        return (UVec3::ZERO, UVec3::splat(params.info.x));
    }
    rho_cells(virtual_box, params)
}

/// The cells of V_ρ that virtual pixels read: those of the virtual content's box and one cell
/// around it (the merge reads half a cell off a surface, trilinearly: at most the next cell
/// out), within the volume, all of it without virtual content. Others are left at zero.
fn rho_cells(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams) -> (UVec3, UVec3) {
    let res = params.info.x;
    let all = (UVec3::ZERO, UVec3::splat(res));
    let Some((lo, hi)) = virtual_box else { return all };
    let origin = params.origin.truncate();
    let h = params.origin.w;
    let cell = |p: Vec3| ((p - origin) / h).floor().as_ivec3();
    let first = (cell(lo) - 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    let last = (cell(hi) + 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    (first, last + 1 - first)
}

/// What the photo's light in V_ρ reads (vpl_photo.wgsl): the frame, its G-buffer and photo.
pub(super) struct VplPhoto<'a> {
    pub frame_uniforms: &'a wgpu::Buffer,
    pub gbuffer: &'a crate::passes::gbuffer::GBuffer,
    pub photo: &'a mrshade_gpu::Target,
    pub internal_size: (u32, u32),
}

/// Pixels per side of the photo's tiles (vpl_photo.wgsl) at `internal_size`: 40 rows of tiles
/// whatever the size (2 to 64 pixels), so that a tile's footprint, not its pixel count, stays
/// alike — 16-pixel tiles are a seventh of a 160 × 120 image and 8 160 VPLs at 1080p. Region
/// FLIP on lavapipe at 640×480 with 60 / 40 / 30 rows: desk-spot-real 0.1619 / 0.1641 / 0.1693,
/// cornell 0.1748 / 0.1743 / 0.1745.
fn photo_tile(internal_size: (u32, u32)) -> u32 {
    internal_size.1.div_ceil(PHOTO_TILE_ROWS).clamp(2, 64)
}

/// Rows of the photo's tiles.
const PHOTO_TILE_ROWS: u32 = 40;

/// GPU bytes of the gathered volumes (`gathered`: `GATHERED_*` bits): their VPLs
/// (`pairs_texels`: the maps' pairs × texels per map, per set, up to four VPLs per block;
/// the photo's tiles for images up to 4:1; with the bounce light one per cell and the
/// cells' planes and their sums, `dlpv.virtual_bounce`) and the gather's partial sums.
pub(super) fn bytes(pairs_texels: &[(u64, u64)], block: u64, cells: u64, gathered: u32) -> u64 {
    let vpl = std::mem::size_of::<GatherVpl>() as u64;
    let map_vpls: u64 = pairs_texels.iter().map(|&(pairs, texels)| pairs * (texels / (block * block)).max(1)).sum();
    let per_block = if gathered & GATHERED_BOUNCE != 0 { VPLS_PER_BLOCK } else { 1 };
    let photo_vpls = PHOTO_TILE_ROWS as u64 * 4 * PHOTO_TILE_ROWS as u64;
    let partial = partial_cell_bytes(gathered);
    let cell_bytes =
        if gathered & GATHERED_BOUNCE != 0 { cells * (VPLS_PER_CELL * vpl + 32 + PLANE_SUM_BYTES) } else { 0 };
    (map_vpls * per_block + photo_vpls) * vpl + cell_bytes + chunks(cells, partial) as u64 * cells * partial
}

/// Bytes of a cell's sums of the virtual texels in it, per way they face (vpl_aggregate.wgsl
/// `PLANE_WAYS` × `PLANE_SUMS`).
const PLANE_SUM_BYTES: u64 = 6 * 8 * 4;

/// VPLs a cell of a virtual surface appends at most (vpl_aggregate.wgsl `cell_vpls`: one per
/// way its texels face).
const VPLS_PER_CELL: u64 = 6;

/// VPLs a block of a map appends at most with the bounce light gathered (vpl_aggregate.wgsl):
/// its lit real texels, its hidden ones the camera does not see and those it sees, and the
/// virtual texels that hide them.
const VPLS_PER_BLOCK: u64 = 4;

/// Chunks the VPLs are gathered in: as many as `PARTIAL_BYTES` of partial sums hold (`partial`
/// bytes per cell), 1 to 16.
fn chunks(cells: u64, partial: u64) -> u32 {
    (PARTIAL_BYTES / (cells * partial)).clamp(1, 16) as u32
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
pub(super) struct VplGather {
    aggregate: wgpu::ComputePipeline,
    /// The virtual surfaces' cells as VPLs of their light (with `dlpv.virtual_bounce`).
    cell_vpls: Option<wgpu::ComputePipeline>,
    /// The sums of the virtual texels in each cell they hold (vpl_aggregate.wgsl
    /// `plane_sums`), cleared before the maps are summed.
    plane_sums: wgpu::Buffer,
    /// Cells in the volume.
    cells: u32,
    photo_tiles: wgpu::ComputePipeline,
    /// Flags the blocks of cells the pixels read (with the bounce light gathered), and its
    /// group 0.
    mark_cells: Option<(wgpu::ComputePipeline, wgpu::BindGroup)>,
    /// Per block of 4³ cells, 1 where a pixel reads one (mark_cells.wgsl).
    blocks_read: wgpu::Buffer,
    /// The internal size (`mark_cells` runs once per pixel).
    pixels: (u32, u32),
    camera_group: wgpu::BindGroup,
    sets: Vec<AggregateSet>,
    gather: wgpu::ComputePipeline,
    gather_sum: wgpu::ComputePipeline,
    gather_group: wgpu::BindGroup,
    info: wgpu::Buffer,
    /// The VPLs appended (cleared before the pass).
    count: wgpu::Buffer,
    /// Chunks the VPLs are gathered in (`vpl_gather.wgsl`).
    chunks: u32,
    /// The cells gathered (`cells_read`): their size.
    size: UVec3,
    /// The volumes gathered (`GATHERED_*`).
    gathered: u32,
    /// Where V_ρ's cells lie (what `info` holds).
    rho_first: UVec3,
    /// The visibility maps of V_ρ's parts (with `dlpv.virtual_bounce`).
    visibility: Option<VisibilityMaps>,
    /// Their parts along each axis at most (`map_room`; 0 without them).
    room: u32,
    /// The index of the first cell VPL (`GatherInfo`).
    cell_base: u32,
}

/// Bytes of the gather's partial sums at most: the chunks are as many as fit (16 at most).
/// 48 MiB: seven chunks of 32³ cells with V_ρ's band 2 (13 vec4f a cell), as many as without
/// it at 32 MiB; four took the gather from 0.18 to 0.28 ms on cornell at 1080p on the H100
/// (docs/benchmarks.md, 2026-12-06).
const PARTIAL_BYTES: u64 = 48 << 20;

impl VplGather {
    /// GPU timing label of the maps' and the photo's VPLs.
    pub const VPLS_LABEL: &'static str = "dlpv-vpls";
    /// GPU timing label of the visibility maps (with `dlpv.virtual_bounce`).
    pub const VISIBILITY_LABEL: &'static str = "dlpv-visibility";
    /// GPU timing label of the gather into V_ρ's cells.
    pub const LABEL: &'static str = "dlpv-vpl-gather";

    /// `params`: the volumes' uniform; `volumes`: the accumulated volumes, V_ρ first;
    /// `rho_band2`: V_ρ's band 2 (volume.wgsl);
    /// `injected`: the injection (V_Δ's direct change); `gathered`: the volumes gathered
    /// (`GATHERED_*`); `block`: texels per VPL side (at most the maps' side); `virtual_box`
    /// and `values`: where the cells read lie.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        volumes: &wgpu::Buffer,
        rho_band2: &wgpu::Buffer,
        injected: &wgpu::Buffer,
        gathered: u32,
        sets: &[MapSet],
        photo: VplPhoto,
        block: u32,
        virtual_box: Option<(Vec3, Vec3)>,
        values: &DlpvParams,
        extent: f32,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let sides: Vec<u32> = sets.iter().map(|s| block.min(s.resolution)).collect();
        let counts: Vec<u32> =
            sets.iter().zip(&sides).map(|(s, side)| s.pairs * (s.resolution / side).pow(2)).collect();
        let tile = photo_tile(photo.internal_size);
        let tiles = [photo.internal_size.0.div_ceil(tile), photo.internal_size.1.div_ceil(tile)];
        let per_block = if gathered & GATHERED_BOUNCE != 0 { VPLS_PER_BLOCK as u32 } else { 1 };
        let map_vpls: u32 = counts.iter().sum::<u32>() * per_block;
        let cells = (values.info.x as u64).pow(3);
        let virtual_bounce = values.virtual_bounce();
        // With the virtual surfaces' bounce, a VPL per way a cell's virtual surfaces face
        // (`cell_vpls`).
        let cell_vpls = if virtual_bounce { (cells * VPLS_PER_CELL) as u32 } else { 0 };
        let total = map_vpls + tiles[0] * tiles[1] + cell_vpls;
        let partial = partial_cell_bytes(gathered);
        let chunks = chunks(cells, partial);
        let room = if virtual_bounce { map_room(values.info.x, extent) } else { 0 };
        // The cells' VPLs after room for every map's and the photo's.
        let cell_base = map_vpls + tiles[0] * tiles[1];
        let info = GatherInfo::new(chunks, virtual_box, values, gathered, [room, cell_base]);
        let size = info.size.truncate();
        let gather_info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dlpv/vpl_gather_info"),
            contents: bytemuck::bytes_of(&info),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let count = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/vpl_vpl_count"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let blocks_read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/blocks_read"),
            size: (cells / 64).max(1) * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Two vec4f a cell (vpl_aggregate.wgsl `planes`) and their sums, with the virtual
        // surfaces' bounce.
        let per_cell = |bytes: u64| if virtual_bounce { cells * bytes } else { bytes };
        let planes = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/virtual_planes"),
            size: per_cell(32),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let plane_sums = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/virtual_plane_sums"),
            size: per_cell(PLANE_SUM_BYTES),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let vpls = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/vpl_vpls"),
            size: (total.max(1) as usize * std::mem::size_of::<GatherVpl>()) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let aggregate_layout = bind::layout(
            device,
            "dlpv/vpl_aggregate_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage_rw(4, cs),
                bind::uniform(5, cs),
                bind::storage_rw(6, cs),
                bind::uniform(7, cs),
                bind::storage_rw(8, cs),
                bind::storage(9, cs),
                bind::storage(10, cs),
                bind::storage_rw(11, cs),
                bind::storage_rw(12, cs),
            ],
        );
        // The frame, the G-buffer's depth, normals and flags, the photo (vpl_photo.wgsl).
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let camera_layout = bind::layout(
            device,
            "dlpv/vpl_camera_layout",
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
            "dlpv/vpl_camera_group",
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
        let aggregate =
            compute_pipeline_entry(device, "dlpv/vpl_aggregate", VPL_AGGREGATE_SHADER, "aggregate", &layouts);
        let photo_tiles =
            compute_pipeline_entry(device, "dlpv/vpl_photo_tiles", VPL_AGGREGATE_SHADER, "photo_tiles", &layouts);
        let cell_vpls = virtual_bounce
            .then(|| compute_pipeline_entry(device, "dlpv/vpl_cell_vpls", VPL_AGGREGATE_SHADER, "cell_vpls", &layouts));
        let mark_cells = (gathered & GATHERED_BOUNCE != 0).then(|| {
            let layout =
                bind::layout(device, "dlpv/mark_cells_layout", &[bind::uniform(0, cs), bind::storage_rw(1, cs)]);
            let group = bind::group(
                device,
                "dlpv/mark_cells_group",
                &layout,
                &[params.as_entire_binding(), blocks_read.as_entire_binding()],
            );
            let pipeline = compute_pipeline_entry(
                device,
                "dlpv/mark_cells",
                VPL_MARK_SHADER,
                "mark_cells",
                &[&layout, &camera_layout],
            );
            (pipeline, group)
        });
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
                    planes.as_entire_binding(),
                    volumes.as_entire_binding(),
                    rho_band2.as_entire_binding(),
                    plane_sums.as_entire_binding(),
                    blocks_read.as_entire_binding(),
                ],
            )
        };
        let mut aggregate_sets: Vec<AggregateSet> = sets
            .iter()
            .zip(&sides)
            .enumerate()
            .map(|(k, (set, &side))| AggregateSet {
                group: aggregate_group(
                    &format!("dlpv/vpl_set{k}"),
                    set.buffers,
                    UVec4::new(set.resolution, set.pairs, 0, side),
                ),
                blocks: [set.resolution / side; 2],
                pairs: set.pairs,
            })
            .collect();
        if values.gathered.y == 1 {
            let maps = sets.first().map_or([&vpls; 3], |s| s.buffers);
            let group = aggregate_group("dlpv/vpl_photo", maps, UVec4::new(0, 0, 0, tile));
            aggregate_sets.push(AggregateSet { group, blocks: tiles, pairs: 0 });
        }
        let gather_layout = bind::layout(
            device,
            "dlpv/vpl_gather_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage_rw(2, cs),
                bind::uniform(3, cs),
                bind::storage(4, cs),
                bind::storage_rw(5, cs),
                bind::storage(6, cs),
                bind::storage(7, cs),
                bind::storage_rw(8, cs),
                bind::storage(9, cs),
                bind::storage(10, cs),
            ],
        );
        let visibility =
            virtual_bounce.then(|| VisibilityMaps::new(device, params, &gather_info, &planes, &blocks_read, room));
        let gather = compute_pipeline_entry(device, "dlpv/vpl_gather", VPL_GATHER_SHADER, "gather", &[&gather_layout]);
        let gather_sum =
            compute_pipeline_entry(device, "dlpv/vpl_gather_sum", VPL_GATHER_SHADER, "gather_sum", &[&gather_layout]);
        let partials = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/vpl_partials"),
            size: chunks as u64 * cells * partial,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });

        let gather_group = bind::group(
            device,
            "dlpv/vpl_gather_group",
            &gather_layout,
            &[
                params.as_entire_binding(),
                vpls.as_entire_binding(),
                volumes.as_entire_binding(),
                gather_info.as_entire_binding(),
                count.as_entire_binding(),
                partials.as_entire_binding(),
                injected.as_entire_binding(),
                blocks_read.as_entire_binding(),
                rho_band2.as_entire_binding(),
                planes.as_entire_binding(),
                visibility.as_ref().map_or(&planes, |v| &v.maps).as_entire_binding(),
            ],
        );
        Self {
            aggregate,
            cell_vpls,
            plane_sums,
            cells: cells as u32,
            photo_tiles,
            mark_cells,
            blocks_read,
            pixels: photo.internal_size,
            camera_group,
            sets: aggregate_sets,
            gather,
            gather_sum,
            gather_group,
            info: gather_info,
            count,
            chunks,
            size,
            gathered,
            visibility,
            room,
            cell_base,
            rho_first: info.rho_first.truncate(),
        }
    }

    /// The visibility maps of V_ρ's parts (with `dlpv.virtual_bounce`).
    pub fn visibility_maps(&self) -> Option<VisibilityMapsView<'_>> {
        let first_part = self.rho_first / 4 * 2;
        self.visibility.as_ref().map(|v| VisibilityMapsView { maps: &v.maps, first_part, room: self.room })
    }

    /// The cells read moved with the virtual content (`values`: the volumes' new place).
    pub fn follow(&mut self, queue: &wgpu::Queue, virtual_box: Option<(Vec3, Vec3)>, values: &DlpvParams) {
        let info = GatherInfo::new(self.chunks, virtual_box, values, self.gathered, [self.room, self.cell_base]);
        self.rho_first = info.rho_first.truncate();
        self.size = info.size.truncate();
        queue.write_buffer(&self.info, 0, bytemuck::bytes_of(&info));
    }

    /// Sums the maps into VPLs (`record_vpls`), then writes the gathered volumes
    /// (`record_gather_pass`).
    /// `bounce`: this frame's `DlpvParams::virtual_bounce` (the virtual surfaces' VPLs and the
    /// visibility maps are left out without it).
    pub fn record(&self, rec: &mut Recorder, bounce: bool) {
        self.record_vpls(rec, bounce);
        self.record_gather_pass(rec, bounce);
    }

    /// Sums the maps into VPLs (with the bounce light: first flags the cells the pixels read;
    /// with the virtual surfaces' bounce, last their cells, which read the V_ρ the last
    /// gather left: before the volumes are cleared).
    pub fn record_vpls(&self, rec: &mut Recorder, bounce: bool) {
        rec.encoder.clear_buffer(&self.count, 0, None);
        if self.mark_cells.is_some() {
            rec.encoder.clear_buffer(&self.blocks_read, 0, None);
        }
        if self.cell_vpls.is_some() {
            rec.encoder.clear_buffer(&self.plane_sums, 0, None);
        }
        rec.compute(Self::VPLS_LABEL, |pass| {
            pass.set_bind_group(1, &self.camera_group, &[]);
            if let Some((mark, group)) = &self.mark_cells {
                pass.set_pipeline(mark);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(self.pixels.0.div_ceil(8), self.pixels.1.div_ceil(8), 1);
            }
            for set in &self.sets {
                pass.set_pipeline(if set.pairs > 0 { &self.aggregate } else { &self.photo_tiles });
                pass.set_bind_group(0, &set.group, &[]);
                pass.dispatch_workgroups(set.blocks[0], set.blocks[1], set.pairs.max(1));
            }
            if let (Some(pipeline), Some(set), true) = (&self.cell_vpls, self.sets.first(), bounce) {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &set.group, &[]);
                pass.dispatch_workgroups(self.cells.div_ceil(64), 1, 1);
            }
        });
    }

    /// Writes the gathered volumes from the VPLs (after the propagation, which leaves them).
    pub fn record_gather_pass(&self, rec: &mut Recorder, bounce: bool) {
        if let (Some(visibility), true) = (&self.visibility, bounce) {
            rec.compute(Self::VISIBILITY_LABEL, |pass| visibility.record(pass));
        }
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

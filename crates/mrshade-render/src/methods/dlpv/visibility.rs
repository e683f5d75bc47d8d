//! The visibility maps of V_ρ's parts (visibility.wgsl, visibility_maps.wgsl): per part of
//! 2³ cells of the blocks that hold V_ρ's cells, how far the first virtual surface lies in
//! each of 1 024 directions, so that the gather tests a VPL's path to the part with one read
//! (with `dlpv.virtual_bounce`).

use super::shaders::VISIBILITY_MAPS_SHADER;
use mrshade_gpu::bind;
use mrshade_gpu::shader::compute_pipeline_entry;

/// Mirrors `MAP_SIDE` in visibility.wgsl: texels per side of a part's octahedral map.
pub const MAP_SIDE: u32 = 32;
/// Mirrors `MAP_WORDS`: two texels of two bytes a word.
const MAP_WORDS: u32 = MAP_SIDE * MAP_SIDE / 2;
/// Mirrors `MAP_UNITS`: a texel's distance in 1/`MAP_UNITS` cells.
pub const MAP_UNITS: f32 = 32.0;
/// Mirrors `NO_CROSSING`: no virtual surface before the edge of V_ρ's box.
pub const NO_CROSSING: u16 = 0xffff;

/// The maps as a test or a view reads them: map `(p.z · room + p.y) · room + p.x` is part
/// `first_part + p`'s (a part: 2³ cells; visibility.wgsl `part_map`), texel (x, y) of it the
/// two bytes `y · MAP_SIDE + x`.
pub struct VisibilityMapsView<'a> {
    /// The maps, two texels a `u32`.
    pub maps: &'a wgpu::Buffer,
    /// The part of the first map (in parts of the volume).
    pub first_part: glam::UVec3,
    /// Maps along each axis.
    pub room: u32,
}

/// Parts a map is kept for along each axis: those of the blocks of 4³ cells that the virtual
/// content's box and a cell around it can touch (`place` makes the volume `extent` times the
/// content's largest side), at most the volume's.
pub(super) fn map_room(resolution: u32, extent: f32) -> u32 {
    let cells = (resolution as f32 / extent).ceil() as u32 + 3;
    (2 * (cells.div_ceil(4) + 1)).min(resolution / 2).max(1)
}

/// Bytes of the maps (with `dlpv.virtual_bounce`).
pub(super) fn bytes(resolution: u32, extent: f32) -> u64 {
    room_bytes(map_room(resolution, extent))
}

/// Bytes of `room`³ maps.
fn room_bytes(room: u32) -> u64 {
    (room as u64).pow(3) * MAP_WORDS as u64 * 4
}

/// The pass and the maps it writes.
pub(super) struct VisibilityMaps {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    /// The maps (vpl_gather.wgsl reads them).
    pub maps: wgpu::Buffer,
    room: u32,
}

impl VisibilityMaps {
    /// `params`: the volumes' uniform; `gather_info`: where V_ρ's cells lie (vpl.wgsl
    /// `GatherInfo`, its `size.w` = `room`); `planes`: the virtual surfaces' planes per cell;
    /// `blocks_read`: which blocks of cells the gather sums (vpl_gather.wgsl).
    pub fn new(
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        gather_info: &wgpu::Buffer,
        planes: &wgpu::Buffer,
        blocks_read: &wgpu::Buffer,
        room: u32,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let maps = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/visibility_maps"),
            size: room_bytes(room),
            // Tests read them back.
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let layout = bind::layout(
            device,
            "dlpv/visibility_maps_layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::storage(2, cs),
                bind::storage_rw(3, cs),
                bind::storage(4, cs),
            ],
        );
        let group = bind::group(
            device,
            "dlpv/visibility_maps_group",
            &layout,
            &[
                params.as_entire_binding(),
                gather_info.as_entire_binding(),
                planes.as_entire_binding(),
                maps.as_entire_binding(),
                blocks_read.as_entire_binding(),
            ],
        );
        let pipeline = compute_pipeline_entry(
            device,
            "dlpv/visibility_maps",
            VISIBILITY_MAPS_SHADER,
            "visibility_maps",
            &[&layout],
        );
        Self { pipeline, group, maps, room }
    }

    /// Writes the maps (after the planes, before the gather).
    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(MAP_WORDS / 64, self.room, self.room * self.room);
    }
}

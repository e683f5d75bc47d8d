//! The landed photons in a hashed world-space grid (`shaders/lib/photon_grid.wgsl`): the
//! caustics of surfaces that reflected and refracted rays reach but the camera does not see,
//! where the screen-space caustic buffer has no texel (reflections spec §2.17.4).

use mrshade_core::settings::CausticsSettings;
use wgpu::util::DeviceExt;

/// Words of the grid buffer before the heads' counts (`GRID_HEADER` in photon_grid.wgsl).
pub const GRID_HEADER_WORDS: u64 = 12;
/// Header word of `splat_min`, written once (`GRID_SPLAT_MIN_WORD` in photon_grid.wgsl).
pub const GRID_SPLAT_MIN_WORD: u64 = 1;
/// Header word of the depth epsilon, written once (`GRID_EPSILON_WORD`).
pub const GRID_EPSILON_WORD: u64 = 2;
/// First header word of the photons' box (`GRID_BOX_MIN_WORD`), from which the frame's clear
/// runs through the heads' counts.
pub const GRID_BOX_MIN_WORD: u64 = 4;
/// Header word of the entries handed out (`GRID_TOTAL_WORD`), cleared with the box.
pub const GRID_TOTAL_WORD: u64 = 11;
/// Bytes of one listed photon (`GridPhoton` in photon_grid.wgsl).
pub const GRID_PHOTON_BYTES: u64 = 48;
/// Heads of the grid: 2^18 (a count and a range end each, 2 MiB), some three times the cells
/// the landed photons of a light fill at the default photon resolution (a few each).
pub const GRID_HEADS: u64 = 1 << 18;
/// Most cells a photon is listed in: three along each axis (`GRID_CELLS_PER_AXIS`).
pub const GRID_CELLS_PER_PHOTON: u64 = 27;
/// Bytes of the cells a photon was counted in (`GridCells` packed in a vec4i).
const GRID_CELLS_BYTES: u64 = 16;
/// Bytes per photon slot of the grid's buffers: the listed photon, its entries at most, the
/// cells it was counted in.
pub const GRID_BYTES_PER_SLOT: u64 = GRID_PHOTON_BYTES + GRID_CELLS_PER_PHOTON * 4 + GRID_CELLS_BYTES;
/// The largest of the grid's buffers per photon slot (its entries), for the device's binding
/// limit.
pub const GRID_ENTRY_BYTES_PER_SLOT: u64 = GRID_CELLS_PER_PHOTON * 4;
/// Workgroup size of `cs_grid_ranges` (one thread per head).
pub const GRID_RANGES_WORKGROUP: u64 = 256;

/// The grid's buffers.
pub struct PhotonGrid {
    /// Header (levels used as bits, splat_min, depth epsilon, the photons' box, the entries
    /// handed out), the heads' counts and range ends.
    pub heads: wgpu::Buffer,
    /// The listed photons, at their indices in the punctual lights' photon G-buffer.
    pub photons: wgpu::Buffer,
    /// The cells' ranges of photon indices, up to 27 entries per photon slot.
    pub entries: wgpu::Buffer,
    /// Per photon slot, the cells `cs_size` counted it in, which `cs_grid_scatter` lists it in.
    pub cells: wgpu::Buffer,
    /// Heads (a power of two; 1 in an empty grid).
    pub head_count: u64,
}

impl PhotonGrid {
    /// A grid for the `capacity` photon slots of the punctual lights, their quads sized by
    /// `settings`; with 0, an empty one that no lookup reads past its header (the resolve's
    /// binding when no photons are traced, and the probe's photon group's, which lists none).
    pub fn new(device: &wgpu::Device, capacity: u64, settings: &CausticsSettings) -> Self {
        let head_count = if capacity == 0 { 1 } else { GRID_HEADS };
        let mut words = vec![0u32; (GRID_HEADER_WORDS + 2 * head_count) as usize];
        words[GRID_SPLAT_MIN_WORD as usize] = settings.splat_min.to_bits();
        words[GRID_EPSILON_WORD as usize] = settings.depth_epsilon.to_bits();
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        Self {
            heads: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("specular/photon_grid/heads"),
                contents: bytemuck::cast_slice(&words),
                usage,
            }),
            photons: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("specular/photon_grid/photons"),
                size: capacity.max(1) * GRID_PHOTON_BYTES,
                usage,
                mapped_at_creation: false,
            }),
            entries: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("specular/photon_grid/entries"),
                size: capacity.max(1) * GRID_ENTRY_BYTES_PER_SLOT,
                usage,
                mapped_at_creation: false,
            }),
            cells: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("specular/photon_grid/cells"),
                size: capacity.max(1) * GRID_CELLS_BYTES,
                usage,
                mapped_at_creation: false,
            }),
            head_count,
        }
    }
}

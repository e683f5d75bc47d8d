//! Shadow pass: for every light, the depth of real casters and of virtual casters in separate
//! layers of one buffer (Knecht §2.7, Eq. 5.1–5.3: `V_r`, `V_v`), drawn by the compute
//! rasteriser. Inputs: geometry, the layers of `pack_lights`. Output: the layer buffer. The
//! maps depend on the geometry and the lights only: they are drawn again when either changed,
//! not for a camera that moves through a still scene, and only the layers of the kind of
//! caster that moved (a turning virtual object leaves the real-only layers as they were).

use crate::raster::{RasterViews, Rasterizer, ViewSpec};
use crate::scene_gpu::{Geometry, Moved, ShadowLayer};
use mrshade_core::settings::ShadowSettings;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;

/// The shadow pass and the maps it owns.
pub struct ShadowPass {
    views: RasterViews,
    /// All layers of all lights: `layers × resolution²` packed `u64` texels (reversed depth in
    /// the high word).
    pub maps: wgpu::Buffer,
    /// The kinds of caster the maps no longer show (all at first and after a light moved;
    /// those of the instances that moved).
    stale: Moved,
}

impl ShadowPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "shadows";

    /// Creates the maps for `layers` and their raster views.
    pub fn new(
        ctx: &GpuContext,
        rasterizer: &Rasterizer,
        geometry: &Geometry,
        layers: &[ShadowLayer],
        settings: &ShadowSettings,
    ) -> Self {
        let res = settings.resolution;
        let layer_bytes = res as u64 * res as u64 * 8;
        let maps = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadows/maps"),
            size: layer_bytes * layers.len().max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let views = rasterizer.views(ctx, geometry, "shadows", Some(&maps), &ViewSpec::of_layers(layers, res));
        Self { views, maps, stale: Moved::ALL }
    }

    /// Moves the layers' projections to `layers` (moving lights); the next frame draws them.
    pub fn set_layers(&mut self, queue: &wgpu::Queue, layers: &[ShadowLayer]) {
        self.views.set_layers(queue, layers);
        self.stale = Moved::ALL;
    }

    /// Casters of the kinds in `moved` moved or deformed: the next frame draws their layers
    /// again.
    pub fn geometry_changed(&mut self, moved: Moved) {
        self.stale = self.stale.union(moved);
    }

    /// Rasterises every layer's casters, if they changed since the last time.
    pub fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        rasterizer.record_moved(rec, Self::LABEL, [(&self.views, self.stale)]);
        self.stale = Moved::NONE;
    }
}

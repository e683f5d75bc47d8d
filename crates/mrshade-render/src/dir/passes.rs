//! The `dir` method's passes, built together because they share the VPL and ISM buffers, and
//! recorded in the order of Knecht §1.4: RSMs → VPLs → ISMs → interleaved indirect shading →
//! temporal smoothing and merge. Direct light and the composite follow in `crate::frame`.

use crate::passes::filter::{FilterPass, History};
use crate::passes::gbuffer::GBuffer;
use crate::passes::indirect::{IndirectBuffers, IndirectPass};
use crate::passes::ism::{IsmPass, IsmResources};
use crate::passes::rsm::RsmPass;
use crate::passes::vpl::VplPass;
use crate::raster::Rasterizer;
use crate::scene_gpu::{Geometry, GpuScene};
use mrshade_core::Differential;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target};
use mrshade_scene::Session;

/// Every pass of differential instant radiosity and the frame counter they share.
pub struct DirPasses {
    /// Reflective shadow maps.
    pub rsm: RsmPass,
    /// Point clouds and ISM atlases.
    pub ism_resources: IsmResources,
    /// VPL creation.
    pub vpl: VplPass,
    /// ISM splatting.
    pub ism: IsmPass,
    /// Interleaved shading output.
    pub interleaved: IndirectBuffers,
    /// Interleaved shading.
    pub indirect: IndirectPass,
    /// Temporal smoothing and merge.
    pub filter: FilterPass,
    frame: u32,
    /// Frames since anything in the scene moved.
    still_frames: u32,
}

impl DirPasses {
    /// Builds every pass for `session`.
    #[allow(clippy::too_many_arguments, reason = "the method's inputs, each a different resource")]
    pub fn new(
        ctx: &GpuContext,
        session: &Session,
        scene: &GpuScene,
        rasterizer: &Rasterizer,
        frame_uniforms: &wgpu::Buffer,
        gbuffer: &GBuffer,
        radiance: &Differential<Target>,
        internal_size: (u32, u32),
    ) -> Self {
        let settings = &session.settings.dir;
        let (center, radius) = match session.scene.bounds() {
            Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3)),
            None => (glam::Vec3::ZERO, 1.0),
        };
        let rsm = RsmPass::new(
            ctx,
            rasterizer,
            scene,
            &scene.shadow_layers,
            settings.rsm_resolution,
            session.settings.shadows.resolution,
        );
        let ism_resources = IsmResources::new(ctx, &session.scene, settings, center, radius);
        let vpl = VplPass::new(ctx, session, settings, scene, &rsm, &ism_resources, center, radius);
        let ism = IsmPass::new(ctx, &ism_resources, &scene.geometry, &vpl.vpls);
        let interleaved = IndirectBuffers::new(&ctx.device, "indirect/interleaved", internal_size);
        let indirect = IndirectPass::new(
            ctx,
            frame_uniforms,
            gbuffer,
            &scene.materials.buffer,
            &vpl.vpls,
            &ism_resources,
            settings,
            radius,
            radiance,
            &interleaved,
        );
        let filter = FilterPass::new(ctx, frame_uniforms, settings, session.exposure, gbuffer, &interleaved);
        Self { rsm, ism_resources, vpl, ism, interleaved, indirect, filter, frame: 0, still_frames: 0 }
    }

    /// Uploads this frame's counters; call before recording it.
    pub fn prepare(&mut self, queue: &wgpu::Queue, geometry: &Geometry) {
        self.vpl.prepare(queue, self.frame, geometry);
        self.ism_resources.prepare(queue, geometry.virtual_box());
        // Only instances move so far; a moving camera or light will have to count as a
        // change here too.
        self.still_frames = if geometry.moved() || self.frame == 0 { 0 } else { self.still_frames + 1 };
        let history = History { exists: self.frame > 0, moved: geometry.moved(), still_frames: self.still_frames };
        self.filter.prepare(queue, history);
    }

    /// Records the method's passes for the current frame and advances the frame counter.
    pub fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        let parity = (self.frame % 2) as usize;
        self.rsm.record(rec, rasterizer);
        self.vpl.record(rec, parity);
        self.ism.record(rec, &self.ism_resources, parity);
        self.indirect.record(rec, parity);
        self.filter.record(rec, parity);
        self.frame += 1;
    }

    /// Frames rendered so far.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// Forgets the history (next frame starts temporal smoothing afresh).
    pub fn reset(&mut self) {
        self.frame = 0;
    }
}

//! Differential instant radiosity, the `dir` method (Knecht §2.7–§2.10): its passes in the
//! order of Knecht §1.4 — RSMs → VPLs → ISMs → interleaved indirect shading → temporal
//! smoothing and merge — built together because they share the VPL and ISM buffers. It hands
//! on the merged [`IndirectLight`]; direct light and the composite follow in `crate::frame`.
//! CPU-side inputs that change only with the scene: the surface point clouds of the
//! imperfect shadow maps (`points`) and the importance pyramid of the probe
//! (`probe_pyramid`).

mod aovs;
pub mod filter;
pub mod indirect;
pub mod ism;
mod limits;
mod points;
mod probe_pyramid;
use super::rsm;
pub mod vpl;

pub use aovs::IsmDepths;
pub(crate) use limits::{estimate, fit};
pub use points::{GpuPoint, PointAnchor, PointCloud};
pub use probe_pyramid::ProbePyramid;

use super::{AovView, FrameChange, IndirectLight, LightTransport, MethodInputs, PointLight};
use crate::outputs::Aov;
use crate::raster::Rasterizer;
use crate::scene_gpu::Moved;
use anyhow::Result;
use filter::{FilterPass, History};
use indirect::IndirectPass;
use ism::{IsmPass, IsmResources};
use mrshade_core::settings::BounceMethod;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;
use rsm::RsmPass;
use vpl::VplPass;

/// Every pass of differential instant radiosity and the frame counter they share.
pub struct DirMethod {
    /// Reflective shadow maps.
    pub rsm: RsmPass,
    /// Point clouds and ISM atlases.
    pub ism_resources: IsmResources,
    /// VPL creation.
    pub vpl: VplPass,
    /// ISM splatting.
    pub ism: IsmPass,
    /// Interleaved shading output.
    pub interleaved: IndirectLight,
    /// Interleaved shading.
    pub indirect: IndirectPass,
    /// Temporal smoothing and merge.
    pub filter: FilterPass,
    /// Frame counter: seeds the VPLs' sampling and picks the double buffers' parity.
    frame: u32,
    /// Frames rendered since the history was last forgotten.
    rendered: u32,
    /// Frames since anything in the scene moved.
    still_frames: u32,
    /// Whether this frame's points on deformed instances must follow them.
    follow_points: bool,
    /// The kinds of caster the RSMs no longer show (all at first and after a light moved).
    rsm_stale: Moved,
    /// Lower bound of the VPL–receiver distance (m): `clamp_distance` × the scene's radius.
    d_min: f32,
    /// The interleave factor I (`dir.interleave`).
    interleave: u32,
}

impl DirMethod {
    /// The interleave factor I its passes were built with.
    pub fn interleave(&self) -> u32 {
        self.interleave
    }
}

/// Builds every pass of the method (the registry's `build`).
pub(crate) fn build(inputs: &MethodInputs) -> Box<dyn LightTransport> {
    Box::new(DirMethod::new(inputs))
}

impl DirMethod {
    /// Builds every pass for the session of `inputs`.
    pub fn new(inputs: &MethodInputs) -> Self {
        let MethodInputs {
            ctx,
            session,
            scene,
            rasterizer,
            frame_uniforms,
            gbuffer,
            radiance,
            internal_size,
            light_photons,
            ..
        } = *inputs;
        let settings = &session.settings.dir;
        let (center, radius) = match session.scene.bounds() {
            Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3)),
            None => (glam::Vec3::ZERO, 1.0),
        };
        let rsm = RsmPass::new(
            ctx,
            rasterizer,
            scene,
            &scene.lights,
            &scene.shadow_layers,
            settings.rsm_resolution,
            session.settings.shadows.resolution,
            light_photons.is_some(),
        );
        let ism_resources = IsmResources::new(ctx, &session.scene, &scene.geometry, settings, center, radius);
        let vpl = VplPass::new(ctx, session, settings, scene, &rsm, &ism_resources, light_photons, center, radius);
        let ism = IsmPass::new(ctx, &ism_resources, &scene.geometry, &vpl.vpls);
        let d_min = settings.clamp_distance * radius;
        let interleaved = IndirectLight::new(&ctx.device, "indirect/interleaved", internal_size);
        let filter = FilterPass::new(ctx, frame_uniforms, settings, session.exposure, gbuffer, &interleaved);
        let indirect = IndirectPass::new(
            ctx,
            frame_uniforms,
            gbuffer,
            &scene.materials.buffer,
            &vpl.vpls,
            &ism_resources,
            settings,
            session.settings.probe_caustics(),
            d_min,
            // Without the multiple-bounce source, light is reflected once: nothing to gather.
            if settings.bounce == BounceMethod::Off { 0.0 } else { settings.near_field_radius * radius },
            radiance,
            // The merged light is still the previous frame's when the interleaved pass reads it.
            &filter.merged.light,
            &interleaved,
        );
        Self {
            rsm,
            ism_resources,
            vpl,
            ism,
            interleaved,
            indirect,
            filter,
            frame: 0,
            rendered: 0,
            still_frames: 0,
            follow_points: false,
            rsm_stale: Moved::ALL,
            d_min,
            interleave: settings.interleave,
        }
    }

    /// Frames rendered so far.
    pub fn frame(&self) -> u32 {
        self.frame
    }
}

impl LightTransport for DirMethod {
    fn prepare(&mut self, queue: &wgpu::Queue, change: &FrameChange) {
        if let Some(layers) = change.moved_light_layers {
            self.rsm.set_layers(queue, layers);
        }
        self.vpl.prepare(queue, self.frame, change.geometry);
        self.ism_resources.prepare(queue, change.geometry.virtual_box());
        // Light in the world changes when geometry or a light moves; a moving camera only
        // reprojects the history (the temporal step's disocclusion tests handle what it
        // newly sees).
        self.follow_points = change.vertices_deformed;
        let light_changed = change.geometry_moved || change.moved_light_layers.is_some();
        // The RSMs see the scene from the lights: only where the geometry or a light moved
        // do they change (a camera moving through a still scene keeps them).
        self.rsm_stale = self.rsm_stale.union(match change.moved_light_layers {
            Some(_) => Moved::ALL,
            None => change.geometry.moved_casters(),
        });
        self.still_frames = if light_changed || self.rendered == 0 { 0 } else { self.still_frames + 1 };
        let history = History {
            exists: self.rendered > 0,
            moved: light_changed,
            camera_moved: change.camera_moved,
            still_frames: self.still_frames,
        };
        self.filter.prepare(queue, history);
    }

    fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        let parity = (self.frame % 2) as usize;
        if std::mem::take(&mut self.follow_points) {
            self.ism_resources.record_follow(rec);
        }
        // Draws nothing where nothing moved.
        self.rsm.record(rec, rasterizer, std::mem::take(&mut self.rsm_stale));
        // The ISM atlases' clear runs beside the VPLs' last dispatch (a few hundred
        // workgroups that leave the GPU room): at the start of the ISM pass it took 0.03 ms.
        self.vpl.record(rec, parity, &self.ism.clear);
        self.ism.record(rec, parity);
        self.indirect.record(rec, parity);
        self.filter.record(rec, parity);
        self.frame += 1;
        self.rendered += 1;
    }

    fn indirect(&self) -> Option<&IndirectLight> {
        Some(&self.filter.merged)
    }

    fn point_light(&self) -> Option<PointLight<'_>> {
        Some(PointLight {
            vpls: &self.vpl.vpls,
            // `record` wrote the VPLs of parity (frame − 1) mod 2 and counted the frame.
            parity: (self.frame.wrapping_add(1) % 2) as usize,
            ism_params: &self.ism_resources.params_buffer,
            ism_real: &self.ism_resources.atlas_real,
            ism_virtual: &self.ism_resources.atlas_virtual,
            count: self.ism_resources.params.tile.z,
            d_min: self.d_min,
            stride: self.interleave,
        })
    }

    fn read_aovs(&self, ctx: &GpuContext, view: &AovView) -> Result<Vec<Aov>> {
        self.aovs(ctx, view)
    }

    fn seek(&mut self, frame: u32) {
        self.frame = frame;
        self.rendered = 0;
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

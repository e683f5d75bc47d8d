//! The seam between the frame and its light-transport methods (Knecht §1.4, step 3: "compute
//! `L_rv` and `L_r` from the same paths").
//!
//! A method is one folder here and one entry in [`REGISTRY`]: it is built from the scene and
//! its own typed settings ([`MethodInputs`]), fits itself to the device's limits before
//! anything is allocated ([`Entry::fit`], [`Entry::estimate`]), is prepared per frame from the
//! frame's inputs ([`LightTransport::prepare`]), records its passes
//! ([`LightTransport::record`]), hands on what the stages after it read ([`IndirectLight`])
//! and reports its AOVs. The frame holds the chosen method as one `Box<dyn LightTransport>`.
//!
//! Adding a method: a variant of `mrshade_core::settings::Method` (its name, description and
//! default still frames live there), a folder here, and one [`Entry`] below. The CLI's
//! choices, `eval`, the invariant and golden tests and `./dev benchmark` loop over
//! `Method::ALL`.

pub mod around;
pub mod dir;
mod direct;
pub mod dlpv;
pub mod dvct;
mod indirect_light;
pub mod probe_maps;
pub mod rsm;

pub use indirect_light::{FORMAT as INDIRECT_FORMAT, IndirectLight, PointLight, TARGETS as INDIRECT_TARGETS};

use crate::limits::Fit;
use crate::outputs::{Aov, Composite};
use crate::passes::gbuffer::GBuffer;
use crate::raster::Rasterizer;
use crate::scene_gpu::{Geometry, GpuScene, ShadowLayer};
use anyhow::Result;
use mrshade_core::Differential;
use mrshade_core::settings::{Method, RenderSettings};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target};
use mrshade_scene::Session;

/// What every method is built from: the session and the resources the frame shares.
#[derive(Clone, Copy)]
pub struct MethodInputs<'a> {
    /// The GPU.
    pub ctx: &'a GpuContext,
    /// The session (scene, settings fitted to the device).
    pub session: &'a Session,
    /// The scene on the GPU.
    pub scene: &'a GpuScene,
    /// The compute rasteriser the frame's views share.
    pub rasterizer: &'a Rasterizer,
    /// The frame's uniform buffer (`Frame` in shaders/lib/frame.wgsl).
    pub frame_uniforms: &'a wgpu::Buffer,
    /// The punctual lights' shadow maps (`crate::passes::shadow::ShadowPass::maps`), drawn
    /// before the method's passes.
    pub shadow_maps: &'a wgpu::Buffer,
    /// The G-buffer of the frame's camera.
    pub gbuffer: &'a GBuffer,
    /// Where the frame's shading writes `L_rv` and `L_r`.
    pub radiance: &'a Differential<Target>,
    /// Internal shading size.
    pub internal_size: (u32, u32),
    /// The punctual lights' photons (the specular stage's caustics), if they shoot any: `dir`
    /// turns them into caustic VPLs (reflections spec §2.18).
    pub light_photons: Option<&'a crate::specular::caustics::LightPhotons>,
    /// The photo (linear camera values at the output size), the real surfaces' measured light.
    pub photo: &'a Target,
}

/// What changed since the previous frame, for a method's per-frame preparation.
pub struct FrameChange<'a> {
    /// The scene's geometry with this frame's transforms uploaded.
    pub geometry: &'a Geometry,
    /// Whether an instance moved.
    pub geometry_moved: bool,
    /// Whether the deformation pass moves vertices this frame (skinned or morphing
    /// instances changed pose).
    pub vertices_deformed: bool,
    /// The lights' shadow layers when a light moved (their RSMs must follow); `None` otherwise.
    pub moved_light_layers: Option<&'a [ShadowLayer]>,
    /// Whether the camera moved (history is reprojected; light in the world did not change).
    pub camera_moved: bool,
    /// Whether a new photo was uploaded for this frame.
    pub photo_changed: bool,
}

/// What a method's AOVs are drawn with.
pub struct AovView<'a> {
    /// The frame's composite.
    pub composite: &'a Composite,
    /// The camera's `clip_from_world` (VPLs are drawn over the image).
    pub clip_from_world: glam::Mat4,
    /// Linear camera value per unit radiance.
    pub exposure: f32,
    /// Internal shading size.
    pub internal_size: (u32, u32),
}

/// One light-transport method behind the seam.
pub trait LightTransport {
    /// Uploads this frame's per-frame data; called before [`LightTransport::record`].
    fn prepare(&mut self, queue: &wgpu::Queue, change: &FrameChange);
    /// Records the method's passes into the frame (after the G-buffer, before direct light).
    fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer);
    /// The indirect light direct lighting adds, if the method computes any.
    fn indirect(&self) -> Option<&IndirectLight>;
    /// The method's light at any surface point (for the surfaces reflections and
    /// refractions reach), if it has more than the punctual lights and the probe (by
    /// default it has not).
    fn point_light(&self) -> Option<PointLight<'_>> {
        None
    }
    /// The method's own AOVs, read back after a frame (by default none).
    fn read_aovs(&self, _ctx: &GpuContext, _view: &AovView) -> Result<Vec<Aov>> {
        Ok(Vec::new())
    }
    /// Forgets the temporal history and numbers the next frame `frame` (its sampling seed):
    /// a range of a sequence rendered on its own then draws the same samples per frame as
    /// the whole run. By default nothing: a method without history or per-frame samples.
    fn seek(&mut self, _frame: u32) {}
    /// The concrete method, for tests and AOVs that read its private buffers.
    fn as_any(&self) -> &dyn std::any::Any;
}

/// Group 0 of a method's per-pixel pass (as the pass's WGSL declares it, read through
/// shaders/lib/gbuffer_pixel.wgsl): the frame's uniform, the pass's own uniform `params`, the
/// camera G-buffer's depth, albedo/metallic, normal/roughness, specular and flag targets, and
/// the materials.
pub(crate) fn pixel_inputs(
    device: &wgpu::Device,
    label: &str,
    frame_uniforms: &wgpu::Buffer,
    params: &wgpu::Buffer,
    gbuffer: &GBuffer,
    materials: &wgpu::Buffer,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    use mrshade_gpu::bind;
    let cs = wgpu::ShaderStages::COMPUTE;
    let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
    let d2 = wgpu::TextureViewDimension::D2;
    let layout = bind::layout(
        device,
        &format!("{label}_layout"),
        &[
            bind::uniform(0, cs),
            bind::uniform(1, cs),
            bind::texture(2, cs, unfilterable, d2),
            bind::texture(3, cs, unfilterable, d2),
            bind::texture(4, cs, unfilterable, d2),
            bind::texture(5, cs, unfilterable, d2),
            bind::texture(6, cs, wgpu::TextureSampleType::Uint, d2),
            bind::storage(7, cs),
        ],
    );
    use wgpu::BindingResource::TextureView;
    let group = bind::group(
        device,
        &format!("{label}_group"),
        &layout,
        &[
            frame_uniforms.as_entire_binding(),
            params.as_entire_binding(),
            TextureView(&gbuffer.depth_motion.view),
            TextureView(&gbuffer.albedo_metallic.view),
            TextureView(&gbuffer.normal_roughness.view),
            TextureView(&gbuffer.specular.view),
            TextureView(&gbuffer.flags.view),
            materials.as_entire_binding(),
        ],
    );
    (layout, group)
}

/// A method's entry in the registry.
pub struct Entry {
    /// Which method.
    pub method: Method,
    /// Builds its passes.
    pub build: fn(&MethodInputs) -> Box<dyn LightTransport>,
    /// Shrinks its settings to the device (with warnings), or says why it cannot render there.
    pub fit: fn(&mut RenderSettings, &mut Fit) -> Result<()>,
    /// Its GPU memory beyond the frame's shared targets, item by item, for `internal_pixels`
    /// shading samples and `shadow_layers` light layers.
    pub estimate: fn(&RenderSettings, u64, u64) -> Vec<(&'static str, u64)>,
}

/// Every method the renderer has; the only place a method is matched to its code.
pub const REGISTRY: &[Entry] = &[
    Entry { method: Method::Dir, build: dir::build, fit: dir::fit, estimate: dir::estimate },
    Entry { method: Method::Direct, build: direct::build, fit: direct::fit, estimate: direct::estimate },
    Entry { method: Method::Dvct, build: dvct::build, fit: dvct::fit, estimate: dvct::estimate },
    Entry { method: Method::Dlpv, build: dlpv::build, fit: dlpv::fit, estimate: dlpv::estimate },
];

/// The registry entry of `method`.
pub fn entry(method: Method) -> &'static Entry {
    REGISTRY.iter().find(|e| e.method == method).expect("every Method has a REGISTRY entry (tested)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_has_one_entry() {
        for m in Method::ALL {
            assert_eq!(REGISTRY.iter().filter(|e| e.method == *m).count(), 1, "{}", m.name());
        }
        assert_eq!(REGISTRY.len(), Method::ALL.len());
    }
}

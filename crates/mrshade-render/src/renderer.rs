//! The renderer of one session: GPU scene, passes and targets, built once; frames are then
//! rendered from per-frame inputs (`crate::frame`).

use crate::methods::{LightTransport, MethodInputs};
use crate::passes::composite::{CompositePass, CompositeTargets};
use crate::passes::deform::DeformPass;
use crate::passes::direct::{DirectPass, radiance_targets};
use crate::passes::gbuffer::{GBuffer, GBufferPass};
use crate::passes::probe_sh::ProbeShPass;
use crate::passes::shadow::ShadowPass;
use crate::passes::upload::{PackedPhoto, PhotoUpload};
use crate::raster::Rasterizer;
use crate::scene_gpu::GpuScene;
use crate::specular::{SpecularInputs, SpecularStage};
use crate::uniforms::FrameUniforms;
use anyhow::Result;
use mrshade_core::Differential;
use mrshade_core::camera::CameraView;
use mrshade_core::settings::VirtualShading;
use mrshade_gpu::{GpuContext, Target};
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

/// Everything needed to render frames of one session.
pub struct Renderer {
    pub(crate) uniforms: FrameUniforms,
    pub(crate) frame_buffer: wgpu::Buffer,
    /// Frames rendered so far.
    pub(crate) frame_index: u32,
    /// The camera of the last frame, without sub-pixel jitter (`None` before the first).
    pub(crate) previous_clip_from_world: Option<glam::Mat4>,
    /// The session's own camera and photo: what a frame without inputs of its own shows.
    pub(crate) session_camera: CameraView,
    pub(crate) scene: GpuScene,
    pub(crate) rasterizer: Rasterizer,
    pub(crate) shadows: ShadowPass,
    /// Skinning and morphing (`None` when nothing in the scene deforms).
    pub(crate) deform: Option<crate::passes::deform::DeformPass>,
    pub(crate) gbuffer: GBuffer,
    pub(crate) gbuffer_pass: GBufferPass,
    /// The light-transport method (the only place the frame holds it).
    pub(crate) method: Box<dyn LightTransport>,
    pub(crate) radiance: Differential<Target>,
    /// The probe's SH coefficients (`None` unless `[ibl] virtual` reads them).
    pub(crate) probe_sh: Option<ProbeShPass>,
    /// PRT irradiance of rigid virtual objects (`[ibl] virtual = "prt"`).
    pub(crate) prt: Option<crate::prt::PrtPass>,
    pub(crate) direct: DirectPass,
    /// Reflections and refractions (`None` when the scene has nothing it traces).
    pub(crate) specular: Option<SpecularStage>,
    /// The specular stage's light, in camera values (zero where nothing is traced).
    pub(crate) specular_light: Target,
    pub(crate) photo: PhotoUpload,
    pub(crate) composite_targets: CompositeTargets,
    pub(crate) composite: CompositePass,
    /// Settings this device could not honour, and what was used instead.
    pub warnings: Vec<String>,
    /// Record the specular rays as passes of their own instead of beside the method's
    /// shading (`mrshade bench --serial`: a time per pass; the same image).
    pub serial_passes: bool,
}

impl Renderer {
    /// Uploads `session` and builds every pass. GPU errors become `Err`.
    pub fn new(ctx: &GpuContext, session: &Session) -> Result<Self> {
        let device_limits = crate::limits::DeviceLimits::from(&ctx.device.limits());
        let (settings, output, warnings) = crate::limits::fit_to_device(session, device_limits)?;
        let fitted;
        let session = if warnings.is_empty() {
            session
        } else {
            fitted = Session { settings, output, ..session.clone() };
            &fitted
        };
        let mut renderer = ctx.checked("creating the renderer", || Ok(Self::build(ctx, session)))?;
        renderer.warnings.extend(warnings);
        Ok(renderer)
    }

    /// A renderer for stills of `session` (frames of one view averaged into one image, as
    /// `render_still` does): the session's settings for stills ([`RenderSettings::for_still`]).
    ///
    /// [`RenderSettings::for_still`]: mrshade_core::settings::RenderSettings::for_still
    pub fn for_still(ctx: &GpuContext, session: &Session) -> Result<Self> {
        let settings = session.settings.for_still();
        if settings == session.settings {
            return Self::new(ctx, session);
        }
        Self::new(ctx, &Session { settings, ..session.clone() })
    }

    /// Moves instance `index` of the session's scene (takes effect at the next frame).
    pub fn set_instance_transform(&mut self, index: usize, world_from_object: glam::Mat4) {
        self.scene.geometry.set_transform(index, world_from_object);
    }

    /// Instance `index`'s world transform.
    pub fn instance_transform(&self, index: usize) -> glam::Mat4 {
        self.scene.geometry.transform(index)
    }

    /// Whether the specular stage runs (the scene holds a material it traces and it is on).
    pub fn specular_traced(&self) -> bool {
        self.specular.is_some()
    }

    /// The light-transport method as its concrete type (`None` if another method runs).
    pub fn method_as<T: 'static>(&self) -> Option<&T> {
        self.method.as_any().downcast_ref()
    }

    fn build(ctx: &GpuContext, session: &Session) -> Self {
        let device = &ctx.device;
        let mut scene = GpuScene::new(device, &ctx.queue, session);
        let mut deform = DeformPass::new(ctx, &session.scene, &scene.geometry.base_vertex, &scene.geometry.vertices);
        if let Some(deform) = &mut deform {
            for (instance, object_box) in deform.update(&ctx.queue, &session.scene.rest_pose().deformations) {
                scene.geometry.set_deformed_box(instance, object_box);
            }
        }
        let session_camera = session.view_at(0);
        let uniforms = FrameUniforms::new(session, &session_camera, scene.light_count, scene.probe.radiance_mips);
        let frame = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame/uniforms"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let mut photo = PhotoUpload::new(ctx, uniforms.output_size());
        photo.write(&ctx.queue, &PackedPhoto::new(&session.background, uniforms.output_size()));
        let settings = &session.settings;
        let internal = uniforms.internal_size();

        let rasterizer = Rasterizer::new(ctx, &scene.geometry);
        let shadows = ShadowPass::new(ctx, &rasterizer, &scene.geometry, &scene.shadow_layers, &settings.shadows);
        let gbuffer = GBuffer::new(device, internal);
        let gbuffer_pass =
            GBufferPass::new(ctx, &frame, &uniforms, &rasterizer, &scene.geometry, &scene.materials, &gbuffer);
        let radiance = radiance_targets(device, internal);
        // The punctual lights' photons: the specular stage traces them, `dir` places caustic
        // VPLs where they landed.
        let light_photons = crate::specular::caustics::LightPhotons::new(ctx, session);
        let method = (crate::methods::entry(settings.method).build)(&MethodInputs {
            ctx,
            session,
            scene: &scene,
            rasterizer: &rasterizer,
            frame_uniforms: &frame,
            shadow_maps: &shadows.maps,
            gbuffer: &gbuffer,
            radiance: &radiance,
            internal_size: internal,
            light_photons: light_photons.as_ref(),
            photo: &photo.photo,
        });
        let shading = settings.ibl.virtual_shading;
        // SH coefficients of the probe's projection: PRT's 9 or 16, else the 9 of irradiance.
        let coefficients = match shading {
            VirtualShading::Prt => settings.ibl.prt_coefficients as usize,
            _ => 9,
        };
        let transfer = (shading == VirtualShading::Prt)
            .then(|| crate::prt::Transfer::of(session, &scene.geometry, settings.ibl.prt_samples, coefficients));
        let prt_instances = transfer.as_ref().map_or(&[][..], |t| &t.instances[..]);
        let probe_sh =
            ProbeShPass::new(ctx, &scene.probe, &frame, &scene.geometry.instances, prt_instances, coefficients);
        let prt = transfer.as_ref().map(|t| {
            let visibility = &gbuffer_pass.camera.target;
            crate::prt::PrtPass::new(ctx, &frame, visibility, &scene.geometry, t, &probe_sh, internal)
        });
        let direct = DirectPass::new(
            ctx,
            &frame,
            &settings.shadows,
            &gbuffer,
            &scene,
            &shadows,
            method.indirect(),
            &radiance,
            (&settings.ibl, &probe_sh, prt.as_ref().map(|p| &p.irradiance)),
        );
        let probe_sh = (shading != VirtualShading::Prefiltered).then_some(probe_sh);
        let specular_light = Target::new_2d(
            device,
            "specular/light",
            internal,
            wgpu::TextureFormat::Rgba16Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
        );
        let composite_targets = CompositeTargets::new(device, uniforms.output_size());
        let composite = CompositePass::new(
            ctx,
            &frame,
            &settings.composite,
            &radiance,
            &gbuffer.flags,
            &photo.photo,
            &specular_light,
            &composite_targets,
        );
        let specular = SpecularStage::new(&SpecularInputs {
            ctx,
            scene: &session.scene,
            settings,
            frame: &frame,
            uniforms: &uniforms,
            gpu_scene: &scene,
            shadow_maps: &shadows.maps,
            rasterizer: &rasterizer,
            gbuffer: &gbuffer,
            camera_visibility: &gbuffer_pass.camera.target,
            radiance: &radiance,
            point_light: method.point_light(),
            light_photons: light_photons.as_ref(),
            photo: &photo.photo,
            composite_params: &composite.params,
            output: &specular_light,
        });
        Self {
            uniforms,
            frame_buffer: frame,
            frame_index: 0,
            previous_clip_from_world: None,
            session_camera,
            scene,
            rasterizer,
            shadows,
            deform,
            gbuffer,
            gbuffer_pass,
            method,
            radiance,
            probe_sh,
            prt,
            direct,
            specular,
            specular_light,
            photo,
            composite_targets,
            composite,
            warnings: transfer.map(|t| t.warnings).unwrap_or_default(),
            serial_passes: false,
        }
    }

    /// Output size (width, height).
    pub fn output_size(&self) -> (u32, u32) {
        self.uniforms.output_size()
    }

    /// Internal shading size (output × supersampling).
    pub fn internal_size(&self) -> (u32, u32) {
        self.uniforms.internal_size()
    }

    /// Bytes one photo upload moves to the GPU.
    pub fn photo_upload_bytes(&self) -> u64 {
        self.photo.bytes()
    }

    /// The session's exposure.
    pub fn exposure(&self) -> f32 {
        self.uniforms.exposure_env.x
    }
}

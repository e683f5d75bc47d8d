//! The renderer of one session: GPU scene, passes and targets, created once.

use crate::dir::DirPasses;
use crate::passes::composite::{CompositePass, CompositeTargets};
use crate::passes::direct::{DirectPass, radiance_targets};
use crate::passes::gbuffer::{GBuffer, GBufferPass};
use crate::passes::shadow::ShadowPass;
use crate::raster::Rasterizer;
use crate::scene_gpu::GpuScene;
use crate::uniforms::FrameUniforms;
use anyhow::Result;
use mrshade_core::Differential;
use mrshade_core::settings::{Method, RenderSettings};
use mrshade_gpu::{GpuContext, Target};
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

/// Everything needed to render frames of one session.
pub struct Renderer {
    pub(crate) uniforms: FrameUniforms,
    /// The camera's `clip_from_world` without the sub-pixel jitter of still images.
    pub(crate) camera_clip_from_world: glam::Mat4,
    pub(crate) frame_buffer: wgpu::Buffer,
    /// Frames rendered so far.
    pub(crate) frame_index: u32,
    pub(crate) settings: RenderSettings,
    pub(crate) scene: GpuScene,
    pub(crate) rasterizer: Rasterizer,
    pub(crate) shadows: ShadowPass,
    pub(crate) gbuffer: GBuffer,
    pub(crate) gbuffer_pass: GBufferPass,
    pub(crate) dir: Option<DirPasses>,
    pub(crate) radiance: Differential<Target>,
    pub(crate) direct: DirectPass,
    pub(crate) composite_targets: CompositeTargets,
    pub(crate) composite: CompositePass,
    /// Settings this device could not honour, and what was used instead.
    pub warnings: Vec<String>,
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
        renderer.warnings = warnings;
        Ok(renderer)
    }

    /// Moves instance `index` of the session's scene (takes effect at the next frame).
    pub fn set_instance_transform(&mut self, index: usize, world_from_object: glam::Mat4) {
        self.scene.geometry.set_transform(index, world_from_object);
    }

    /// Instance `index`'s world transform.
    pub fn instance_transform(&self, index: usize) -> glam::Mat4 {
        self.scene.geometry.transform(index)
    }

    fn build(ctx: &GpuContext, session: &Session) -> Self {
        let device = &ctx.device;
        let scene = GpuScene::new(device, &ctx.queue, session);
        let uniforms = FrameUniforms::new(session, scene.light_count, scene.probe.radiance_mips);
        let frame = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame/uniforms"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let photo = upload_photo(ctx, session);
        let settings = session.settings.clone();
        let internal = uniforms.internal_size();

        let rasterizer = Rasterizer::new(ctx, &scene.geometry);
        let shadows = ShadowPass::new(ctx, &rasterizer, &scene.geometry, &scene.shadow_layers, &settings.shadows);
        let gbuffer = GBuffer::new(device, internal);
        let gbuffer_pass =
            GBufferPass::new(ctx, &frame, &uniforms, &rasterizer, &scene.geometry, &scene.materials, &gbuffer);
        let radiance = radiance_targets(device, internal);
        let dir = (settings.method == Method::Dir)
            .then(|| DirPasses::new(ctx, session, &scene, &rasterizer, &frame, &gbuffer, &radiance, internal));
        let indirect = dir.as_ref().map(|d| &d.filter.merged);
        let direct = DirectPass::new(ctx, &frame, &settings.shadows, &gbuffer, &scene, &shadows, indirect, &radiance);
        let composite_targets = CompositeTargets::new(device, uniforms.output_size());
        let composite =
            CompositePass::new(ctx, &frame, &settings.composite, &radiance, &gbuffer.flags, &photo, &composite_targets);
        Self {
            camera_clip_from_world: uniforms.clip_from_world,
            uniforms,
            frame_buffer: frame,
            frame_index: 0,
            settings,
            scene,
            rasterizer,
            shadows,
            gbuffer,
            gbuffer_pass,
            dir,
            radiance,
            direct,
            composite_targets,
            composite,
            warnings: Vec::new(),
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

    /// The session's exposure.
    pub fn exposure(&self) -> f32 {
        self.uniforms.exposure_env.x
    }
}

/// The photo as linear `Rgba32Float` (exact: decoded on the CPU from the 8-bit table).
fn upload_photo(ctx: &GpuContext, session: &Session) -> Target {
    let bg = &session.background;
    let target = Target::new_2d(
        &ctx.device,
        "composite/photo",
        (bg.width, bg.height),
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let texels: Vec<f32> = bg.pixels.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).collect();
    mrshade_gpu::texture::write_level(
        &ctx.queue,
        &target.texture,
        0,
        (bg.width, bg.height),
        16,
        bytemuck::cast_slice(&texels),
    );
    target
}

//! Composite pass (TVCG Eq. 1–2, Debevec 1998): adds `L_rv − L_r` to the photo on real
//! pixels (α-scaled by default) and shows `L_rv` on virtual ones, in linear camera values.
//! Inputs: `Differential { rv, r }`, G-buffer flags, the photo. Outputs: the composite
//! (linear, with virtual coverage in alpha) and the α image.

use mrshade_core::Differential;
use mrshade_core::settings::{CompositeMode, CompositeSettings};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// The composite's outputs, at output resolution.
pub struct CompositeTargets {
    /// Linear camera value (rgb) and virtual coverage (a), `Rgba32Float`.
    pub composite: Target,
    /// α per channel, `Rgba16Float`.
    pub alpha: Target,
}

impl CompositeTargets {
    /// Allocates the outputs at `size`.
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let usage =
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING;
        Self {
            composite: Target::new_2d(device, "composite/output", size, wgpu::TextureFormat::Rgba32Float, usage),
            alpha: Target::new_2d(device, "composite/alpha", size, wgpu::TextureFormat::Rgba16Float, usage),
        }
    }
}

/// The composite pass.
pub struct CompositePass {
    /// `CompositeParams` of shaders/lib/alpha.wgsl (the specular stage computes α too).
    pub params: wgpu::Buffer,
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl CompositePass {
    /// GPU timing label.
    pub const LABEL: &'static str = "composite";

    /// Binds radiance, flags, photo and the specular stage's light; writes `targets`.
    #[allow(clippy::too_many_arguments, reason = "the pass's inputs, each a different resource")]
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        settings: &CompositeSettings,
        radiance: &Differential<Target>,
        flags: &Target,
        photo: &Target,
        specular: &Target,
        targets: &CompositeTargets,
    ) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let mode = if settings.mode == CompositeMode::AlphaScaled { 1.0f32 } else { 0.0 };
        let params = [mode, settings.alpha_epsilon, settings.alpha_max, 0.0];
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("composite/params"),
            contents: bytemuck::cast_slice(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let layout = bind::layout(
            device,
            "composite/layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::texture(2, cs, unfilterable, d2),
                bind::texture(3, cs, unfilterable, d2),
                bind::texture(4, cs, wgpu::TextureSampleType::Uint, d2),
                bind::texture(5, cs, unfilterable, d2),
                bind::storage_texture(6, wgpu::TextureFormat::Rgba32Float),
                bind::storage_texture(7, wgpu::TextureFormat::Rgba16Float),
                bind::texture(8, cs, unfilterable, d2),
            ],
        );
        use wgpu::BindingResource::TextureView;
        let group = bind::group(
            device,
            "composite/group",
            &layout,
            &[
                frame.as_entire_binding(),
                params.as_entire_binding(),
                TextureView(&radiance.rv.view),
                TextureView(&radiance.r.view),
                TextureView(&flags.view),
                TextureView(&photo.view),
                TextureView(&targets.composite.view),
                TextureView(&targets.alpha.view),
                TextureView(&specular.view),
            ],
        );
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, "composite", SHADER, &[&layout]);
        Self { params, pipeline, group, size: targets.composite.size() }
    }

    /// Composites every output pixel.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/alpha.wgsl",
    "composite.wgsl",
);

//! Shadow pass: renders, for every light, the depth of real casters and of virtual casters
//! into separate layers of one depth array (Knecht §2.7, Eq. 5.1–5.3: `V_r`, `V_v`).
//! Inputs: geometry, the layers of `pack_lights`. Output: the depth array and its sampler.

use crate::scene_gpu::{Geometry, ShadowLayer, Vertex};
use mrshade_core::settings::ShadowSettings;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// Format of every shadow map.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The shadow pass and the maps it owns.
pub struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    layers: Vec<ShadowLayer>,
    layer_views: Vec<wgpu::TextureView>,
    uniform_stride: u32,
    /// All layers of all lights.
    pub maps: Target,
    /// Comparison sampler for `textureSampleCompareLevel` (reversed depth: lit if ≥).
    pub sampler: wgpu::Sampler,
}

impl ShadowPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "shadows";

    /// Creates the maps for `layers` and the pipeline that fills them.
    pub fn new(ctx: &GpuContext, geometry: &Geometry, layers: Vec<ShadowLayer>, settings: &ShadowSettings) -> Self {
        let device = &ctx.device;
        let res = settings.resolution;
        let maps = Target::new_array(
            device,
            "shadows/maps",
            (res, res, layers.len().max(1) as u32),
            SHADOW_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let layer_views = (0..layers.len() as u32).map(|l| maps.layer_view(l)).collect();

        // One clip_from_world per layer at dynamic-offset-aligned strides.
        let uniform_stride = device.limits().min_uniform_buffer_offset_alignment.max(64);
        let mut bytes = vec![0u8; uniform_stride as usize * layers.len().max(1)];
        for (i, layer) in layers.iter().enumerate() {
            let at = i * uniform_stride as usize;
            bytes[at..at + 64].copy_from_slice(bytemuck::bytes_of(&layer.clip_from_world));
        }
        let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shadows/layer_matrices"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let layout = bind::layout(
            device,
            "shadows/layout",
            &[bind::uniform_dynamic(0, wgpu::ShaderStages::VERTEX), bind::storage(1, wgpu::ShaderStages::VERTEX)],
        );
        let bind_group = bind::group(
            device,
            "shadows/bind_group",
            &layout,
            &[
                wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &uniforms,
                    offset: 0,
                    size: wgpu::BufferSize::new(64),
                }),
                geometry.instances.as_entire_binding(),
            ],
        );
        let module = mrshade_gpu::shader::create_module(device, "shadows/shader", SHADER);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadows/pipeline_layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadows/pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(Vertex::LAYOUT)],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                // Reversed depth: pushing casters away from the light lowers their depth.
                bias: wgpu::DepthBiasState {
                    constant: -settings.depth_bias,
                    slope_scale: -settings.slope_bias,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadows/compare_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::GreaterEqual),
            ..Default::default()
        });
        Self { pipeline, bind_group, layers, layer_views, uniform_stride, maps, sampler }
    }

    /// Renders every layer's casters.
    pub fn record(&self, rec: &mut Recorder, geometry: &Geometry) {
        for (i, (layer, view)) in self.layers.iter().zip(&self.layer_views).enumerate() {
            let depth = wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            };
            rec.render(Self::LABEL, &[], Some(depth), |pass| {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[i as u32 * self.uniform_stride]);
                geometry.draw(pass, geometry.draws.iter().filter(|d| d.realness == layer.casters));
            });
        }
    }
}

/// The WGSL module.
pub const SHADER: &str = wgsl!("../../../shaders/lib/instance.wgsl", "shadow.wgsl");

//! G-buffer pass (Knecht §2.12): rasterises real and virtual geometry from the camera into
//! depth, albedo/metallic, normal/roughness, specular (dielectric F0/F90),
//! emission/occlusion and a flag word (covered, real, material index).

use crate::scene_gpu::{Geometry, GpuMaterials, Vertex};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};

/// The G-buffer targets, at the internal (shading) resolution.
pub struct GBuffer {
    /// Reversed depth (1 = near plane, 0 = nothing).
    pub depth: Target,
    /// Base color (sRGB storage, linear when read), metallic in alpha.
    pub albedo_metallic: Target,
    /// World-space shading normal facing the camera, roughness in alpha.
    pub normal_roughness: Target,
    /// Dielectric F0 (rgb) and F90 (a).
    pub specular: Target,
    /// Emitted radiance (rgb), ambient occlusion (a).
    pub emission_occlusion: Target,
    /// `SURFACE_COVERED | SURFACE_REAL | material << SURFACE_MATERIAL_SHIFT`; 0 where no surface.
    pub flags: Target,
}

const COLOR_FORMATS: [wgpu::TextureFormat; 5] = [
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::R32Uint,
];
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl GBuffer {
    /// Allocates the targets at `size`.
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let target = |label: &str, format| Target::new_2d(device, label, size, format, usage);
        Self {
            depth: target("gbuffer/depth", DEPTH_FORMAT),
            albedo_metallic: target("gbuffer/albedo_metallic", COLOR_FORMATS[0]),
            normal_roughness: target("gbuffer/normal_roughness", COLOR_FORMATS[1]),
            specular: target("gbuffer/specular", COLOR_FORMATS[2]),
            emission_occlusion: target("gbuffer/emission_occlusion", COLOR_FORMATS[3]),
            flags: target("gbuffer/flags", COLOR_FORMATS[4]),
        }
    }

    fn colors(&self) -> [&Target; 5] {
        [&self.albedo_metallic, &self.normal_roughness, &self.specular, &self.emission_occlusion, &self.flags]
    }
}

/// The G-buffer pass.
pub struct GBufferPass {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
}

impl GBufferPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "gbuffer";

    /// Creates the pipeline for `materials` (group 1) and frame/instances/materials (group 0).
    pub fn new(ctx: &GpuContext, frame: &wgpu::Buffer, geometry: &Geometry, materials: &GpuMaterials) -> Self {
        let device = &ctx.device;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layout =
            bind::layout(device, "gbuffer/layout", &[bind::uniform(0, vf), bind::storage(1, vf), bind::storage(2, vf)]);
        let bind_group = bind::group(
            device,
            "gbuffer/bind_group",
            &layout,
            &[frame.as_entire_binding(), geometry.instances.as_entire_binding(), materials.buffer.as_entire_binding()],
        );
        let module = mrshade_gpu::shader::create_module(device, "gbuffer/shader", SHADER);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gbuffer/pipeline_layout"),
            bind_group_layouts: &[Some(&layout), Some(&materials.layout)],
            immediate_size: 0,
        });
        let targets: Vec<Option<wgpu::ColorTargetState>> = COLOR_FORMATS.iter().map(|&f| Some(f.into())).collect();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer/pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(Vertex::LAYOUT)],
            },
            // No culling: open and double-sided meshes show both sides (the shader flips the normal).
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { pipeline, bind_group }
    }

    /// Clears `gbuffer` and draws every instance into it.
    pub fn record(&self, rec: &mut Recorder, geometry: &Geometry, materials: &GpuMaterials, gbuffer: &GBuffer) {
        let colors: Vec<Option<wgpu::RenderPassColorAttachment>> = gbuffer
            .colors()
            .iter()
            .map(|t| {
                Some(wgpu::RenderPassColorAttachment {
                    view: &t.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let depth = wgpu::RenderPassDepthStencilAttachment {
            view: &gbuffer.depth.view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        };
        rec.render(Self::LABEL, &colors, Some(depth), |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_vertex_buffer(0, geometry.vertices.slice(..));
            pass.set_index_buffer(geometry.indices.slice(..), wgpu::IndexFormat::Uint32);
            let mut bound = usize::MAX;
            for d in &geometry.draws {
                if d.material != bound {
                    pass.set_bind_group(1, &materials.bind_groups[d.material], &[]);
                    bound = d.material;
                }
                pass.draw_indexed(
                    d.first_index..d.first_index + d.index_count,
                    d.base_vertex,
                    d.instance..d.instance + 1,
                );
            }
        });
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "gbuffer.wgsl",
);

//! G-buffer pass (Knecht §2.12): the camera's visibility buffer from the compute rasteriser,
//! then a compute resolve into depth and motion, albedo/metallic, normal/roughness, specular
//! (dielectric F0/F90), emission/occlusion and a flag word (covered, real, material index).

use crate::raster::{Casters, RasterViews, Rasterizer};
use crate::scene_gpu::{Geometry, GpuMaterials};
use crate::uniforms::FrameUniforms;
use mrshade_gpu::timing::{Recorder, set_pipeline_and_groups};
use mrshade_gpu::{GpuContext, Target, bind, wgsl};

/// The G-buffer targets, at the internal (shading) resolution.
pub struct GBuffer {
    /// Reversed depth (1 = near plane, 0 = nothing), offset to the pixel in the previous
    /// frame (x, y), reversed depth there.
    pub depth_motion: Target,
    /// Linear base color, metallic in alpha.
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

const FORMATS: [wgpu::TextureFormat; 6] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::R32Uint,
];

impl GBuffer {
    /// Allocates the targets at `size`.
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST;
        let target = |label: &str, format| Target::new_2d(device, label, size, format, usage);
        Self {
            depth_motion: target("gbuffer/depth_motion", FORMATS[0]),
            albedo_metallic: target("gbuffer/albedo_metallic", FORMATS[1]),
            normal_roughness: target("gbuffer/normal_roughness", FORMATS[2]),
            specular: target("gbuffer/specular", FORMATS[3]),
            emission_occlusion: target("gbuffer/emission_occlusion", FORMATS[4]),
            flags: target("gbuffer/flags", FORMATS[5]),
        }
    }

    fn all(&self) -> [&Target; 6] {
        [
            &self.depth_motion,
            &self.albedo_metallic,
            &self.normal_roughness,
            &self.specular,
            &self.emission_occlusion,
            &self.flags,
        ]
    }
}

/// Visibility raster and resolve of the camera view.
pub struct GBufferPass {
    /// The camera's visibility buffer.
    pub camera: RasterViews,
    pipeline: wgpu::ComputePipeline,
    groups: [wgpu::BindGroup; 3],
    size: (u32, u32),
}

impl GBufferPass {
    /// GPU timing label of the visibility raster.
    pub const RASTER_LABEL: &'static str = "visibility";
    /// GPU timing label of the resolve.
    pub const LABEL: &'static str = "gbuffer";

    /// Creates the camera view and the resolve writing `gbuffer`.
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        uniforms: &FrameUniforms,
        rasterizer: &Rasterizer,
        geometry: &Geometry,
        materials: &GpuMaterials,
        gbuffer: &GBuffer,
    ) -> Self {
        let device = &ctx.device;
        let size = uniforms.internal_size();
        let camera = rasterizer.view(
            ctx,
            geometry,
            "visibility/camera",
            size,
            Casters::All,
            uniforms.clip_from_world,
            uniforms.exposure_env.z,
        );
        let cs = wgpu::ShaderStages::COMPUTE;
        let scene_layout = bind::layout(
            device,
            "gbuffer/scene_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage(4, cs),
                bind::storage(5, cs),
                bind::storage(6, cs),
            ],
        );
        let texture_layout = bind::layout(device, "gbuffer/texture_layout", &GpuMaterials::texture_entries(0, cs));
        let outputs: Vec<wgpu::BindGroupLayoutEntry> =
            FORMATS.iter().enumerate().map(|(i, &f)| bind::storage_texture(i as u32, f)).collect();
        let output_layout = bind::layout(device, "gbuffer/output_layout", &outputs);
        use wgpu::BindingResource::TextureView;
        let groups = [
            bind::group(
                device,
                "gbuffer/scene_group",
                &scene_layout,
                &[
                    frame.as_entire_binding(),
                    geometry.instances.as_entire_binding(),
                    geometry.vertices.as_entire_binding(),
                    geometry.indices.as_entire_binding(),
                    geometry.triangles.as_entire_binding(),
                    materials.buffer.as_entire_binding(),
                    camera.target.as_entire_binding(),
                ],
            ),
            bind::group(device, "gbuffer/texture_group", &texture_layout, &materials.texture_resources()),
            bind::group(device, "gbuffer/output_group", &output_layout, &gbuffer.all().map(|t| TextureView(&t.view))),
        ];
        let pipeline = mrshade_gpu::shader::compute_pipeline(
            device,
            "gbuffer",
            SHADER,
            &[&scene_layout, &texture_layout, &output_layout],
        );
        Self { camera, pipeline, groups, size }
    }

    /// Rasterises the camera's visibility and resolves the G-buffer.
    pub fn record(&self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        rasterizer.record(rec, Self::RASTER_LABEL, [&self.camera]);
        rec.compute(Self::LABEL, |pass| {
            set_pipeline_and_groups(pass, &self.pipeline, &self.groups);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "../../../shaders/lib/material_textures.wgsl",
    "resolve.wgsl",
);

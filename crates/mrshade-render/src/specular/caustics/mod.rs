//! Caustics of the punctual lights through the traced objects (reflections spec §2.17):
//! photon G-buffers (`emit.wgsl`), splatted as surface-aligned quads into a screen-space
//! caustic buffer of irradiance per differential half (`splat.wgsl`), applied to the diffuse
//! surfaces the camera sees by the specular stage's resolve.

use crate::scene_gpu::{Geometry, GpuScene};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::Differential;
use mrshade_core::settings::{CausticsSettings, Concentration};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// Mirrors `CausticParams` in photons.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CausticParams {
    /// Photon resolution, light count, concentration (0 energy, 1 thesis), k_c n_max.
    pub info: UVec4,
    /// Bounding sphere of the casters: centre, radius.
    pub casters: Vec4,
    /// Splat half-size min, max, depth epsilon, k_c base.
    pub splat: Vec4,
}

/// Bytes of one photon (`Photon` in photons.wgsl).
pub const PHOTON_BYTES: u64 = 48;
/// Photons per light and photon-map texel: reflected and refracted, of `L_rv` and of `L_r`.
pub const PHOTON_KINDS: u64 = 4;

/// Buffers of the specular stage the photons are traced through.
pub struct CausticInputs<'a> {
    /// `SpecularParams` (impostor resolution, march steps, bounces).
    pub specular_params: &'a wgpu::Buffer,
    /// `ShadowParams` of the punctual lights' maps.
    pub shadow_params: &'a wgpu::Buffer,
    /// Shadow-map texels of the punctual lights.
    pub shadow_maps: &'a wgpu::Buffer,
    /// Impostor table, owners, impostor texels.
    pub impostors: [&'a wgpu::Buffer; 3],
    /// Interiors table, BVH nodes, BVH triangles, BVH corners.
    pub interiors: [&'a wgpu::Buffer; 4],
    /// The camera's depth and normal G-buffer targets.
    pub depth_motion: &'a Target,
    /// See `depth_motion`.
    pub normal_roughness: &'a Target,
}

/// The caustic buffer and what fills it.
pub struct Caustics {
    settings: CausticsSettings,
    /// The instances whose world boxes bound the photon maps.
    casters: Vec<usize>,
    lights: u32,
    params: wgpu::Buffer,
    /// The photon G-buffers of every light (AOV `photons`).
    pub photons: wgpu::Buffer,
    emit: wgpu::ComputePipeline,
    emit_groups: [wgpu::BindGroup; 3],
    splat: wgpu::RenderPipeline,
    splat_group: wgpu::BindGroup,
}

impl Caustics {
    /// GPU timing label of the photon tracing.
    pub const PHOTONS_LABEL: &'static str = "specular/photons";
    /// GPU timing label of the splatting.
    pub const SPLAT_LABEL: &'static str = "specular/caustic_splat";

    /// The caustics of `gpu_scene`'s punctual lights through the traced instances `casters`,
    /// or `None` when they are off or there is no punctual light.
    pub fn new(
        ctx: &GpuContext,
        settings: CausticsSettings,
        frame: &wgpu::Buffer,
        gpu_scene: &GpuScene,
        casters: Vec<usize>,
        inputs: &CausticInputs,
    ) -> Option<Self> {
        let lights = gpu_scene.light_count;
        if !settings.enabled || lights == 0 || casters.is_empty() {
            return None;
        }
        let device = &ctx.device;
        let res = settings.photon_resolution;
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("specular/caustic_params"),
            contents: bytemuck::bytes_of(&Self::params_of(&settings, lights, Vec4::ZERO)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let photons = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/photons"),
            size: lights as u64 * PHOTON_KINDS * res as u64 * res as u64 * PHOTON_BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let half = wgpu::TextureFormat::Rgba16Float;
        let cs = wgpu::ShaderStages::COMPUTE;
        let s = gpu_scene;
        let g = &s.geometry;
        let emit_uniforms = bind::layout(
            device,
            "specular/photons_uniforms",
            &[bind::uniform(0, cs), bind::uniform(1, cs), bind::uniform(2, cs), bind::uniform(3, cs)],
        );
        let emit_scene =
            bind::layout(device, "specular/photons_scene", &(0..15).map(|i| bind::storage(i, cs)).collect::<Vec<_>>());
        let emit_output = bind::layout(device, "specular/photons_output", &[bind::storage_rw(0, cs)]);
        let [impostors, owners, impostor_texels] = inputs.impostors;
        let scene_buffers: [&wgpu::Buffer; 15] = [
            &g.instances,
            &g.vertices,
            &g.indices,
            &g.triangles,
            &s.materials.buffer,
            impostors,
            owners,
            impostor_texels,
            &s.lights,
            &s.shadow_matrices,
            inputs.shadow_maps,
            inputs.interiors[0],
            inputs.interiors[1],
            inputs.interiors[2],
            inputs.interiors[3],
        ];
        let emit_groups = [
            bind::group(
                device,
                "specular/photons_uniforms",
                &emit_uniforms,
                &[frame, inputs.specular_params, &params, inputs.shadow_params].map(|b| b.as_entire_binding()),
            ),
            bind::group(device, "specular/photons_scene", &emit_scene, &scene_buffers.map(|b| b.as_entire_binding())),
            bind::group(device, "specular/photons_output", &emit_output, &[photons.as_entire_binding()]),
        ];
        let emit = mrshade_gpu::shader::compute_pipeline(
            device,
            Self::PHOTONS_LABEL,
            PHOTONS_SHADER,
            &[&emit_uniforms, &emit_scene, &emit_output],
        );

        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let splat_layout = bind::layout(
            device,
            "specular/caustic_splat",
            &[
                bind::uniform(0, vf),
                bind::uniform(1, vf),
                bind::storage(2, vf),
                bind::texture(3, wgpu::ShaderStages::FRAGMENT, unfilterable, d2),
                bind::texture(4, wgpu::ShaderStages::FRAGMENT, unfilterable, d2),
            ],
        );
        use wgpu::BindingResource::TextureView;
        let splat_group = bind::group(
            device,
            "specular/caustic_splat",
            &splat_layout,
            &[
                frame.as_entire_binding(),
                params.as_entire_binding(),
                photons.as_entire_binding(),
                TextureView(&inputs.depth_motion.view),
                TextureView(&inputs.normal_roughness.view),
            ],
        );
        let splat = mrshade_gpu::shader::additive_render_pipeline(
            device,
            Self::SPLAT_LABEL,
            SPLAT_SHADER,
            &[&splat_layout],
            &[half, half],
        );
        Some(Self { settings, casters, lights, params, photons, emit, emit_groups, splat, splat_group })
    }

    fn params_of(settings: &CausticsSettings, lights: u32, casters: Vec4) -> CausticParams {
        CausticParams {
            info: UVec4::new(
                settings.photon_resolution,
                lights,
                (settings.concentration == Concentration::Thesis) as u32,
                settings.thesis_photons,
            ),
            casters,
            splat: Vec4::new(settings.splat_min, settings.splat_max, settings.depth_epsilon, settings.thesis_base),
        }
    }

    /// Aims the photon maps at where the casters are now: the bounding sphere of their
    /// world boxes.
    pub fn prepare(&self, queue: &wgpu::Queue, geometry: &Geometry) {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for &i in &self.casters {
            let (a, b) = geometry.world_box(i);
            lo = lo.min(a);
            hi = hi.max(b);
        }
        let sphere = ((lo + hi) * 0.5).extend(((hi - lo) * 0.5).length().max(1e-6));
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&Self::params_of(&self.settings, self.lights, sphere)));
    }

    /// Photon tracing, then splatting into `buffer` (see [`caustic_buffer`]).
    pub fn record(&self, rec: &mut Recorder, buffer: &Differential<Target>) {
        let res = self.settings.photon_resolution;
        rec.compute(Self::PHOTONS_LABEL, |pass| {
            pass.set_pipeline(&self.emit);
            for (i, g) in self.emit_groups.iter().enumerate() {
                pass.set_bind_group(i as u32, g, &[]);
            }
            pass.dispatch_workgroups(res.div_ceil(8), res.div_ceil(8), self.lights);
        });
        fn clear(t: &Target) -> Option<wgpu::RenderPassColorAttachment<'_>> {
            Some(wgpu::RenderPassColorAttachment {
                view: &t.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        }
        let photons = self.lights * PHOTON_KINDS as u32 * res * res;
        rec.render(Self::SPLAT_LABEL, &[clear(&buffer.rv), clear(&buffer.r)], None, |pass| {
            pass.set_pipeline(&self.splat);
            pass.set_bind_group(0, &self.splat_group, &[]);
            pass.draw(0..6, 0..photons);
        });
    }
}

/// The caustic buffer of a frame of `size`: per differential half, the irradiance of the
/// photons (rgb, W/m²) and their count (a). Zero where no caustic is traced.
pub fn caustic_buffer(device: &wgpu::Device, size: (u32, u32)) -> Differential<Target> {
    let usage =
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
    let half = wgpu::TextureFormat::Rgba16Float;
    Differential {
        rv: Target::new_2d(device, "specular/caustics_rv", size, half, usage),
        r: Target::new_2d(device, "specular/caustics_r", size, half, usage),
    }
}

/// The composed WGSL module of the photon tracing.
pub const PHOTONS_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/sampling.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/shadow.wgsl",
    "../tracing.wgsl",
    "photons.wgsl",
    "emit.wgsl",
);
/// The composed WGSL module of the splatting.
pub const SPLAT_SHADER: &str =
    wgsl!("../../../shaders/lib/frame.wgsl", "../../../shaders/lib/sampling.wgsl", "photons.wgsl", "splat.wgsl",);

//! Caustics of the punctual lights and of the probe's sky through the traced objects
//! (reflections spec §2.17): photon G-buffers (`emit.wgsl`), splatted as surface-aligned quads into a screen-space
//! caustic buffer of irradiance per differential half (`splat.wgsl`), applied to the diffuse
//! surfaces the camera sees by the specular stage's resolve.

use crate::scene_gpu::{Geometry, GpuProbe, GpuScene};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::Differential;
use mrshade_core::settings::CausticsSettings;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// Mirrors `CausticParams` in photons.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CausticParams {
    /// Photon resolution, source count, sources (0 the punctual lights, 1 probe directions),
    /// caustic buffer divisor.
    pub info: UVec4,
    /// Bounding sphere of the casters: centre, radius.
    pub casters: Vec4,
    /// Splat half-size min, max (metres), depth epsilon, unused.
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

/// One set of photon sources: the punctual lights, or this frame's probe directions.
struct PhotonGroup {
    /// Sources (lights or directions) and the side of each one's photon map.
    sources: u32,
    resolution: u32,
    /// 1 for probe directions.
    from_probe: u32,
    params: wgpu::Buffer,
    /// The photon G-buffer lives in these (wgpu bind groups keep their buffers).
    emit_groups: [wgpu::BindGroup; 2],
    splat_group: wgpu::BindGroup,
}

/// The photon tracing and splatting that fill the caustic buffer.
pub struct Caustics {
    settings: CausticsSettings,
    /// The instances whose world boxes bound the photon maps.
    casters: Vec<usize>,
    groups: Vec<PhotonGroup>,
    /// Bind groups every group's photon tracing shares: the scene, the probe.
    scene_group: wgpu::BindGroup,
    probe_group: wgpu::BindGroup,
    emit: wgpu::ComputePipeline,
    /// Each photon's quad size, from its neighbours (after all have landed).
    size: wgpu::ComputePipeline,
    splat: wgpu::RenderPipeline,
}

impl Caustics {
    /// GPU timing label of the photon tracing.
    pub const PHOTONS_LABEL: &'static str = "specular/photons";
    /// GPU timing label of the splatting.
    pub const SPLAT_LABEL: &'static str = "specular/caustic_splat";

    /// The caustics of `gpu_scene`'s punctual lights (and of the probe, with
    /// `probe_caustics`) through the traced instances `casters`, or `None` when they are off
    /// or nothing shoots photons.
    pub fn new(
        ctx: &GpuContext,
        settings: CausticsSettings,
        probe_caustics: bool,
        frame: &wgpu::Buffer,
        gpu_scene: &GpuScene,
        casters: Vec<usize>,
        inputs: &CausticInputs,
    ) -> Option<Self> {
        let lights = gpu_scene.light_count;
        let directions = if probe_caustics { settings.environment_directions } else { 0 };
        if !settings.enabled || (lights == 0 && directions == 0) || casters.is_empty() {
            return None;
        }
        let device = &ctx.device;
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
        let emit_probe = bind::layout(device, "specular/photons_probe", &GpuProbe::layout_entries(cs));
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
        use wgpu::BindingResource::TextureView;
        let probe_group = bind::group(device, "specular/photons_probe", &emit_probe, &s.probe.resources());
        let emit_layouts = [&emit_uniforms, &emit_scene, &emit_output, &emit_probe];
        let emit = mrshade_gpu::shader::compute_pipeline(device, Self::PHOTONS_LABEL, PHOTONS_SHADER, &emit_layouts);
        let size = mrshade_gpu::shader::compute_pipeline_entry(
            device,
            "specular/photon_size",
            PHOTONS_SHADER,
            "cs_size",
            &emit_layouts,
        );

        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let splat_layout = bind::layout(
            device,
            "specular/caustic_splat",
            &[
                bind::uniform(0, vf),
                bind::uniform(1, vf),
                bind::storage(2, vf),
                bind::texture(3, fragment, unfilterable, d2),
                bind::texture(4, fragment, unfilterable, d2),
            ],
        );
        let half = wgpu::TextureFormat::Rgba16Float;
        let splat = mrshade_gpu::shader::additive_render_pipeline(
            device,
            Self::SPLAT_LABEL,
            SPLAT_SHADER,
            &[&splat_layout],
            &[half, half],
        );

        let mut groups = Vec::new();
        for (label, sources, resolution, from_probe) in [
            ("specular/photons_lights", lights, settings.photon_resolution, 0),
            ("specular/photons_probe", directions, settings.environment_resolution, 1),
        ] {
            if sources == 0 {
                continue;
            }
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}/params")),
                contents: bytemuck::bytes_of(&CausticParams::zeroed()),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
            let photons = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: sources as u64 * PHOTON_KINDS * resolution as u64 * resolution as u64 * PHOTON_BYTES,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let emit_groups = [
                bind::group(
                    device,
                    &format!("{label}/uniforms"),
                    &emit_uniforms,
                    &[frame, inputs.specular_params, &params, inputs.shadow_params].map(|b| b.as_entire_binding()),
                ),
                bind::group(device, &format!("{label}/output"), &emit_output, &[photons.as_entire_binding()]),
            ];
            let splat_group = bind::group(
                device,
                &format!("{label}/splat"),
                &splat_layout,
                &[
                    frame.as_entire_binding(),
                    params.as_entire_binding(),
                    photons.as_entire_binding(),
                    TextureView(&inputs.depth_motion.view),
                    TextureView(&inputs.normal_roughness.view),
                ],
            );
            groups.push(PhotonGroup { sources, resolution, from_probe, params, emit_groups, splat_group });
        }
        let scene_group =
            bind::group(device, "specular/photons_scene", &emit_scene, &scene_buffers.map(|b| b.as_entire_binding()));
        Some(Self { settings, casters, groups, scene_group, probe_group, emit, size, splat })
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
        for g in &self.groups {
            let params = CausticParams {
                info: UVec4::new(g.resolution, g.sources, g.from_probe, self.settings.buffer_divisor),
                casters: sphere,
                splat: Vec4::new(self.settings.splat_min, self.settings.splat_max, self.settings.depth_epsilon, 0.0),
            };
            queue.write_buffer(&g.params, 0, bytemuck::bytes_of(&params));
        }
    }

    /// Photon tracing, then splatting into `buffer` (see [`caustic_buffer`]).
    pub fn record(&self, rec: &mut Recorder, buffer: &Differential<Target>) {
        rec.compute(Self::PHOTONS_LABEL, |pass| {
            for pipeline in [&self.emit, &self.size] {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(1, &self.scene_group, &[]);
                pass.set_bind_group(3, &self.probe_group, &[]);
                for g in &self.groups {
                    pass.set_bind_group(0, &g.emit_groups[0], &[]);
                    pass.set_bind_group(2, &g.emit_groups[1], &[]);
                    pass.dispatch_workgroups(g.resolution.div_ceil(8), g.resolution.div_ceil(8), g.sources);
                }
            }
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
        rec.render(Self::SPLAT_LABEL, &[clear(&buffer.rv), clear(&buffer.r)], None, |pass| {
            pass.set_pipeline(&self.splat);
            for g in &self.groups {
                pass.set_bind_group(0, &g.splat_group, &[]);
                pass.draw(0..6 * g.sources * PHOTON_KINDS as u32 * g.resolution * g.resolution, 0..1);
            }
        });
    }
}

/// The caustic buffer of a frame of `size` (1/`divisor` of it along each axis): per
/// differential half, the irradiance of the photons (rgb, W/m²) and their count (a). Zero
/// where no caustic is traced.
pub fn caustic_buffer(device: &wgpu::Device, size: (u32, u32), divisor: u32) -> Differential<Target> {
    let size = (size.0.div_ceil(divisor), size.1.div_ceil(divisor));
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
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../tracing.wgsl",
    "photons.wgsl",
    "emit.wgsl",
);
/// The composed WGSL module of the splatting.
pub const SPLAT_SHADER: &str =
    wgsl!("../../../shaders/lib/frame.wgsl", "../../../shaders/lib/sampling.wgsl", "photons.wgsl", "splat.wgsl",);

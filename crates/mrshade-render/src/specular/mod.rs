//! The specular stage (Winklhofer's thesis and the TVCG paper; extraction
//! `reflections-refractions-caustics.md`): reflections and refractions of mirror-like and
//! transmissive surfaces, real or virtual, for every light-transport method. It reads the
//! G-buffer, the method's `L_rv`/`L_r` and the photo, and hands the composite one buffer of
//! camera values per traced pixel:
//!
//! 1. impostors: every other instance seen from each traced instance (spec §2.16.2);
//! 2. camera views: the real-only visibility (back-projection's occlusion test, §2.8) and
//!    the farthest surfaces of transmissive instances (Wyman's back faces, §2.12);
//! 3. trace: reflection and refraction G-buffers (§2.10–§2.12, §2.16.3);
//! 4. caustics: photons of the punctual lights through the traced objects, splatted into a
//!    caustic buffer (§2.17);
//! 5. resolve: shading of the hit surfaces, back-projection into the photo and the
//!    differential routing of each branch (§2.5–§2.9); the caustics on diffuse surfaces;
//! 6. temporal smoothing of that light (§2.19).

pub mod caustics;
mod gbuffers;
pub mod impostors;
pub mod interior;
pub mod planar;
pub mod temporal;

use crate::methods::PointLight;
use crate::passes::direct::ShadowParams;
use crate::passes::gbuffer::GBuffer;
use crate::raster::{Casters, RasterViews, Rasterizer, ViewSpec};
use crate::scene_gpu::{GpuMaterials, GpuProbe, GpuScene};
use crate::uniforms::FrameUniforms;
use bytemuck::{Pod, Zeroable};
pub use gbuffers::SpecularGBuffers;
use glam::{Mat4, UVec4, Vec3, Vec4};
use impostors::Impostors;
use interior::Interiors;
use mrshade_core::Differential;
use mrshade_core::flags::Realness;
use mrshade_core::settings::{
    Concentration, InternalReflections, Intersection, Refraction, RefractionPolicy, RenderSettings, SpecularSettings,
};
use mrshade_gpu::timing::{Dispatch, Recorder, SideJob, set_pipeline_and_groups};
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use mrshade_scene::Scene;
use wgpu::util::DeviceExt;

/// Mirrors `SpecularParams` in tracing.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SpecularParams {
    steps: UVec4,
    info: UVec4,
    tolerances: Vec4,
    more: UVec4,
}

const NO_VIEW: u32 = u32::MAX;

/// Whether the stage traces scene instance `instance` (its material is mirror-like or
/// transmissive, within `settings`).
pub fn traces_instance(scene: &Scene, settings: &SpecularSettings, instance: &mrshade_scene::Instance) -> bool {
    let m = &scene.materials[scene.primitives[instance.primitive].material];
    settings.traces(m.metallic, m.roughness, m.transmission)
}

/// Everything the stage reads, built before it.
pub struct SpecularInputs<'a> {
    /// The device.
    pub ctx: &'a GpuContext,
    /// The session's scene (its materials decide what is traced).
    pub scene: &'a Scene,
    /// All settings (`specular`, `shadows`).
    pub settings: &'a RenderSettings,
    /// `FrameUniforms` buffer.
    pub frame: &'a wgpu::Buffer,
    /// The frame uniforms at build time (sizes, first camera).
    pub uniforms: &'a FrameUniforms,
    /// Geometry, materials, lights and probe on the GPU.
    pub gpu_scene: &'a GpuScene,
    /// Shadow-map texels of the punctual lights.
    pub shadow_maps: &'a wgpu::Buffer,
    /// The compute rasteriser (impostors and camera views).
    pub rasterizer: &'a Rasterizer,
    /// The camera's G-buffer.
    pub gbuffer: &'a GBuffer,
    /// The camera's visibility buffer (triangle per pixel).
    pub camera_visibility: &'a wgpu::Buffer,
    /// The method's `L_rv`, `L_r`.
    pub radiance: &'a Differential<Target>,
    /// The method's light at any point, which off-screen hit surfaces are shaded with.
    pub point_light: Option<PointLight<'a>>,
    /// The punctual lights' photon G-buffer (made before the method, which reads it too).
    pub light_photons: Option<&'a caustics::LightPhotons>,
    /// The photo at the output size.
    pub photo: &'a Target,
    /// The composite's α parameters.
    pub composite_params: &'a wgpu::Buffer,
    /// Where the stage writes its light (read by the composite).
    pub output: &'a Target,
}

/// The stage: built only when the scene holds a traced material and the stage is on.
pub struct SpecularStage {
    impostors: Impostors,
    interiors: Interiors,
    /// The camera's view of real geometry only, and of the farthest surface of each
    /// transmissive traced instance.
    camera_views: [RasterViews; 2],
    /// The camera the views were last set to, and whether they must be drawn again.
    camera_views_clip: Option<Mat4>,
    camera_views_stale: bool,
    /// Reflection and refraction G-buffers.
    pub gbuffers: SpecularGBuffers,
    /// Photon tracing and splatting, when the scene shoots photons.
    pub caustics: Option<caustics::Caustics>,
    /// The caustic buffer (AOVs `caustics_rv`, `caustics_r`, `caustics_coarse_rv`,
    /// `caustics_coarse_r`).
    pub caustic_buffer: caustics::CausticBuffer,
    /// The trace, the photon tracing and the caustic buffer's clear, handed to the method's
    /// host pass every frame (`record_rays`).
    rays: SideJob,
    resolve: wgpu::ComputePipeline,
    /// Groups 0, 2 and 3 of the resolve.
    resolve_groups: [wgpu::BindGroup; 3],
    /// Group 1 of the resolve, with the method's VPLs of either parity.
    resolve_scene_groups: [wgpu::BindGroup; 2],
    /// Temporal smoothing of the resolve's light (off when `specular.temporal_weight` is 0:
    /// the resolve then writes the output itself).
    temporal: Option<temporal::SpecularTemporal>,
    size: (u32, u32),
}

impl SpecularStage {
    /// GPU timing label of the trace.
    pub const TRACE_LABEL: &'static str = "specular/trace";
    /// GPU timing label of the trace and the photon tracing, one job (caustics on).
    pub const RAYS_LABEL: &'static str = "specular/trace+photons";
    /// GPU timing label of the resolve.
    pub const RESOLVE_LABEL: &'static str = "specular/resolve";

    /// The stage for `inputs.scene`, or `None` when it traces nothing.
    pub fn new(inputs: &SpecularInputs) -> Option<Self> {
        let settings = inputs.settings.specular;
        let geometry = &inputs.gpu_scene.geometry;
        let material = |i: usize| &inputs.scene.materials[geometry.instance_triangles(i).0 as usize];
        let traced: Vec<bool> = (0..geometry.instance_count())
            .map(|i| {
                let m = material(i);
                settings.traces(m.metallic, m.roughness, m.transmission)
            })
            .collect();
        if !traced.contains(&true) {
            return None;
        }
        let ctx = inputs.ctx;
        let device = &ctx.device;
        let size = inputs.uniforms.internal_size();
        let near = inputs.uniforms.exposure_env.z;
        let reflectors = planar::reflectors(inputs.scene, &settings);
        let impostors = Impostors::new(ctx, inputs.rasterizer, geometry, &traced, &settings, &reflectors, size, near);

        // Camera views: real-only, then one farthest-surface view per transmissive instance,
        // each at an aligned offset of one buffer.
        let clip = inputs.uniforms.clip_from_world;
        let view_bytes = crate::raster::shared_view_bytes(size);
        let traced_instances: Vec<usize> = (0..traced.len()).filter(|&i| traced[i]).collect();
        let interiors = Interiors::new(device, inputs.scene, geometry, &traced_instances);
        // Wyman's farthest surfaces, for the transmissive instances not traced through a BVH.
        let transmissive: Vec<usize> = (0..traced.len())
            .filter(|&i| traced[i] && material(i).transmission > 0.0)
            .filter(|&i| settings.refraction == Refraction::TwoInterfaces || !interiors.has(i))
            .collect();
        let farthest = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/farthest_surfaces"),
            size: view_bytes * transmissive.len().max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let raster = inputs.rasterizer;
        let real_only =
            raster.view(ctx, geometry, "specular/real_only", size, Casters::Only(Realness::Real), clip, near);
        let mut farthest_specs = Vec::new();
        // Per instance (`Owner` in tracing.wgsl): its slices, farthest-surface view and BVH
        // flag; its planar views.
        let mut owners: Vec<[UVec4; 2]> = impostors
            .ranges
            .iter()
            .zip(&impostors.planar_slices)
            .map(|(&(first, count), planar)| {
                [UVec4::new(first, count, NO_VIEW, 0), UVec4::new(planar[0], planar[1], 0, 0)]
            })
            .collect();
        for (k, &i) in transmissive.iter().enumerate() {
            let (_, first, count) = geometry.instance_triangles(i);
            let casters = Casters::FarthestOf { first, count };
            farthest_specs.push(ViewSpec { size, casters, clip_from_world: clip, near, offset: k as u64 * view_bytes });
            owners[i][0].z = (k as u64 * view_bytes / 8) as u32;
        }
        let farthest_views = raster.views(ctx, geometry, "specular/farthest", Some(&farthest), &farthest_specs);
        let camera_views = [real_only, farthest_views];
        if settings.refraction == Refraction::Traced {
            for owner in &mut owners {
                owner[0].w = 1;
            }
        }
        let storage = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let owners = storage("specular/owners", bytemuck::cast_slice(&owners), wgpu::BufferUsages::STORAGE);
        let params = SpecularParams {
            steps: UVec4::new(
                impostors::slice_resolution(&settings),
                settings.linear_steps,
                settings.binary_steps,
                settings.max_bounces,
            ),
            info: UVec4::new(
                (settings.refraction_policy == RefractionPolicy::Rendered) as u32,
                (inputs.settings.caustics.concentration == Concentration::Thesis) as u32,
                inputs.settings.caustics.thesis_photons,
                inputs.settings.caustics.buffer_divisor,
            ),
            tolerances: Vec4::new(
                settings.backprojection_epsilon,
                inputs.settings.caustics.thesis_base,
                inputs.point_light.as_ref().map_or(0.0, |p| p.d_min),
                settings.probe_lobe,
            ),
            more: UVec4::new(
                inputs.point_light.as_ref().map_or(0, |p| p.count),
                inputs.point_light.as_ref().map_or(1, |p| p.stride.max(1)),
                (settings.internal_reflections == InternalReflections::Sampled) as u32,
                match settings.intersection {
                    // Planar views are read through `Owner`; the rest is marched.
                    Intersection::Impostor | Intersection::Planar => 0,
                    Intersection::Cube => 1,
                    Intersection::LayeredCube => 2,
                },
            ),
        };
        let params = storage("specular/params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
        let shadow_params = ShadowParams::new(&inputs.settings.shadows, false);
        let shadow_params =
            storage("specular/shadow_params", bytemuck::bytes_of(&shadow_params), wgpu::BufferUsages::UNIFORM);
        let gbuffers = SpecularGBuffers::new(device, size);
        let caustic_buffer = caustics::CausticBuffer::new(device, size, inputs.settings.caustics.buffer_divisor);
        // Photons start on the rigid traced instances, whose BVHs they are traced into.
        let casters: Vec<usize> = traced_instances.iter().copied().filter(|&i| interiors.has(i)).collect();
        let caustics = caustics::Caustics::new(
            ctx,
            inputs.settings.caustics,
            inputs.settings.probe_caustics(),
            inputs.frame,
            inputs.gpu_scene,
            casters,
            &caustics::CausticInputs {
                specular_params: &params,
                shadow_params: &shadow_params,
                shadow_maps: inputs.shadow_maps,
                impostors: [&impostors.table, &owners, &impostors.texels],
                interiors: [&interiors.table, &interiors.nodes, &interiors.triangles, &interiors.corners],
                light_photons: inputs.light_photons,
                buffer: &caustic_buffer,
                depth_motion: &inputs.gbuffer.depth_motion,
                normal_roughness: &inputs.gbuffer.normal_roughness,
            },
        );

        let cs = wgpu::ShaderStages::COMPUTE;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let uint = wgpu::TextureSampleType::Uint;
        let d2 = wgpu::TextureViewDimension::D2;
        let storage_entries = |n: u32| (0..n).map(|i| bind::storage(i, cs)).collect::<Vec<_>>();
        use wgpu::BindingResource::{Sampler, TextureView};
        let s = inputs.gpu_scene;
        let g = inputs.gbuffer;
        let probe = &s.probe;
        let scene_buffers = [
            &geometry.instances,
            &geometry.vertices,
            &geometry.indices,
            &geometry.triangles,
            &s.materials.buffer,
            &impostors.table,
            &owners,
            &impostors.texels,
            inputs.camera_visibility,
        ];

        // Trace.
        let trace_inputs = bind::layout(
            device,
            "specular/trace_inputs",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::texture(2, cs, unfilterable, d2),
                bind::texture(3, cs, unfilterable, d2),
                bind::texture(4, cs, unfilterable, d2),
                bind::texture(5, cs, unfilterable, d2),
                bind::texture(6, cs, unfilterable, d2),
                bind::texture(7, cs, uint, d2),
                bind::texture_float(8, cs),
                bind::sampler(9, cs, wgpu::SamplerBindingType::Filtering),
            ],
        );
        let trace_scene = bind::layout(device, "specular/trace_scene", &storage_entries(14));
        let formats: Vec<_> = gbuffers.all().iter().map(|t| t.texture.format()).collect();
        let outputs: Vec<_> = formats.iter().enumerate().map(|(i, &f)| bind::storage_texture(i as u32, f)).collect();
        let trace_outputs = bind::layout(device, "specular/trace_outputs", &outputs);
        let mut trace_buffers: Vec<wgpu::BindingResource> =
            scene_buffers.iter().map(|b| b.as_entire_binding()).collect();
        let interior_buffers = [&interiors.table, &interiors.nodes, &interiors.triangles, &interiors.corners];
        trace_buffers.push(farthest.as_entire_binding());
        trace_buffers.extend(interior_buffers.iter().map(|b| b.as_entire_binding()));
        let trace_groups = [
            bind::group(
                device,
                "specular/trace_inputs",
                &trace_inputs,
                &[
                    inputs.frame.as_entire_binding(),
                    params.as_entire_binding(),
                    TextureView(&g.depth_motion.view),
                    TextureView(&g.albedo_metallic.view),
                    TextureView(&g.normal_roughness.view),
                    TextureView(&g.specular.view),
                    TextureView(&g.emission_occlusion.view),
                    TextureView(&g.flags.view),
                    TextureView(&probe.dfg.view),
                    Sampler(&probe.sampler),
                ],
            ),
            bind::group(device, "specular/trace_scene", &trace_scene, &trace_buffers),
            bind::group(
                device,
                "specular/trace_outputs",
                &trace_outputs,
                &gbuffers.all().map(|t| TextureView(&t.view)),
            ),
        ];
        let trace = mrshade_gpu::shader::compute_pipeline(
            device,
            Self::TRACE_LABEL,
            TRACE_SHADER,
            &[&trace_inputs, &trace_scene, &trace_outputs],
        );

        // Resolve.
        let mut resolve_entries = vec![
            bind::uniform(0, cs),
            bind::uniform(1, cs),
            bind::uniform(2, cs),
            bind::uniform(3, cs),
            bind::texture(4, cs, uint, d2),
        ];
        resolve_entries.extend((5..=18).map(|b| bind::texture(b, cs, unfilterable, d2)));
        resolve_entries.push(bind::uniform(19, cs));
        resolve_entries.extend((20..=21).map(|b| bind::texture(b, cs, unfilterable, d2)));
        resolve_entries.extend((22..=24).map(|b| bind::storage(b, cs)));
        let resolve_inputs = bind::layout(device, "specular/resolve_inputs", &resolve_entries);
        let resolve_scene = bind::layout(device, "specular/resolve_scene", &storage_entries(20));
        // The probe (bindings 0–3) and the material textures hit surfaces are shaded with.
        let mut probe_entries = GpuProbe::layout_entries(cs).to_vec();
        probe_entries.extend(GpuMaterials::texture_entries(4, cs));
        let resolve_probe = bind::layout(device, "specular/resolve_probe", &probe_entries);
        let temporal = (settings.temporal_weight > 0.0).then(|| {
            temporal::SpecularTemporal::new(
                device,
                inputs.frame,
                &inputs.gbuffer.depth_motion,
                inputs.output,
                size,
                settings.temporal_weight,
            )
        });
        let resolved = temporal.as_ref().map_or(inputs.output, |t| &t.fresh);
        let resolve_output = bind::layout(
            device,
            "specular/resolve_output",
            &[bind::storage_texture(0, inputs.output.texture.format())],
        );
        let mut resolve_textures = vec![
            inputs.frame.as_entire_binding(),
            params.as_entire_binding(),
            inputs.composite_params.as_entire_binding(),
            shadow_params.as_entire_binding(),
            TextureView(&g.flags.view),
            TextureView(&inputs.radiance.rv.view),
            TextureView(&inputs.radiance.r.view),
            TextureView(&inputs.photo.view),
        ];
        resolve_textures.extend(gbuffers.all().map(|t| TextureView(&t.view)));
        resolve_textures.extend([
            TextureView(&g.albedo_metallic.view),
            TextureView(&caustic_buffer.levels[0].rv.view),
            TextureView(&caustic_buffer.levels[0].r.view),
        ]);
        // The method's VPLs and ISMs, or placeholders that no shader reads (0 VPL slots).
        let placeholder = |label: &str, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let no_vpls = placeholder("specular/no_vpls", 256, wgpu::BufferUsages::STORAGE);
        let no_ism_params = placeholder("specular/no_ism_params", 256, wgpu::BufferUsages::UNIFORM);
        let (vpls, ism_params, ism_real, ism_virtual) = match &inputs.point_light {
            Some(p) => ([&p.vpls[0], &p.vpls[1]], p.ism_params, p.ism_real, p.ism_virtual),
            None => ([&no_vpls, &no_vpls], &no_ism_params, &no_vpls, &no_vpls),
        };
        resolve_textures.push(ism_params.as_entire_binding());
        resolve_textures
            .extend([TextureView(&caustic_buffer.levels[1].rv.view), TextureView(&caustic_buffer.levels[1].r.view)]);
        // The photons' world-space grid, or an empty one (14 words; the bind group keeps it).
        let no_grid = caustics::PhotonGrid::new(device, 0, &inputs.settings.caustics);
        let grid = caustics.as_ref().map_or(&no_grid, |c| &c.grid);
        resolve_textures.extend([&grid.heads, &grid.photons, &grid.entries].map(|b| b.as_entire_binding()));
        let mut resolve_buffers: Vec<wgpu::BindingResource> =
            scene_buffers.iter().map(|b| b.as_entire_binding()).collect();
        resolve_buffers.extend([
            camera_views[0].target.as_entire_binding(),
            s.lights.as_entire_binding(),
            s.shadow_matrices.as_entire_binding(),
            inputs.shadow_maps.as_entire_binding(),
        ]);
        resolve_buffers.extend(interior_buffers.iter().map(|b| b.as_entire_binding()));
        let resolve_scene_groups = [0, 1].map(|parity| {
            let mut buffers = resolve_buffers.clone();
            buffers.extend([vpls[parity], ism_real, ism_virtual].map(|b| b.as_entire_binding()));
            bind::group(device, &format!("specular/resolve_scene_{parity}"), &resolve_scene, &buffers)
        });
        let resolve_groups = [
            bind::group(device, "specular/resolve_inputs", &resolve_inputs, &resolve_textures),
            bind::group(
                device,
                "specular/resolve_probe",
                &resolve_probe,
                &[probe.resources().as_slice(), &s.materials.texture_resources()].concat(),
            ),
            bind::group(device, "specular/resolve_output", &resolve_output, &[TextureView(&resolved.view)]),
        ];
        let resolve = mrshade_gpu::shader::compute_pipeline(
            device,
            Self::RESOLVE_LABEL,
            RESOLVE_SHADER,
            &[&resolve_inputs, &resolve_scene, &resolve_probe, &resolve_output],
        );
        // The rays read the G-buffer and the scene, nothing the method writes.
        let (w, h) = (size.0.div_ceil(8), size.1.div_ceil(8));
        let mut first = vec![Dispatch { pipeline: trace, groups: trace_groups.to_vec(), workgroups: [w, h, 1] }];
        let mut then = Vec::new();
        if let Some(c) = &caustics {
            let (photons, sizes) = c.photon_dispatches();
            first.extend_from_slice(photons);
            then.extend_from_slice(sizes);
        }
        let label = if caustics.is_some() { Self::RAYS_LABEL } else { Self::TRACE_LABEL };
        let rays = SideJob { label: label.into(), first, then };
        Some(Self {
            impostors,
            interiors,
            camera_views,
            camera_views_clip: None,
            camera_views_stale: true,
            gbuffers,
            caustics,
            caustic_buffer,
            rays,
            resolve,
            resolve_groups,
            resolve_scene_groups,
            temporal,
            size,
        })
    }

    /// Moves the impostor cameras to where the instances are and the camera views (and the
    /// planar reflectors' mirrored cameras) to `clip_from_world` at `eye` (this frame's
    /// camera, jittered like the G-buffer's); `changed`: the camera, an instance, a light or
    /// the photo changed since the last frame (the temporal smoothing's weights).
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        geometry: &crate::scene_gpu::Geometry,
        clip_from_world: Mat4,
        eye: Vec3,
        changed: bool,
    ) {
        if let Some(temporal) = &mut self.temporal {
            temporal.prepare(queue, changed);
        }
        self.impostors.update(queue, geometry);
        self.impostors.update_planar(queue, geometry, clip_from_world, eye);
        self.interiors.update(queue, geometry);
        if let Some(caustics) = &self.caustics {
            caustics.prepare(queue, geometry);
        }
        // The camera views change only where the camera or the geometry moved (a still
        // frame keeps them, as the impostors).
        if geometry.moved() || self.camera_views_clip != Some(clip_from_world) {
            self.camera_views_clip = Some(clip_from_world);
            self.camera_views_stale = true;
            for views in &mut self.camera_views {
                for i in 0..views.len() {
                    views.set_clip_from_world(queue, i, clip_from_world);
                }
            }
        }
    }

    /// What the rays need of the frame (impostors, camera views), then the trace and the
    /// photon tracing handed to the method's host pass (they read the G-buffer and the scene,
    /// nothing the method writes): the GPU runs their chains of dependent reads beside the
    /// method's shading.
    pub fn record_rays(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        self.impostors.record(rec, rasterizer);
        if std::mem::take(&mut self.camera_views_stale) {
            rasterizer.record(rec, "specular/camera_views", &self.camera_views);
        }
        rec.beside(self.rays.clone());
    }

    /// Caustic splat, resolve (with the method's VPLs of `vpl_parity`, see
    /// [`PointLight::parity`]) and smoothing, after `record_rays` and the method.
    pub fn record_light(&mut self, rec: &mut Recorder, vpl_parity: usize) {
        rec.flush_side_jobs();
        let (w, h) = (self.size.0.div_ceil(8), self.size.1.div_ceil(8));
        rec.compute(Self::RESOLVE_LABEL, |pass| {
            let [inputs, probe, output] = &self.resolve_groups;
            let groups = [inputs, &self.resolve_scene_groups[vpl_parity], probe, output];
            set_pipeline_and_groups(pass, &self.resolve, groups);
            pass.dispatch_workgroups(w, h, 1);
        });
        // The photon grid is emptied for the next frame once the resolve has read it.
        let grid_clear = self.caustics.as_ref().and_then(|c| c.grid_clear.as_ref());
        match &mut self.temporal {
            Some(temporal) => temporal.record(rec, grid_clear),
            None => {
                if let Some(d) = grid_clear {
                    rec.compute("specular/photon_grid/clear", |pass| d.record(pass));
                }
            }
        }
    }

    /// Forgets the temporal history (a seek).
    pub fn seek(&mut self) {
        if let Some(temporal) = &mut self.temporal {
            temporal.reset();
        }
    }

    /// Turns the temporal smoothing off while `paused` (see `SpecularTemporal::pause`).
    pub fn pause_smoothing(&mut self, paused: bool) {
        if let Some(temporal) = &mut self.temporal {
            temporal.pause(paused);
        }
    }
}

/// The composed WGSL module of the trace.
pub const TRACE_SHADER: &str = wgsl!(
    "../../shaders/lib/frame.wgsl",
    "../../shaders/lib/gbuffer.wgsl",
    "../../shaders/lib/instance.wgsl",
    "../../shaders/lib/triangles.wgsl",
    "../../shaders/lib/brdf.wgsl",
    "../../shaders/lib/gbuffer_pixel.wgsl",
    "../../shaders/lib/sampling.wgsl",
    "../../shaders/lib/dfg.wgsl",
    "../../shaders/lib/cube.wgsl",
    "../../shaders/lib/box_span.wgsl",
    "tracing.wgsl",
    "trace.wgsl",
);
/// The composed WGSL module of the resolve.
pub const RESOLVE_SHADER: &str = wgsl!(
    "../../shaders/lib/frame.wgsl",
    "../../shaders/lib/gbuffer.wgsl",
    "../../shaders/lib/instance.wgsl",
    "../../shaders/lib/triangles.wgsl",
    "../../shaders/lib/brdf.wgsl",
    "../../shaders/lib/dfg.wgsl",
    "../../shaders/lib/env.wgsl",
    "../../shaders/lib/lights.wgsl",
    "../../shaders/lib/cube.wgsl",
    "../../shaders/lib/shadow.wgsl",
    "../../shaders/lib/punctual.wgsl",
    "../../shaders/lib/material_textures.wgsl",
    "../../shaders/lib/alpha.wgsl",
    "../../shaders/lib/sampling.wgsl",
    "../../shaders/lib/vpl.wgsl",
    "../../shaders/lib/ism.wgsl",
    "../../shaders/lib/vpl_light.wgsl",
    "../../shaders/lib/box_span.wgsl",
    "tracing.wgsl",
    "caustics/levels.wgsl",
    "../../shaders/lib/photon.wgsl",
    "../../shaders/lib/photon_grid.wgsl",
    "resolve.wgsl",
);

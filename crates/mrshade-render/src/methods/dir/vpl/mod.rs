//! VPL creation (Knecht §2.8, §2.2): slots are shared among the sources (each punctual light,
//! the probe, the multiple-bounce source), then filled in parallel from the lights' RSMs, the
//! probe's importance pyramid, and, for the bounce source, from the previous frame's VPLs and
//! the ISM point clouds. The VPL buffer is double-buffered: the bounce source and the flux
//! distribution read the previous frame's.
//! Inputs: RSMs, probe pyramid, point clouds, previous VPLs. Output: this frame's VPLs.

use crate::methods::dir::ProbePyramid;
use crate::methods::dir::ism::IsmResources;
use crate::methods::rsm::RsmPass;
use crate::scene_gpu::{Geometry, GpuScene};
use crate::specular::caustics::{LightPhotons, PHOTON_BYTES, SPLAT_DRAWS_BYTES, SPLAT_LIST_BYTES};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};
use mrshade_core::settings::{BounceMethod, DirSettings, Distribution};
use mrshade_gpu::timing::{Dispatch, Recorder};
use mrshade_gpu::{GpuContext, bind, wgsl};
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

/// Mirrors `struct Vpl` in shaders/lib/vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuVpl {
    /// World position (surface VPL) or direction of propagation (directional VPL).
    pub position: Vec4,
    /// Normal; w: roughness.
    pub normal: Vec4,
    /// Incident power (W) or irradiance (W/m²); w: metallic.
    pub power: Vec4,
    /// Power of a co-located VPL3 (adds to `L_r` only).
    pub power_ir: Vec4,
    /// Base color; w: dielectric F90.
    pub albedo: Vec4,
    /// Direction toward the light's origin; w: dielectric F0.
    pub incoming: Vec4,
    /// Flags (r, ir, x̄), source index, kind, reflections so far (1 on RSM VPLs, 0 directional).
    pub info: UVec4,
}

/// VPL kinds (`VPL_*` in vpl.wgsl).
pub mod kind {
    /// Unused slot.
    pub const EMPTY: u32 = 0;
    /// A point on a surface.
    pub const SURFACE: u32 = 1;
    /// Parallel light from a probe direction.
    pub const DIRECTIONAL: u32 = 2;
}

/// VPL flag bits (`VPL_REAL`, `VPL_IR`, `VPL_PATH_REAL` in vpl.wgsl).
pub mod flags {
    /// r(VPL).
    pub const REAL: u32 = 1;
    /// ir(VPL), "illuminate real only".
    pub const IR: u32 = 2;
    /// x̄, the path flag.
    pub const PATH_REAL: u32 = 4;
}

/// Mirrors `VplParams` in vpl/common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VplParams {
    /// VPL count, frame index, source count, light count.
    pub counts: UVec4,
    /// RSM resolution, RSM levels, RSM pyramid stride, interleave².
    pub rsm: UVec4,
    /// Probe pyramid width, height, levels, present.
    pub probe: UVec4,
    /// Probe intensity, total importance.
    pub probe_scale: Vec4,
    /// Scene bounding sphere.
    pub scene: Vec4,
    /// Distribution, bounce method, real points, virtual points.
    pub modes: UVec4,
    /// cos(cone), real area, virtual area, unused.
    pub bounce: Vec4,
    /// Virtual bounding spheres, probe caustics, the punctual lights' photon slots (0: no
    /// caustic VPLs), photons per light and kind.
    pub strata: UVec4,
    /// Probe → world rotation.
    pub world_from_probe: Mat4,
}

/// Mirrors `Source` in vpl/common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Source {
    info: UVec4,
    weight: Vec4,
}

/// Bytes of a `BounceSlot`.
const BOUNCE_SLOT_BYTES: u64 = 64;

/// The VPL buffers and the passes that fill them.
pub struct VplPass {
    /// This frame's and the previous frame's VPLs (index = frame parity).
    pub vpls: [wgpu::Buffer; 2],
    /// Slot range of every source.
    pub ranges: wgpu::Buffer,
    /// Names of the sources, in slot order (light names, "environment", "environment_bounce",
    /// "bounce", "caustics").
    pub source_names: Vec<String>,
    params: VplParams,
    params_buffer: wgpu::Buffer,
    best: wgpu::Buffer,
    virtual_spheres: wgpu::Buffer,
    near: wgpu::Buffer,
    allocate: wgpu::ComputePipeline,
    near_points: wgpu::ComputePipeline,
    generate: wgpu::ComputePipeline,
    candidates: wgpu::ComputePipeline,
    finalize: wgpu::ComputePipeline,
    /// `[parity]` groups of allocate, generate, bounce.
    groups: [[wgpu::BindGroup; 3]; 2],
    point_count: u32,
    real_count: u32,
    /// `dir.seed`: where in the sampling sequences frame 0 starts.
    seed: u32,
}

/// Frames of the sampling sequences between two seeds' starts.
const SEED_STRIDE: u32 = 1 << 16;

impl VplPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "vpl";

    /// Builds the buffers and pipelines.
    #[allow(clippy::too_many_arguments, reason = "VPLs are made from all of these")]
    pub fn new(
        ctx: &GpuContext,
        session: &Session,
        settings: &DirSettings,
        scene: &GpuScene,
        rsm: &RsmPass,
        ism: &IsmResources,
        light_photons: Option<&LightPhotons>,
        center: Vec3,
        radius: f32,
    ) -> Self {
        let device = &ctx.device;
        let n = settings.vpl_count;
        let mut sources: Vec<Source> = Vec::new();
        let mut source_names = Vec::new();
        let weight = |name: &str| settings.weights.get(name).copied().unwrap_or(1.0);
        for (i, light) in session.scene.lights.iter().enumerate() {
            sources.push(Source {
                info: UVec4::new(0, i as u32, 0, 0),
                weight: Vec4::new(weight(&light.name), 0.0, 0.0, 0.0),
            });
            source_names.push(light.name.clone());
        }
        let probe = session.environment.as_ref().map(|env| (env, ProbePyramid::new(&env.image)));
        if probe.is_some() {
            sources
                .push(Source { info: UVec4::new(1, 0, 0, 0), weight: Vec4::new(weight("environment"), 0.0, 0.0, 0.0) });
            source_names.push("environment".into());
            // Our environment VPLs are directional (the probe is distant), so their first
            // bounce, which the thesis's hemisphere VPLs get from the multiple-bounce source,
            // has a source of its own.
            let w = weight("environment_bounce");
            sources.push(Source { info: UVec4::new(3, 0, 0, 0), weight: Vec4::new(w, 0.0, 0.0, 0.0) });
            source_names.push("environment_bounce".into());
        }
        if settings.bounce != BounceMethod::Off {
            sources.push(Source { info: UVec4::new(2, 0, 0, 0), weight: Vec4::new(weight("bounce"), 0.0, 0.0, 0.0) });
            source_names.push("bounce".into());
        }
        // Caustic VPLs (reflections spec §2.18): where the light that the punctual lights'
        // mirrors and glass send on landed (the RSMs then place none on them).
        if light_photons.is_some() {
            let w = weight("caustics");
            sources.push(Source { info: UVec4::new(4, 0, 0, 0), weight: Vec4::new(w, 0.0, 0.0, 0.0) });
            source_names.push("caustics".into());
        }
        let source_count = sources.len() as u32;
        if sources.is_empty() {
            sources.push(Source::zeroed());
        }
        let (probe_info, probe_scale, importance, offsets, radiance, world_from_probe) = match &probe {
            Some((env, p)) => (
                UVec4::new(p.width, p.height, p.offsets.len() as u32, 1),
                Vec4::new(env.intensity, p.total(), 0.0, 0.0),
                p.importance.clone(),
                p.offsets.clone(),
                p.radiance.clone(),
                Mat4::from_mat3(mrshade_core::math::probe_from_world(env.rotation_deg).transpose()),
            ),
            None => (UVec4::ZERO, Vec4::ZERO, vec![0.0], vec![0], vec![[0.0; 4]], Mat4::IDENTITY),
        };
        let params = VplParams {
            counts: UVec4::new(n, 0, source_count, session.scene.lights.len() as u32),
            rsm: UVec4::new(
                rsm.resolution,
                rsm.resolution.ilog2() + 1,
                rsm.pyramid_stride,
                settings.interleave * settings.interleave,
            ),
            probe: probe_info,
            probe_scale,
            scene: center.extend(radius),
            modes: UVec4::new(
                match settings.distribution {
                    Distribution::Equal => 0,
                    Distribution::Weighted => 1,
                    Distribution::Flux => 2,
                },
                match settings.bounce {
                    BounceMethod::Off => 0,
                    BounceMethod::Importance => 1,
                    BounceMethod::Fitness => 2,
                },
                ism.real_count,
                ism.virtual_count,
            ),
            bounce: Vec4::new(
                settings.bounce_cone_deg.to_radians().cos(),
                ism.areas.0,
                ism.areas.1,
                settings.clamp_distance * radius,
            ),
            strata: UVec4::new(
                0,
                session.settings.probe_caustics() as u32,
                light_photons.map_or(0, |p| p.slots),
                light_photons.map_or(0, |p| p.resolution * p.resolution),
            ),
            world_from_probe,
        };
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let rw = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: storage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let vpl_bytes = n as u64 * std::mem::size_of::<GpuVpl>() as u64;
        let vpls = [rw("vpl/buffer0", vpl_bytes), rw("vpl/buffer1", vpl_bytes)];
        let ranges = rw("vpl/ranges", sources.len() as u64 * 16);
        let bounce_slots = rw("vpl/bounce_slots", n as u64 * BOUNCE_SLOT_BYTES);
        // Per slot: the nearest (or fittest) candidate, then the nearest real one.
        let best = rw("vpl/bounce_best", n as u64 * 2 * 8);
        let flux_cdf = rw("vpl/previous_flux_cdf", n as u64 * 4);
        let sphere_capacity =
            scene.geometry.realness.iter().filter(|r| **r == mrshade_core::flags::Realness::Virtual).count().max(1);
        let virtual_spheres = rw("vpl/virtual_spheres", sphere_capacity as u64 * 16);
        let near = rw("vpl/near_count", 4);
        let params_buffer =
            init("vpl/params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        let sources_buffer = init("vpl/sources", bytemuck::cast_slice(&sources), storage);
        let importance = init("vpl/probe_importance", bytemuck::cast_slice(&importance), storage);
        let offsets = init("vpl/probe_offsets", bytemuck::cast_slice(&offsets), storage);
        let radiance = init("vpl/probe_radiance", bytemuck::cast_slice(&radiance), storage);

        let cs = wgpu::ShaderStages::COMPUTE;
        // Layout entries: uniform at 0, then read-only storage, with the listed bindings read-write.
        let layout = |label: &str, count: u32, writable: &[u32], uniforms: &[u32]| {
            let entries: Vec<wgpu::BindGroupLayoutEntry> = (0..count)
                .map(|b| {
                    if uniforms.contains(&b) {
                        bind::uniform(b, cs)
                    } else if writable.contains(&b) {
                        bind::storage_rw(b, cs)
                    } else {
                        bind::storage(b, cs)
                    }
                })
                .collect();
            bind::layout(device, label, &entries)
        };
        let allocate_layout = layout("vpl/allocate_layout", 5, &[3, 4], &[0]);
        let generate_layout = layout("vpl/generate_layout", 19, &[10, 11], &[0]);
        // Without caustic VPLs the photon bindings hold stand-ins.
        let no_photons = [
            rw("vpl/no_photons", PHOTON_BYTES),
            rw("vpl/no_photon_list", SPLAT_LIST_BYTES),
            rw("vpl/no_landed", SPLAT_DRAWS_BYTES),
        ];
        let [photons, photon_list, landed] = match light_photons {
            Some(p) => [&p.buffer, &p.list, &p.landed],
            None => [&no_photons[0], &no_photons[1], &no_photons[2]],
        };
        let bounce_layout = layout("vpl/bounce_layout", 16, &[9, 10, 15], &[0, 11]);
        let groups = [0usize, 1].map(|parity| {
            let (current, previous) = (&vpls[parity], &vpls[1 - parity]);
            [
                bind::group(
                    device,
                    "vpl/allocate_group",
                    &allocate_layout,
                    &[
                        params_buffer.as_entire_binding(),
                        sources_buffer.as_entire_binding(),
                        previous.as_entire_binding(),
                        ranges.as_entire_binding(),
                        flux_cdf.as_entire_binding(),
                    ],
                ),
                bind::group(
                    device,
                    "vpl/generate_group",
                    &generate_layout,
                    &[
                        params_buffer.as_entire_binding(),
                        sources_buffer.as_entire_binding(),
                        ranges.as_entire_binding(),
                        scene.lights.as_entire_binding(),
                        rsm.texels.as_entire_binding(),
                        rsm.pyramid.as_entire_binding(),
                        importance.as_entire_binding(),
                        offsets.as_entire_binding(),
                        radiance.as_entire_binding(),
                        previous.as_entire_binding(),
                        current.as_entire_binding(),
                        bounce_slots.as_entire_binding(),
                        flux_cdf.as_entire_binding(),
                        photons.as_entire_binding(),
                        photon_list.as_entire_binding(),
                        landed.as_entire_binding(),
                        scene.geometry.triangles.as_entire_binding(),
                        scene.geometry.instances.as_entire_binding(),
                        scene.materials.buffer.as_entire_binding(),
                    ],
                ),
                bind::group(
                    device,
                    "vpl/bounce_group",
                    &bounce_layout,
                    &[
                        params_buffer.as_entire_binding(),
                        ranges.as_entire_binding(),
                        sources_buffer.as_entire_binding(),
                        scene.geometry.instances.as_entire_binding(),
                        scene.materials.buffer.as_entire_binding(),
                        ism.points_real.as_entire_binding(),
                        ism.points_virtual.as_entire_binding(),
                        previous.as_entire_binding(),
                        bounce_slots.as_entire_binding(),
                        best.as_entire_binding(),
                        current.as_entire_binding(),
                        ism.params_buffer.as_entire_binding(),
                        ism.atlas_real.as_entire_binding(),
                        ism.atlas_virtual.as_entire_binding(),
                        virtual_spheres.as_entire_binding(),
                        near.as_entire_binding(),
                    ],
                ),
            ]
        });
        let pipeline = |label: &str, source: &str, entry: &str, layout: &wgpu::BindGroupLayout| {
            mrshade_gpu::shader::compute_pipeline_entry(device, label, source, entry, &[layout])
        };
        Self {
            vpls,
            ranges,
            source_names,
            params,
            params_buffer,
            best,
            virtual_spheres,
            near,
            near_points: pipeline("vpl/near_points", BOUNCE_SHADER, "cs_near", &bounce_layout),
            allocate: pipeline("vpl/allocate", ALLOCATE_SHADER, "cs_main", &allocate_layout),
            generate: pipeline("vpl/generate", GENERATE_SHADER, "cs_main", &generate_layout),
            candidates: pipeline("vpl/bounce_candidates", BOUNCE_SHADER, "cs_candidates", &bounce_layout),
            finalize: pipeline("vpl/bounce_finalize", BOUNCE_SHADER, "cs_finalize", &bounce_layout),
            groups,
            point_count: ism.real_count + ism.virtual_count,
            real_count: ism.real_count,
            seed: settings.seed,
        }
    }

    /// Sets the frame index (Halton sequences continue from frame to frame) and where the
    /// virtual instances are.
    pub fn prepare(&mut self, queue: &wgpu::Queue, frame: u32, geometry: &Geometry) {
        self.params.counts.y = frame.wrapping_add(self.seed.wrapping_mul(SEED_STRIDE));
        let spheres = geometry.virtual_spheres();
        self.params.strata.x = spheres.len() as u32;
        if !spheres.is_empty() {
            queue.write_buffer(&self.virtual_spheres, 0, bytemuck::cast_slice(&spheres));
        }
        queue.write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
    }

    /// Creates this frame's VPLs in buffer `parity`; `beside` runs beside the pass's last
    /// dispatch (work for the passes after it that none of this pass's dispatches touches).
    pub fn record(&self, rec: &mut Recorder, parity: usize, beside: &Dispatch) {
        rec.encoder.clear_buffer(&self.best, 0, None);
        rec.encoder.clear_buffer(&self.near, 0, Some(4));
        let n = self.params.counts.x;
        let [allocate, generate, bounce] = &self.groups[parity];
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.allocate);
            pass.set_bind_group(0, allocate, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            if self.real_count > 0 {
                pass.set_pipeline(&self.near_points);
                pass.set_bind_group(0, bounce, &[]);
                mrshade_gpu::shader::dispatch_linear(pass, self.real_count, 64);
            }
            pass.set_pipeline(&self.generate);
            pass.set_bind_group(0, generate, &[]);
            pass.dispatch_workgroups(n.div_ceil(64), 1, 1);
            if self.point_count > 0 {
                pass.set_bind_group(0, bounce, &[]);
                if self.params.modes.y != 0 {
                    pass.set_pipeline(&self.candidates);
                    mrshade_gpu::shader::dispatch_linear(pass, self.point_count, 64);
                }
                // One workgroup per slot (bounce.wgsl: LANES threads share its sums).
                pass.set_pipeline(&self.finalize);
                pass.dispatch_workgroups(n, 1, 1);
            }
            beside.record(pass);
        });
    }
}

/// A module of this pass: the shared library files, common.wgsl, then `$file`.
macro_rules! vpl_shader {
    ($file:literal) => {
        wgsl!(
            "../../../../shaders/lib/frame.wgsl",
            "../../../../shaders/lib/gbuffer.wgsl",
            "../../../../shaders/lib/brdf.wgsl",
            "../../../../shaders/lib/lights.wgsl",
            "../../../../shaders/lib/instance.wgsl",
            "../../../../shaders/lib/sampling.wgsl",
            "../../../../shaders/lib/vpl.wgsl",
            "../../../../shaders/lib/ism.wgsl",
            "../../../../shaders/lib/photon.wgsl",
            "../../../../shaders/lib/rsm_texel.wgsl",
            "common.wgsl",
            $file,
        )
    };
}

/// The allocation module.
pub const ALLOCATE_SHADER: &str = vpl_shader!("allocate.wgsl");
/// The generation module.
pub const GENERATE_SHADER: &str = vpl_shader!("generate.wgsl");
/// The multiple-bounce module.
pub const BOUNCE_SHADER: &str = vpl_shader!("bounce.wgsl");

//! Caustics of the punctual lights and of the probe's sky through the traced objects
//! (reflections spec §2.17): photon G-buffers (`emit.wgsl`), splatted as surface-aligned quads into a screen-space
//! caustic buffer of irradiance per differential half (`splat.wgsl`), applied to the diffuse
//! surfaces the camera sees by the specular stage's resolve; the punctual lights' photons
//! also listed in a world-space grid (`grid.rs`) for the surfaces that reflected and
//! refracted rays reach but the camera does not see.

use crate::scene_gpu::{Geometry, GpuProbe, GpuScene};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::Differential;
use mrshade_core::settings::CausticsSettings;
use mrshade_gpu::timing::Dispatch;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

mod grid;
pub use grid::{
    GRID_BOX_MIN_WORD, GRID_BYTES_PER_SLOT, GRID_CELLS_PER_PHOTON, GRID_ENTRY_BYTES_PER_SLOT, GRID_EPSILON_WORD,
    GRID_HEADER_WORDS, GRID_HEADS, GRID_PHOTON_BYTES, GRID_RANGES_WORKGROUP, GRID_SPLAT_MIN_WORD, GRID_TOTAL_WORD,
    PhotonGrid,
};

/// Mirrors `CausticParams` in photons.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CausticParams {
    /// Photon resolution, source count, sources (0 the punctual lights, 1 probe directions),
    /// caustic buffer divisor.
    pub info: UVec4,
    /// Bounding sphere of the casters: centre, radius.
    pub casters: Vec4,
    /// Splat half-size min, max of the fine level, max of the coarse level (metres), depth
    /// epsilon.
    pub splat: Vec4,
}

/// The coarse caustic level has 1/this of the fine level's texels per axis (`COARSE_LEVEL_FACTOR`
/// in levels.wgsl).
pub const COARSE_LEVEL_FACTOR: u32 = 8;

/// Bytes of one photon (`Photon` in shaders/lib/photon.wgsl).
pub const PHOTON_BYTES: u64 = 48;
/// Photons per light and photon-map texel: reflected and refracted, of `L_rv` and of `L_r`.
pub const PHOTON_KINDS: u64 = 4;
/// Bytes per photon slot of the splat lists (one `u32` per caustic level).
pub const SPLAT_LIST_BYTES: u64 = 8;
/// The two levels' indirect draws (`SplatDraw` in photons.wgsl) before cs_size counts.
const EMPTY_DRAWS: [u32; 8] = [0, 1, 0, 0, 0, 1, 0, 0];
/// Workgroups of the splat per level, each taking every `SPLAT_GROUPS`-th photon of the
/// level's list (`SPLAT_GROUPS` in splat.wgsl).
pub const SPLAT_GROUPS: u32 = 4096;
/// The splat's 64-bit fixed-point sums per texel and differential half (`SUM_WORDS`).
pub const SUM_WORDS: u64 = 4;

/// Bytes of the splat's fixed-point sums (both levels and halves) for a frame of `size` and
/// a fine level of 1/`divisor` of it per axis: 64 bytes a caustic texel.
pub fn sum_bytes(size: (u32, u32), divisor: u32) -> u64 {
    let texels = |d: u32| {
        let (w, h) = level_size(size, d);
        w as u64 * h as u64
    };
    2 * SUM_WORDS * 8 * (texels(divisor) + texels(divisor * COARSE_LEVEL_FACTOR))
}

/// Texels of a caustic level of 1/`divisor` of a frame of `size` per axis (`level_size` in
/// splat.wgsl).
fn level_size(size: (u32, u32), divisor: u32) -> (u32, u32) {
    (size.0.div_ceil(divisor), size.1.div_ceil(divisor))
}
/// Bytes of a group's two indirect draws (what `LightPhotons::landed` keeps of them).
pub const SPLAT_DRAWS_BYTES: u64 = std::mem::size_of_val(&EMPTY_DRAWS) as u64;

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
    /// The punctual lights' photon G-buffer, made before the stage.
    pub light_photons: Option<&'a LightPhotons>,
    /// The caustic buffer the photons are splatted into.
    pub buffer: &'a CausticBuffer,
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
    /// The photon G-buffer (`Photon` in photons.wgsl), per source, kind and texel.
    photons: wgpu::Buffer,
    /// The indirect draw of each level (`SplatDraw` in photons.wgsl).
    draws: wgpu::Buffer,
}

/// The photon G-buffer of the punctual lights (`Photon` in shaders/lib/photon.wgsl, per light,
/// kind and texel) and its lists of landed photons, made before the method and the specular
/// stage: the stage's photon pass fills them, and `dir` places its caustic VPLs where the last
/// frame's photons landed (reflections spec §2.18).
pub struct LightPhotons {
    /// The photons.
    pub buffer: wgpu::Buffer,
    /// The landed photons' indices, per caustic level (level × slots + i).
    pub list: wgpu::Buffer,
    /// Last frame's landed photons per level (the splat draws' vertex counts, six per photon:
    /// `SplatDraw` × 2), copied after the photon pass.
    pub landed: wgpu::Buffer,
    /// Photon slots: lights × kinds × resolution².
    pub slots: u32,
    /// Side of each light's photon map.
    pub resolution: u32,
}

impl LightPhotons {
    /// The buffers, when the session's punctual lights shoot photons: caustics and the
    /// specular stage on, a light, and a rigid instance of a traced material to start on.
    pub fn new(ctx: &GpuContext, session: &Session) -> Option<Self> {
        let (scene, settings) = (&session.scene, &session.settings);
        let caster = scene.instances.iter().any(|i| {
            super::traces_instance(scene, &settings.specular, i) && !scene.primitives[i.primitive].is_deformable()
        });
        if !settings.caustics.enabled || scene.lights.is_empty() || !caster {
            return None;
        }
        let resolution = settings.caustics.photon_resolution;
        let slots = scene.lights.len() as u64 * PHOTON_KINDS * resolution as u64 * resolution as u64;
        let (buffer, list) = photon_buffers(&ctx.device, LIGHTS_LABEL, slots);
        let landed = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/photons_lights/landed"),
            size: SPLAT_DRAWS_BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Some(Self { buffer, list, landed, slots: slots as u32, resolution })
    }
}

/// Label of the punctual lights' photon group (the probe's is "specular/photons_probe").
const LIGHTS_LABEL: &str = "specular/photons_lights";

/// A photon group's G-buffer and splat lists for `slots` photons.
fn photon_buffers(device: &wgpu::Device, label: &str, slots: u64) -> (wgpu::Buffer, wgpu::Buffer) {
    let buffer = |label: &str, size: u64, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | usage,
            mapped_at_creation: false,
        })
    };
    (
        buffer(label, slots * PHOTON_BYTES, wgpu::BufferUsages::COPY_SRC),
        buffer(&format!("{label}/splat_list"), slots * SPLAT_LIST_BYTES, wgpu::BufferUsages::empty()),
    )
}

/// The photon tracing and splatting that fill the caustic buffer.
pub struct Caustics {
    settings: CausticsSettings,
    /// The instances whose world boxes bound the photon maps.
    casters: Vec<usize>,
    groups: Vec<PhotonGroup>,
    /// The photon tracing of each group (reflections spec §2.17.1), one thread per photon
    /// and kind.
    emit: Vec<Dispatch>,
    /// Each group's photons' quad sizes, from their neighbours (after all have landed), and
    /// splat lists; then the splat of each group and the caustic buffer's finish.
    then: Vec<Dispatch>,
    /// The landed photons in world space, for the surfaces the camera does not see.
    pub grid: PhotonGrid,
    /// Empties the grid once the resolve has read it (with punctual lights).
    pub grid_clear: Option<Dispatch>,
}

impl Caustics {
    /// GPU timing label of the photon tracing.
    pub const PHOTONS_LABEL: &'static str = "specular/photons";

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
        let emit_output = bind::layout(
            device,
            "specular/photons_output",
            &(0..7).map(|i| bind::storage_rw(i, cs)).collect::<Vec<_>>(),
        );
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
        let [grid_ranges, grid_scatter, grid_clear] = [
            ("specular/photon_grid/ranges", "cs_grid_ranges"),
            ("specular/photon_grid/scatter", "cs_grid_scatter"),
            ("specular/photon_grid/clear", "cs_grid_clear"),
        ]
        .map(|(label, entry)| {
            mrshade_gpu::shader::compute_pipeline_entry(device, label, PHOTONS_SHADER, entry, &emit_layouts)
        });

        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let splat_layout = bind::layout(
            device,
            "specular/caustic_splat",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::storage(2, cs),
                bind::texture(3, cs, unfilterable, d2),
                bind::texture(4, cs, unfilterable, d2),
                bind::storage(5, cs),
                bind::storage(6, cs),
                bind::storage_rw(7, cs),
            ],
        );
        let half = wgpu::TextureFormat::Rgba16Float;
        let mut finish_entries: Vec<_> = (0..4).map(|i| bind::storage_texture(i, half)).collect();
        finish_entries.push(bind::storage_rw(4, cs));
        let finish_layout = bind::layout(device, "specular/caustic_finish", &finish_entries);
        let splat = mrshade_gpu::shader::compute_pipeline_entry(
            device,
            "specular/caustic_splat",
            SPLAT_SHADER,
            "cs_splat",
            &[&splat_layout],
        );
        let finish = mrshade_gpu::shader::compute_pipeline_entry(
            device,
            "specular/caustic_finish",
            SPLAT_SHADER,
            "cs_finish",
            &[&splat_layout, &finish_layout],
        );
        let levels = &inputs.buffer.levels;
        // Both halves of both levels, SUM_WORDS sums of 8 bytes a texel (zero at creation;
        // cs_finish empties them after every frame).
        let sums = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/caustic_sums"),
            size: sum_bytes(inputs.buffer.size, settings.buffer_divisor),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        // cs_finish keeps the first group's draws: the lights' landed photons for the next
        // frame's caustic VPLs (or, without lights, a buffer nothing reads).
        let no_landed = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/caustic_no_landed"),
            size: SPLAT_DRAWS_BYTES,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let landed = inputs.light_photons.filter(|_| lights > 0).map_or(&no_landed, |l| &l.landed);
        let mut targets: Vec<_> = [&levels[0].rv, &levels[0].r, &levels[1].rv, &levels[1].r]
            .map(|t| wgpu::BindingResource::TextureView(&t.view))
            .into();
        targets.push(landed.as_entire_binding());
        let finish_group = bind::group(device, "specular/caustic_finish", &finish_layout, &targets);
        let mut splat_dispatches = Vec::new();

        let scene_group =
            bind::group(device, "specular/photons_scene", &emit_scene, &scene_buffers.map(|b| b.as_entire_binding()));
        let slots =
            |sources: u32, resolution: u32| sources as u64 * PHOTON_KINDS * resolution as u64 * resolution as u64;
        // The punctual lights' photons (emit.wgsl leaves the probe's off the grid).
        let grid = PhotonGrid::new(device, slots(lights, settings.photon_resolution), &settings);
        // The probe's group binds an empty grid of its own: two dispatches of one pass that
        // bind the same buffer for writing get a barrier between them, which waits for all
        // the pass's work, and the probe's photons then ran after the method's ISMs, the trace
        // and the lights' photons instead of beside them (the bench scene's rays 1.30 → 1.88 ms
        // on an H100).
        let no_grid = PhotonGrid::new(device, 0, &settings);
        let (mut groups, mut emit_dispatches, mut size_dispatches) = (Vec::new(), Vec::new(), Vec::new());
        let mut grid_clear_dispatch = None;
        for (label, sources, resolution, from_probe) in [
            (LIGHTS_LABEL, lights, settings.photon_resolution, 0),
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
            let slots = slots(sources, resolution);
            // The lights' photons live in `LightPhotons` (dir reads them too).
            let shared = inputs.light_photons.filter(|_| from_probe == 0);
            let own_grid = if from_probe == 0 { &grid } else { &no_grid };
            let (photons, list) = match shared {
                Some(lights) => (lights.buffer.clone(), lights.list.clone()),
                None => photon_buffers(device, label, slots),
            };
            let draws = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}/splat_draws")),
                contents: bytemuck::cast_slice(&EMPTY_DRAWS),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
            });
            // The photon G-buffer and the splat lists live in these bind groups (wgpu bind
            // groups keep their buffers).
            let emit_groups = vec![
                bind::group(
                    device,
                    &format!("{label}/uniforms"),
                    &emit_uniforms,
                    &[frame, inputs.specular_params, &params, inputs.shadow_params].map(|b| b.as_entire_binding()),
                ),
                scene_group.clone(),
                bind::group(
                    device,
                    &format!("{label}/output"),
                    &emit_output,
                    &[&photons, &list, &draws, &own_grid.heads, &own_grid.photons, &own_grid.entries, &own_grid.cells]
                        .map(|b| b.as_entire_binding()),
                ),
                probe_group.clone(),
            ];
            let side = resolution.div_ceil(8);
            for (pipeline, kinds, dispatches) in
                [(&emit, PHOTON_KINDS as u32, &mut emit_dispatches), (&size, 1, &mut size_dispatches)]
            {
                let workgroups = [side, side, sources * kinds];
                dispatches.push(Dispatch { pipeline: pipeline.clone(), groups: emit_groups.clone(), workgroups });
            }
            if from_probe == 0 {
                // The grid's counting sort after cs_size counted: the cells' ranges, then
                // the photons listed in them.
                let heads = (grid.head_count / GRID_RANGES_WORKGROUP) as u32;
                size_dispatches.extend([
                    Dispatch { pipeline: grid_ranges.clone(), groups: emit_groups.clone(), workgroups: [heads, 1, 1] },
                    Dispatch {
                        pipeline: grid_scatter.clone(),
                        groups: emit_groups.clone(),
                        workgroups: [side, side, sources],
                    },
                ]);
                let words = (GRID_HEADER_WORDS + grid.head_count) as u32;
                grid_clear_dispatch = Some(Dispatch {
                    pipeline: grid_clear.clone(),
                    groups: emit_groups.clone(),
                    workgroups: [words.div_ceil(256), 1, 1],
                });
            }
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
                    list.as_entire_binding(),
                    draws.as_entire_binding(),
                    sums.as_entire_binding(),
                ],
            );
            // Both levels' photons, after every group's cs_size (the grid's lists need not
            // wait: the splat reads neither).
            splat_dispatches.push(Dispatch {
                pipeline: splat.clone(),
                groups: vec![splat_group],
                workgroups: [SPLAT_GROUPS, 2, 1],
            });
            groups.push(PhotonGroup { sources, resolution, from_probe, params, photons, draws });
        }
        // The finish reads the first group's draws (see `landed`) through its splat group.
        let (w, h) = (levels[0].rv.texture.width(), levels[0].rv.texture.height());
        let splat_finish = splat_dispatches.first().map(|d| Dispatch {
            pipeline: finish,
            groups: vec![d.groups[0].clone(), finish_group],
            workgroups: [w.div_ceil(8), h.div_ceil(8), 1],
        });
        let mut then = size_dispatches;
        then.extend(splat_dispatches);
        then.extend(splat_finish);
        Some(Self { settings, casters, groups, emit: emit_dispatches, then, grid, grid_clear: grid_clear_dispatch })
    }

    /// Aims the photon maps at where the casters are now: the bounding sphere of their
    /// world boxes; empties the splat lists' draws (before every frame's `record`).
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
                splat: Vec4::new(
                    self.settings.splat_min,
                    self.settings.splat_max,
                    self.settings.splat_far_max,
                    self.settings.depth_epsilon,
                ),
            };
            queue.write_buffer(&g.params, 0, bytemuck::bytes_of(&params));
            queue.write_buffer(&g.draws, 0, bytemuck::cast_slice(&EMPTY_DRAWS));
        }
    }

    /// The photon tracing, one thread per photon and kind: the chain of one photon's reads,
    /// not the GPU's throughput, bounds it, so it runs beside other work (`SideJob::first`);
    /// then each photon's quad size and the splat lists, the splat and the caustic buffer
    /// (`SideJob::then`).
    pub fn photon_dispatches(&self) -> (&[Dispatch], &[Dispatch]) {
        (&self.emit, &self.then)
    }
}

/// One photon of the last frame that landed on a diffuse surface (read back for the
/// `photon_hits` AOV and for tests).
#[derive(Clone, Copy, Debug)]
pub struct LandedPhoton {
    /// Whether it came from a probe direction (else from a punctual light).
    pub from_probe: bool,
    /// The light or probe direction it came from.
    pub source: u32,
    /// 0 reflected, 1 refracted (of `L_rv`); 2, 3 the same of `L_r`.
    pub kind: u32,
    /// Its texel in the source's photon map.
    pub texel: (u32, u32),
    /// Where it landed.
    pub position: Vec3,
    /// The receiver's normal there.
    pub normal: Vec3,
    /// Its quad's half-size, metres.
    pub half_size: f32,
    /// Its power, W.
    pub power: Vec3,
}

impl Caustics {
    /// The photons of the last frame that landed, read back from the GPU.
    pub fn read_photons(&self, ctx: &GpuContext) -> anyhow::Result<Vec<LandedPhoton>> {
        let mut out = Vec::new();
        for g in &self.groups {
            let bytes = mrshade_gpu::readback::read_buffer(ctx, &g.photons)?;
            let floats: &[f32] = bytemuck::cast_slice(&bytes);
            let res = g.resolution as usize;
            for (index, p) in floats.chunks_exact(PHOTON_BYTES as usize / 4).enumerate() {
                if p[3] == 0.0 {
                    continue;
                }
                let (texel, rest) = (index % (res * res), index / (res * res));
                out.push(LandedPhoton {
                    from_probe: g.from_probe == 1,
                    source: (rest / PHOTON_KINDS as usize) as u32,
                    kind: (rest % PHOTON_KINDS as usize) as u32,
                    texel: ((texel % res) as u32, (texel / res) as u32),
                    position: Vec3::new(p[0], p[1], p[2]),
                    normal: Vec3::new(p[4], p[5], p[6]),
                    half_size: p[7],
                    power: Vec3::new(p[8], p[9], p[10]),
                });
            }
        }
        Ok(out)
    }
}

/// The caustic buffer of a frame, in two levels: per differential half, the irradiance of
/// the photons (rgb, W/m²) and their count (a). Zero where no caustic is traced.
pub struct CausticBuffer {
    /// The fine level (1/`buffer_divisor` of the frame along each axis) of the photons at
    /// most `splat_max` apart, and the coarse one (1/`COARSE_LEVEL_FACTOR` of that) of those
    /// farther apart.
    pub levels: [Differential<Target>; 2],
    /// The frame's size it was made for.
    pub size: (u32, u32),
}

impl CausticBuffer {
    /// Both levels for a frame of `size` and the fine level's `divisor`.
    pub fn new(device: &wgpu::Device, size: (u32, u32), divisor: u32) -> Self {
        let usage =
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let half = wgpu::TextureFormat::Rgba16Float;
        let level = |name: &str, divisor: u32| {
            let size = level_size(size, divisor);
            Differential {
                rv: Target::new_2d(device, &format!("specular/{name}_rv"), size, half, usage),
                r: Target::new_2d(device, &format!("specular/{name}_r"), size, half, usage),
            }
        };
        Self { levels: [level("caustics", divisor), level("caustics_coarse", divisor * COARSE_LEVEL_FACTOR)], size }
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
    "../../../shaders/lib/cube.wgsl",
    "../../../shaders/lib/shadow.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/box_span.wgsl",
    "../tracing.wgsl",
    "../../../shaders/lib/photon.wgsl",
    "../../../shaders/lib/photon_grid.wgsl",
    "photons.wgsl",
    "emit.wgsl",
);
/// The composed WGSL module of the splatting.
pub const SPLAT_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/sampling.wgsl",
    "../../../shaders/lib/photon.wgsl",
    "photons.wgsl",
    "levels.wgsl",
    "splat.wgsl",
);

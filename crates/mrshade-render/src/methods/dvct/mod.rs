//! Delta voxel cone tracing, the `dvct` method (Franke §2.13, [Fra14a]), its passes in the
//! order of the spec's pseudo-code (§2.13.8): voxelise the real and virtual scene around the
//! virtual content → inject the first bounce of both solutions per voxel → (a second bounce,
//! gathered by cones per voxel, and while the content rests a third) → the photo's light in
//! the real voxels the camera sees → 3D mipmaps → per-pixel cone tracing into the
//! [`IndirectLight`] that direct lighting adds.
//! Voxels and their light are redrawn only when geometry or a light moved, the photo's light
//! when the photo or the camera did; the cones are traced every frame.
//!
//! Where it departs from the thesis, and why: the direct change T_Δ¹ comes from the frame's
//! real-only and virtual-only shadow maps (exact, unbounded, never darkening a real shadow
//! twice; spec §2.13.3's pitfall) instead of one shadow cone per light; the split injection is
//! per voxel (each voxel lit through the shadow maps for both solutions) instead of per RSM
//! texel with racing writes; a voxel that holds both faces of a thin real wall keeps the one
//! facing the content (voxelize.wgsl); a second bounce is injected, and while the content and
//! the lights rest a third, which takes the virtual content's light off the real surfaces back
//! onto it (`dvct.bounces`); real
//! voxels the camera sees take the photo's light (spec §2.11's B ≈ (T_μ² + T_μ)·L_e applied to
//! the voxels, `dvct.photo_voxels`, photo.wgsl); the mipmaps are anisotropic, a chain per way
//! along each axis ([CNS+11]), and a voxel shows its light only on its own side (mips.wgsl);
//! the probe's light from its narrower lights is shadowed through their maps
//! (`probe_maps`, `dvct.probe_lights`) rather than by the nine wide cones alone (gather.wgsl),
//! and while the view holds still each frame draws those lights anew within their regions,
//! every one shadowing through its maps, so that a still's mean is the probe's exact
//! visibility (`dvct.sample_probe_lights`, `ibl::ProbeRegions::sampled`), and the virtual
//! surfaces gather with a few thin rays per frame whose running mean each texel keeps
//! (`dvct.still_rays`, still_rays.wgsl) rather than with the nine wide cones;
//! and the virtual content's change along a cone, which covers the same part of the cone
//! sample after sample, lies between compounding its samples and taking the most opaque one
//! (cones.wgsl `probe_occlusion`, `cone_seen`).

mod cascade;
mod pixels;
mod shaders;
mod volume;

pub use shaders::*;
pub use volume::{RawPair, Volume, VolumePair, VolumeParams, VoxelNormals, levels};

use cascade::{Cascade, VOXEL_BYTES};

use super::probe_maps::ProbeMaps;
use super::{FrameChange, IndirectLight, LightTransport, MethodInputs};
use crate::ibl::ProbeRegions;
use crate::limits::Fit;
use crate::passes::direct::ShadowParams;
use crate::raster::Rasterizer;
use crate::scene_gpu::{Geometry, GpuMaterials, GpuProbe};
use anyhow::{Result, bail};
use mrshade_core::settings::{RenderSettings, ShadowSettings};
use mrshade_gpu::bind;
use mrshade_gpu::shader::{compute_pipeline, compute_pipeline_entry, dispatch_linear};
use mrshade_gpu::timing::{Dispatch, Recorder, set_pipeline_and_groups};
use wgpu::util::DeviceExt;

/// The start of both groups over the triangles: the volume's uniform and the geometry.
fn geometry<'a>(c: &'a Cascade, g: &'a Geometry) -> Vec<wgpu::BindingResource<'a>> {
    vec![
        c.params_buffer.as_entire_binding(),
        g.instances.as_entire_binding(),
        g.vertices.as_entire_binding(),
        g.indices.as_entire_binding(),
        g.triangles.as_entire_binding(),
    ]
}

/// One level of one solution's mipmaps (mips.wgsl).
struct MipDispatch {
    group: wgpu::BindGroup,
    /// The level's side.
    side: u32,
    /// Whether it is the first, read from the voxels themselves.
    from_voxels: bool,
}

/// A pass over every voxel of one cascade: its pipeline and groups.
type VoxelPass = (wgpu::ComputePipeline, Vec<wgpu::BindGroup>);

/// The method's passes and volumes.
pub struct DvctMethod {
    /// The volume around the virtual content, then the outer one (`dvct.outer_scale` > 1).
    cascades: Vec<Cascade>,
    scene_box: Option<(glam::Vec3, glam::Vec3)>,
    clear: wgpu::ComputePipeline,
    voxelize: wgpu::ComputePipeline,
    /// Per cascade.
    voxelize_groups: Vec<wgpu::BindGroup>,
    /// The first bounce, per cascade.
    light: Vec<VoxelPass>,
    /// The second bounce, per cascade (`dvct.bounces` ≥ 2).
    bounce: Vec<VoxelPass>,
    /// The photo's light in the second bounce's real voxels, per cascade (`dvct.photo_voxels`
    /// with two bounces; with one the light pass takes it).
    photo: Vec<VoxelPass>,
    /// The third bounce and its photo pass, per cascade (`dvct.bounces` = 3): into the first
    /// bounce's volumes.
    third: Vec<VoxelPass>,
    third_photo: Vec<VoxelPass>,
    /// `dvct.third_bounce_moving`.
    third_moving: bool,
    /// Whether the volumes hold the third bounce of the content and lights as they are.
    third_done: bool,
    /// What the pixels' cones read (cones.wgsl's group 1): the second bounce's volumes, and
    /// the first's, which a third bounce writes.
    cone_volumes: [wgpu::BindGroup; 2],
    /// The mipmaps' first level (from the voxels) and the levels after it (mips.wgsl).
    mips_base: wgpu::ComputePipeline,
    mips: wgpu::ComputePipeline,
    /// Per volume pair (first bounces, then second bounces, cascade by cascade), per level from
    /// 1 and solution.
    first_mips: Vec<MipDispatch>,
    second_mips: Vec<MipDispatch>,
    /// The cones, once per trace texel (`dvct.trace_block`).
    trace: Dispatch,
    /// Their light per pixel, over the internal size.
    resolve: Dispatch,
    /// The cones of the pixels no trace texel around them is like (`dvct.retrace_likeness`).
    retrace: pixels::Retrace,
    /// A still view's thin rays for the virtual trace texels (`dvct.still_rays`).
    still_rays: pixels::StillRays,
    /// What direct lighting adds.
    pub indirect: IndirectLight,
    /// The probe's lights and their maps around the inner volume (`dvct.probe_lights`).
    probe_maps: ProbeMaps,
    /// Where the probe's maps reach (their depth bias).
    shadows: ShadowSettings,
    stale_voxels: bool,
    stale_light: bool,
    /// The photo or the camera changed: the photo's light goes into the voxels again.
    stale_photo: bool,
    /// `dvct.photo_voxels`.
    photo_voxels: bool,
    /// The probe's regions to draw its lights from while the view holds still
    /// (`dvct.sample_probe_lights`).
    probe_regions: Option<ProbeRegions>,
    /// Frames since anything changed (0: this one did).
    still_frames: u32,
    /// The probe's maps need drawing again (new lights, or the content moved).
    stale_probe_maps: bool,
}

/// Builds the method (the registry's `build`).
pub(crate) fn build(inputs: &MethodInputs) -> Box<dyn LightTransport> {
    Box::new(DvctMethod::new(inputs))
}

/// Halves the volumes until their voxelisation fits one buffer binding and their side one 3D
/// texture.
pub(crate) fn fit(settings: &mut RenderSettings, fit: &mut Fit) -> Result<()> {
    let (max_binding, max_side) = (fit.max_binding, fit.max_texture_3d as u64);
    let fits = |res: u64| res * res * res * VOXEL_BYTES <= max_binding && res <= max_side;
    if !fit.shrink("dvct.resolution", &mut settings.dvct.resolution, &fits, 16) {
        bail!("this device cannot hold even a 16³ voxel volume for `dvct`");
    }
    let d = &mut settings.dvct;
    super::rsm::fit_resolution(fit, "dvct.probe_map_resolution", 2 * d.probe_lights as u64, &mut d.probe_map_resolution)
}

/// GPU bytes of the method, item by item.
pub(crate) fn estimate(settings: &RenderSettings, internal_pixels: u64, _layers: u64) -> Vec<(&'static str, u64)> {
    let d = &settings.dvct;
    let mut sides = vec![d.resolution as u64];
    if d.outer_scale > 1.0 {
        sides.push(d.outer_voxels() as u64);
    }
    let voxels: u64 = sides.iter().map(|&r| r.pow(3) * VOXEL_BYTES + VoxelNormals::bytes(r as u32)).sum();
    let light: u64 = sides.iter().map(|&r| d.bounces.min(2) as u64 * VolumePair::bytes(r as u32)).sum();
    let raw: u64 = if d.raw_volumes() { sides.iter().map(|&r| RawPair::bytes(r as u32)).sum() } else { 0 };
    vec![
        ("dvct screen targets (output size × supersample²)", internal_pixels * 5 * 8),
        (
            "dvct still rays' means per trace texel (dvct.still_rays)",
            if d.still_rays > 0 {
                internal_pixels.div_ceil((d.trace_block * d.trace_block) as u64) * pixels::STILL_HISTORY_BYTES
            } else {
                0
            },
        ),
        ("dvct voxels and their normals (dvct.resolution³, dvct.outer_resolution³)", voxels),
        ("dvct light volumes (voxels × bounces per volume, with mips)", light),
        ("dvct last bounce before the photo's light (dvct.photo_voxels, dvct.bounces = 3)", raw),
        (
            "dvct probe-light maps (2 × dvct.probe_lights × dvct.probe_map_resolution²)",
            super::rsm::bytes(2 * settings.dvct.probe_lights as u64, settings.dvct.probe_map_resolution),
        ),
    ]
}

impl DvctMethod {
    /// GPU timing label of the voxelisation.
    pub const VOXELIZE_LABEL: &'static str = "dvct-voxelize";
    /// GPU timing label of the injection (first bounce) and its mipmaps.
    pub const LIGHT_LABEL: &'static str = "dvct-light";
    /// GPU timing label of the second bounce and its mipmaps.
    pub const BOUNCE_LABEL: &'static str = "dvct-bounce";
    /// GPU timing label of the photo's light in the second bounce's voxels and their mipmaps.
    pub const PHOTO_LABEL: &'static str = "dvct-photo";
    /// GPU timing label of the third bounce, its photo's light and the mipmaps.
    pub const THIRD_LABEL: &'static str = "dvct-third-bounce";
    /// GPU timing label of the pixels' cones.
    pub const LABEL: &'static str = "dvct-cones";

    /// Builds every pass for the session of `inputs`.
    pub fn new(inputs: &MethodInputs) -> Self {
        let MethodInputs { ctx, session, scene, frame_uniforms, shadow_maps, gbuffer, photo, .. } = *inputs;
        let device = &ctx.device;
        let settings = &session.settings.dvct;
        let cs = wgpu::ShaderStages::COMPUTE;
        let g = &scene.geometry;
        let scene_box = session.scene.bounds();
        let boxes = (g.virtual_box(), scene_box);
        let inner = (settings.extent, settings.resolution);
        let flags = volume::flags(settings, session.scene.has_virtual_lights());
        let mut cascades = vec![Cascade::new(device, "dvct", settings, inner, boxes, g.triangle_count, flags)];
        if settings.outer_scale > 1.0 {
            let outer = (settings.extent * settings.outer_scale, settings.outer_voxels());
            cascades.push(Cascade::new(device, "dvct/outer", settings, outer, boxes, g.triangle_count, flags));
        }
        let outermost = cascades.last().expect("one cascade");

        // Voxelisation.
        // Both groups over the triangles start with the volume's uniform and the geometry.
        let geometry_entries = [
            bind::uniform(0, cs),
            bind::storage(1, cs),
            bind::storage(2, cs),
            bind::storage(3, cs),
            bind::storage(4, cs),
        ];
        let mut entries = geometry_entries.to_vec();
        entries.push(bind::storage_rw(5, cs));
        let voxelize_layout = bind::layout(device, "dvct/voxelize_layout", &entries);
        let voxelize_groups = cascades
            .iter()
            .map(|c| {
                let mut resources = geometry(c, g);
                resources.push(c.voxels.as_entire_binding());
                bind::group(device, "dvct/voxelize_group", &voxelize_layout, &resources)
            })
            .collect();
        let voxelize = compute_pipeline(device, "dvct/voxelize", VOXELIZE_SHADER, &[&voxelize_layout]);
        let clear = compute_pipeline_entry(device, "dvct/clear", VOXELIZE_SHADER, "clear", &[&voxelize_layout]);

        // Shared groups of the light and bounce passes: the voxels' surfaces.
        let mut entries = geometry_entries.to_vec();
        entries.extend([bind::storage(5, cs), bind::storage(6, cs)]);
        let surface_layout = bind::layout(device, "dvct/surface_layout", &entries);
        let surface_group = |c: &Cascade| {
            let mut resources = geometry(c, g);
            resources.push(scene.materials.buffer.as_entire_binding());
            resources.push(c.voxels.as_entire_binding());
            bind::group(device, "dvct/surface_group", &surface_layout, &resources)
        };
        let storage_3d = |i| bind::storage_texture_of(i, volume::FORMAT, wgpu::TextureViewDimension::D3);
        let out_layout = bind::layout(device, "dvct/out_layout", &[storage_3d(0), storage_3d(1)]);
        let out_group = |pair: &VolumePair, label: &str| {
            let ([rv, ..], [r, ..]) = (pair.rv.level(0), pair.r.level(0));
            use wgpu::BindingResource::TextureView;
            bind::group(device, label, &out_layout, &[TextureView(&rv), TextureView(&r)])
        };
        use wgpu::BindingResource::{Sampler, TextureView};
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        // The light and bounce passes' group 2: the probe, the material textures and the frame.
        let mut entries = GpuProbe::layout_entries(cs).to_vec();
        entries.extend(GpuMaterials::texture_entries(4, cs));
        entries.push(bind::uniform(7, cs));
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        entries.extend([
            bind::texture(8, cs, unfilterable, d2),
            bind::texture(9, cs, unfilterable, d2),
            bind::texture(10, cs, wgpu::TextureSampleType::Uint, d2),
            bind::texture(11, cs, unfilterable, d2),
        ]);
        let probe_textures_layout = bind::layout(device, "dvct/probe_textures_layout", &entries);
        let mut resources = scene.probe.resources().to_vec();
        resources.extend(scene.materials.texture_resources());
        resources.push(frame_uniforms.as_entire_binding());
        resources.extend([
            TextureView(&gbuffer.depth_motion.view),
            TextureView(&gbuffer.normal_roughness.view),
            TextureView(&gbuffer.flags.view),
            TextureView(&photo.view),
        ]);
        let probe_textures_group = bind::group(device, "dvct/probe_textures_group", &probe_textures_layout, &resources);

        // First bounce.
        let shadow_params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dvct/shadow_params"),
            contents: bytemuck::bytes_of(&ShadowParams::new(&session.settings.shadows, false)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let lights_layout = bind::layout(
            device,
            "dvct/lights_layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage(4, cs),
            ],
        );
        let lights_group = bind::group(
            device,
            "dvct/lights_group",
            &lights_layout,
            &[
                frame_uniforms.as_entire_binding(),
                shadow_params.as_entire_binding(),
                scene.lights.as_entire_binding(),
                scene.shadow_matrices.as_entire_binding(),
                shadow_maps.as_entire_binding(),
            ],
        );
        // The first bounce's volumes and the voxels' normals (VoxelNormals).
        let normal_3d = |i| bind::storage_texture_of(i, volume::NORMAL_FORMAT, wgpu::TextureViewDimension::D3);
        let light_out_layout =
            bind::layout(device, "dvct/light_out_layout", &[storage_3d(0), storage_3d(1), normal_3d(2), normal_3d(3)]);
        let light_pipeline = compute_pipeline(
            device,
            "dvct/light",
            LIGHT_SHADER,
            &[&surface_layout, &lights_layout, &probe_textures_layout, &light_out_layout],
        );
        let light = cascades
            .iter()
            .map(|c| {
                let groups = vec![surface_group(c), lights_group.clone(), probe_textures_group.clone(), {
                    let ([rv, ..], [r, ..]) = (c.first.rv.level(0), c.first.r.level(0));
                    let [n_rv, n_r] = &c.normals.views;
                    let resources = [&rv, &r, n_rv, n_r].map(TextureView);
                    bind::group(device, "dvct/first_bounce_out_group", &light_out_layout, &resources)
                }];
                (light_pipeline.clone(), groups)
            })
            .collect();

        // Sampled volumes (the second bounce's and the pixels' cones).
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("dvct/volume_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        // cones.wgsl's group 1: the volume's bases, the sampler, its axis chains, then the outer
        // volume's uniform, bases and chains (VolumePair::sampled).
        let volume_3d = |i| bind::texture(i, cs, filterable, wgpu::TextureViewDimension::D3);
        let mut entries = vec![volume_3d(0), volume_3d(1), bind::sampler(2, cs, wgpu::SamplerBindingType::Filtering)];
        entries.extend((3..9).map(volume_3d));
        entries.push(bind::uniform(9, cs));
        entries.extend((10..18).map(volume_3d));
        let volume_layout = bind::layout(device, "dvct/volume_layout", &entries);
        // The bases (the voxels themselves) of `based`, the chains of `pair`: a third bounce
        // adds to the first bounce's voxels what it gathers through the second's chains (its
        // samples finer than the chains' first level, within a voxel or two of the voxel,
        // read the first bounce's voxels).
        let mixed_group =
            |based: &VolumePair, pair: &VolumePair, outer: &VolumePair, outer_params: &wgpu::Buffer, label: &str| {
                let bases = &based.sampled[..2];
                let chains = &pair.sampled[2..];
                let mut resources = vec![TextureView(&bases[0]), TextureView(&bases[1]), Sampler(&sampler)];
                resources.extend(chains.iter().map(TextureView));
                resources.push(outer_params.as_entire_binding());
                resources.extend(outer.sampled.iter().map(TextureView));
                bind::group(device, label, &volume_layout, &resources)
            };
        let volume_group = |pair: &VolumePair, outer: &VolumePair, outer_params: &wgpu::Buffer, label: &str| {
            mixed_group(pair, pair, outer, outer_params, label)
        };

        // The raw volumes as a bounce's output (before the photo pass).
        let raw_out_group = |raw: &RawPair, label: &str| {
            let [rv, r] = &raw.views;
            bind::group(device, label, &out_layout, &[TextureView(rv), TextureView(r)])
        };

        // Second bounce: each cascade's voxels gather its first bounce and the outer one's.
        let mut bounce = Vec::new();
        if settings.bounces >= 2 {
            let pipeline = compute_pipeline(
                device,
                "dvct/bounce",
                BOUNCE_SHADER,
                &[&surface_layout, &volume_layout, &probe_textures_layout, &out_layout],
            );
            for c in &cascades {
                let second = c.second.as_ref().expect("two bounces");
                // Into the volumes the cones read, or before the photo's light (photo pass).
                let out = match &c.raw {
                    Some(raw) => raw_out_group(raw, "dvct/second_bounce_raw_group"),
                    None => out_group(second, "dvct/second_bounce_out_group"),
                };
                let groups = vec![
                    surface_group(c),
                    volume_group(&c.first, &outermost.first, &outermost.params_buffer, "dvct/first_bounce_group"),
                    probe_textures_group.clone(),
                    out,
                ];
                bounce.push((pipeline.clone(), groups));
            }
        }

        // Third bounce (`dvct.bounces` = 3): each cascade's voxels gather the second bounce
        // (after its photo's light) and add it to their first, into the raw volumes; its photo
        // pass then writes the first bounce's volumes, which the pixels' cones read.
        let mut third = Vec::new();
        if settings.bounces >= 3 {
            let (pipeline, _) = &bounce[0];
            for c in &cascades {
                let (Some(second), Some(raw)) = (&c.second, &c.raw) else { continue };
                let groups = vec![
                    surface_group(c),
                    mixed_group(
                        &c.first,
                        second,
                        outermost.second.as_ref().expect("three bounces"),
                        &outermost.params_buffer,
                        "dvct/third_bounce_group",
                    ),
                    probe_textures_group.clone(),
                    raw_out_group(raw, "dvct/third_bounce_raw_group"),
                ];
                third.push((pipeline.clone(), groups));
            }
        }

        // The photo's light in the second bounce's real voxels (photo_pass.wgsl).
        // A 3D texture read texel by texel (the raw volumes, the mipmaps' finer level).
        let unfiltered_3d = |i| {
            let unfiltered = wgpu::TextureSampleType::Float { filterable: false };
            bind::texture(i, cs, unfiltered, wgpu::TextureViewDimension::D3)
        };
        let mut photo_passes = Vec::new();
        let mut third_photo = Vec::new();
        if cascades.iter().any(|c| c.raw.is_some()) {
            let raw_layout = bind::layout(device, "dvct/raw_layout", &[unfiltered_3d(0), unfiltered_3d(1)]);
            let pipeline = compute_pipeline(
                device,
                "dvct/photo",
                PHOTO_SHADER,
                &[&surface_layout, &raw_layout, &probe_textures_layout, &out_layout],
            );
            for c in &cascades {
                let (Some(raw), Some(second)) = (&c.raw, &c.second) else { continue };
                let [rv, r] = &raw.views;
                let groups = vec![
                    surface_group(c),
                    bind::group(device, "dvct/raw_group", &raw_layout, &[TextureView(rv), TextureView(r)]),
                    probe_textures_group.clone(),
                    out_group(second, "dvct/photo_out_group"),
                ];
                if !third.is_empty() {
                    let mut groups = groups.clone();
                    groups[3] = out_group(&c.first, "dvct/third_photo_out_group");
                    third_photo.push((pipeline.clone(), groups));
                }
                photo_passes.push((pipeline.clone(), groups));
            }
        }

        // Mipmaps: the chains of one solution per dispatch, with its voxels' normals.
        let mips_entries: Vec<_> =
            (0..3).map(unfiltered_3d).chain((3..6).map(storage_3d)).chain([unfiltered_3d(6)]).collect();
        let mips_layout = bind::layout(device, "dvct/mips_layout", &mips_entries);
        let mips = compute_pipeline(device, "dvct/mips", MIPS_SHADER, &[&mips_layout]);
        let mips_base = compute_pipeline_entry(device, "dvct/mips_base", MIPS_SHADER, "cs_base", &[&mips_layout]);
        let chain = |pairs: Vec<(&VolumePair, &VoxelNormals)>| {
            let mut groups = Vec::new();
            for (pair, normals) in pairs {
                let res = pair.resolution();
                for level in 1..levels(res) {
                    for (volume, normal) in [&pair.rv, &pair.r].into_iter().zip(&normals.views) {
                        let finer = volume.level(level - 1);
                        let out = volume.level(level);
                        let resources: Vec<_> = finer.iter().chain(&out).chain([normal]).map(TextureView).collect();
                        let group = bind::group(device, "dvct/mips_group", &mips_layout, &resources);
                        groups.push(MipDispatch { group, side: res >> level, from_voxels: level == 1 });
                    }
                }
            }
            groups
        };
        let first_mips = chain(cascades.iter().map(|c| (&c.first, &c.normals)).collect());
        let second_mips = chain(cascades.iter().filter_map(|c| Some((c.second.as_ref()?, &c.normals))).collect());

        // The pixels' cones, once per trace texel, then resolved per pixel, then those of the
        // pixels that no texel around them is like.
        let inner = &cascades[0];
        let volumes = volume_group(inner.lit(), outermost.lit(), &outermost.params_buffer, "dvct/volume_group");
        // After a third bounce they read the first bounce's volumes, into which it went.
        let third_volumes = (!third.is_empty())
            .then(|| volume_group(&inner.first, &outermost.first, &outermost.params_buffer, "dvct/third_volume_group"));
        let cone_volumes = [volumes.clone(), third_volumes.unwrap_or_else(|| volumes.clone())];
        let pixels::PixelPasses { trace, resolve, retrace, indirect, probe_maps, still_rays } =
            pixels::PixelPasses::new(inputs, inner, &volume_layout, volumes);
        Self {
            cascades,
            scene_box,
            clear,
            voxelize,
            voxelize_groups,
            light,
            bounce,
            photo: photo_passes,
            third,
            third_photo,
            third_moving: settings.third_bounce_moving,
            third_done: false,
            cone_volumes,
            mips_base,
            mips,
            first_mips,
            second_mips,
            trace,
            resolve,
            retrace,
            still_rays,
            indirect,
            probe_maps,
            shadows: session.settings.shadows,
            stale_voxels: true,
            stale_light: true,
            stale_photo: false,
            photo_voxels: settings.photo_voxels,
            probe_regions: session
                .environment
                .as_ref()
                .filter(|_| settings.sample_probe_lights && settings.probe_lights > 0)
                .map(|env| ProbeRegions::new(env, settings.probe_lights)),
            still_frames: 0,
            stale_probe_maps: true,
        }
    }

    /// The uniform of the volume around the virtual content (where the cube lies).
    pub fn params(&self) -> VolumeParams {
        self.cascades[0].params
    }

    /// The voxelisation of the volume around the virtual content: per voxel, the real and the
    /// virtual triangle + 1 (0: empty).
    pub fn voxels(&self) -> &wgpu::Buffer {
        &self.cascades[0].voxels
    }

    /// The light volumes the pixels' cones read in the volume around the virtual content (the
    /// second bounce's, else the first's; the first's once a third bounce went into them).
    pub fn volumes(&self) -> &VolumePair {
        let inner = &self.cascades[0];
        if self.third_done { &inner.first } else { inner.lit() }
    }

    /// The normals of the voxels of the volume around the virtual content.
    pub fn normals(&self) -> &VoxelNormals {
        &self.cascades[0].normals
    }

    fn record_mips(&self, pass: &mut wgpu::ComputePass<'_>, dispatches: &[MipDispatch]) {
        for d in dispatches {
            pass.set_pipeline(if d.from_voxels { &self.mips_base } else { &self.mips });
            pass.set_bind_group(0, &d.group, &[]);
            // Both ways of each chain, side by side along x (Volume::chains).
            let n = d.side.div_ceil(4);
            pass.dispatch_workgroups((2 * d.side).div_ceil(4), n, n);
        }
    }

    /// Whether nothing changed since the last frame: a still view's frames draw the probe's
    /// lights anew, retrace the pixels no block is like and gather the virtual texels' thin
    /// rays.
    fn view_still(&self) -> bool {
        self.still_frames > 0
    }

    /// Records one pass per cascade (`passes` in the cascades' order).
    fn record_voxel_passes(&self, pass: &mut wgpu::ComputePass<'_>, passes: &[VoxelPass]) {
        for ((pipeline, bind_groups), cascade) in passes.iter().zip(&self.cascades) {
            let groups = cascade.resolution().div_ceil(4);
            set_pipeline_and_groups(pass, pipeline, bind_groups);
            pass.dispatch_workgroups(groups, groups, groups);
        }
    }
}

impl LightTransport for DvctMethod {
    fn prepare(&mut self, queue: &wgpu::Queue, change: &FrameChange) {
        if change.geometry_moved || change.vertices_deformed {
            let boxes = (change.geometry.virtual_box(), self.scene_box);
            for c in &mut self.cascades {
                c.follow(queue, boxes);
            }
            self.probe_maps.follow(queue, self.cascades[0].cube(), self.scene_box, &self.shadows);
            self.stale_voxels = true;
        }
        self.stale_light |= self.stale_voxels || change.moved_light_layers.is_some();
        self.stale_probe_maps |= self.stale_voxels;
        let moved = change.geometry_moved
            || change.vertices_deformed
            || change.moved_light_layers.is_some()
            || change.camera_moved
            || change.photo_changed;
        self.still_frames = if moved { 0 } else { self.still_frames + 1 };
        self.still_rays.set_frame(queue, self.still_frames);
        // A still view draws the probe's lights anew each frame (`dvct.sample_probe_lights`),
        // a moving one keeps the fixed ones.
        if let Some(regions) = &self.probe_regions {
            let sampling = self.view_still();
            if sampling || self.probe_maps.sampled() {
                let samples = sampling.then(|| regions.sampled(self.still_frames));
                self.probe_maps.sample_lights(queue, samples, self.cascades[0].cube(), self.scene_box, &self.shadows);
                self.stale_probe_maps = true;
            }
        }
        // The photo's light in the real voxels (photo.wgsl) follows the photo and what the
        // camera sees: the photo pass runs again (with one bounce, the light pass).
        self.stale_photo |= self.photo_voxels && (change.photo_changed || change.camera_moved);
    }

    fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        if std::mem::take(&mut self.stale_probe_maps) {
            self.probe_maps.record(rec, rasterizer);
        }
        if std::mem::take(&mut self.stale_voxels) {
            rec.compute(Self::VOXELIZE_LABEL, |pass| {
                for (c, group) in self.cascades.iter().zip(&self.voxelize_groups) {
                    pass.set_bind_group(0, group, &[]);
                    pass.set_pipeline(&self.clear);
                    dispatch_linear(pass, c.voxel_words, 64);
                    pass.set_pipeline(&self.voxelize);
                    dispatch_linear(pass, c.params.info.z, 1);
                }
            });
        }
        let stale_photo = std::mem::take(&mut self.stale_photo);
        let stale_light = std::mem::take(&mut self.stale_light);
        // The first bounce when the scene's light changed, or when it is the only one and the
        // photo did (it takes the photo's light itself); the second when the light changed; the
        // photo pass after either, or alone when only the photo or the camera did.
        if stale_light || (stale_photo && self.bounce.is_empty()) {
            rec.compute(Self::LIGHT_LABEL, |pass| {
                self.record_voxel_passes(pass, &self.light);
                self.record_mips(pass, &self.first_mips);
            });
        }
        if stale_light && !self.bounce.is_empty() {
            rec.compute(Self::BOUNCE_LABEL, |pass| {
                self.record_voxel_passes(pass, &self.bounce);
                if self.photo.is_empty() {
                    self.record_mips(pass, &self.second_mips);
                }
            });
        }
        // The third bounce (`dvct.bounces` = 3) in the first frame in which the content and the
        // lights rest, or in this one with `dvct.third_bounce_moving`; once gathered, a new
        // photo or camera alone puts the photo's light in its voxels again (the second
        // bounce's keep the photo of the frame the light last changed in, as the first's do).
        if stale_light {
            self.third_done = false;
        }
        let gather_third = !self.third.is_empty() && !self.third_done && (!stale_light || self.third_moving);
        let photo_again = stale_photo && !self.third_done;
        if (stale_light || photo_again) && !self.photo.is_empty() {
            rec.compute(Self::PHOTO_LABEL, |pass| {
                self.record_voxel_passes(pass, &self.photo);
                self.record_mips(pass, &self.second_mips);
            });
        }
        if gather_third || (stale_photo && self.third_done) {
            rec.compute(Self::THIRD_LABEL, |pass| {
                if gather_third {
                    self.record_voxel_passes(pass, &self.third);
                }
                self.record_voxel_passes(pass, &self.third_photo);
                self.record_mips(pass, &self.first_mips);
            });
            self.third_done = true;
        }
        let volumes = &self.cone_volumes[self.third_done as usize];
        self.trace.groups[1] = volumes.clone();
        self.retrace.set_volumes(volumes);
        self.retrace.begin(&mut rec.encoder, self.view_still());
        rec.compute(Self::LABEL, |pass| {
            self.trace.record(pass);
            self.resolve.record(pass);
            self.retrace.record(pass);
        });
    }

    fn indirect(&self) -> Option<&IndirectLight> {
        Some(&self.indirect)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

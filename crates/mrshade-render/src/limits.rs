//! Fitting a session to the device before anything is allocated on it.
//!
//! Every large GPU resource the renderer makes is sized here from the scene, the output size
//! and the settings, and checked against the device's limits (one buffer binding, one texture
//! side, texture-array layers) and against the session's GPU memory budget
//! (`limits.gpu_mib`). What can shrink without changing what is computed, only its
//! resolution, is halved until it fits, with a warning naming the setting: shadow maps, RSMs,
//! ISM tiles, ISM points, supersampling. What cannot (too many lights, triangles or textures
//! for this device, an output too large) is an error naming the input and the limit, before
//! wgpu would fail with a validation error.

use crate::scene_gpu::{GpuInstance, GpuMaterial, MAX_FRUSTUM_HALF_ANGLE, Vertex};
use anyhow::{Result, bail};
use mrshade_core::settings::{Intersection, RenderSettings, SpecularSettings};
use mrshade_scene::{LightKind, OutputSize, Scene, Session};
use std::mem::size_of;

/// Bytes of one compute-raster view beyond its target: its big-triangle list (16384 records
/// of 80 bytes, `raster::BIG_CAPACITY × raster::BIG_RECORD_BYTES`).
pub(crate) const VIEW_BYTES: u64 = 16384 * 80;
/// Bytes per internal pixel of the screen targets every method has: the G-buffer (six
/// targets, 44 bytes), its visibility buffer (8), `L_rv` and `L_r` (16); per output pixel the
/// photo, the composite and α (40).
const SCREEN_BYTES: u64 = 44 + 8 + 16;
const OUTPUT_BYTES: u64 = 40;
/// Bytes per scene vertex, index, placed triangle, placed primitive and material on the GPU.
const VERTEX_BYTES: u64 = size_of::<Vertex>() as u64;
const INDEX_BYTES: u64 = 4;
const TRIANGLE_BYTES: u64 = 16;
const INSTANCE_BYTES: u64 = size_of::<GpuInstance>() as u64;
const MATERIAL_BYTES: u64 = size_of::<GpuMaterial>() as u64;

/// Shadow-map layers of `scene`'s lights: real-only and virtual-only sets, six faces for
/// point lights and wide spots.
pub fn shadow_layer_count(scene: &Scene) -> u64 {
    scene
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Directional => 2,
            LightKind::Spot { outer_cone, .. } if outer_cone <= MAX_FRUSTUM_HALF_ANGLE => 2,
            _ => 12,
        })
        .sum()
}

/// Shrinking settings to a device: what every method's `fit` is given.
pub struct Fit<'a> {
    /// Shadow-map layers of the scene's lights (at least 1).
    pub shadow_layers: u64,
    /// Largest buffer binding, in bytes.
    pub max_binding: u64,
    /// Number of lights, for messages.
    pub lights: usize,
    /// Largest 3D texture side.
    pub max_texture_3d: u32,
    warnings: &'a mut Vec<String>,
}

impl Fit<'_> {
    /// Halves `value` (named `name` in the warning) down to `minimum` until `fits`; whether
    /// it fits in the end.
    pub fn shrink(&mut self, name: &str, value: &mut u32, fits: &dyn Fn(u64) -> bool, minimum: u32) -> bool {
        let requested = *value;
        while *value > minimum && !fits(*value as u64) {
            *value /= 2;
        }
        if *value != requested {
            self.warnings.push(format!(
                "{name} = {requested} needs more GPU memory in one buffer than this device binds ({} MiB); using {}",
                self.max_binding >> 20,
                *value
            ));
        }
        fits(*value as u64)
    }
}

/// The largest `caustics.buffer_divisor` (its settings' bound).
const MAX_CAUSTIC_DIVISOR: u32 = 8;

/// What a device allows, from `wgpu::Limits`.
#[derive(Clone, Copy, Debug)]
pub struct DeviceLimits {
    /// Largest storage-buffer binding (and buffer), in bytes.
    pub max_binding: u64,
    /// Largest 2D texture side.
    pub max_texture_side: u32,
    /// Most layers of a texture array.
    pub max_array_layers: u32,
    /// Largest 3D texture side.
    pub max_texture_3d: u32,
}

impl From<&wgpu::Limits> for DeviceLimits {
    fn from(l: &wgpu::Limits) -> Self {
        Self {
            max_binding: l.max_storage_buffer_binding_size.min(l.max_buffer_size),
            max_texture_side: l.max_texture_dimension_2d,
            max_array_layers: l.max_texture_array_layers,
            max_texture_3d: l.max_texture_dimension_3d,
        }
    }
}

/// The settings and output size `session` renders with on a device of `device` limits, and
/// what had to change; or why it cannot render there at all.
pub fn fit_to_device(session: &Session, device: DeviceLimits) -> Result<(RenderSettings, OutputSize, Vec<String>)> {
    let scene = &session.scene;
    let mut settings = session.settings.clone();
    let mut output = session.output;
    let mut warnings = Vec::new();
    let max_binding = device.max_binding;
    let layers = shadow_layer_count(scene).max(1);
    let mut fit = Fit {
        shadow_layers: layers,
        max_binding,
        lights: scene.lights.len(),
        max_texture_3d: device.max_texture_3d,
        warnings: &mut warnings,
    };
    let screen_fits = |ss: u64| {
        let (w, h) = (output.width as u64 * ss, output.height as u64 * ss);
        w <= device.max_texture_side as u64 && h <= device.max_texture_side as u64 && w * h * 8 <= max_binding
    };
    if !fit.shrink("output.supersample", &mut output.supersample, &screen_fits, 1) {
        bail!(
            "the output of {}×{} pixels is larger than this device renders (textures of at most {} pixels a side, \
             a visibility buffer of at most {} MiB); lower --width/--height",
            output.width,
            output.height,
            device.max_texture_side,
            max_binding >> 20
        );
    }
    let shadow_fits = |res: u64| layers * res * res * 8 <= max_binding;
    if !fit.shrink("shadows.resolution", &mut settings.shadows.resolution, &shadow_fits, 64) {
        bail!(
            "the scene's {} lights need {layers} shadow-map layers, more than one GPU buffer of this device holds \
             ({} MiB) even at 64×64 texels; remove lights",
            scene.lights.len(),
            max_binding >> 20
        );
    }
    // The photon G-buffers of every light in one buffer (specular/caustics), and the photon
    // grid's entries, the largest of its buffers per photon slot: fewer photons.
    let lights = scene.lights.len().max(1) as u64;
    use crate::specular::caustics::{GRID_ENTRY_BYTES_PER_SLOT, PHOTON_BYTES, PHOTON_KINDS};
    let light_photon_bytes = PHOTON_BYTES.max(GRID_ENTRY_BYTES_PER_SLOT) * PHOTON_KINDS;
    let photons_fit = |res: u64| lights * res * res * light_photon_bytes <= max_binding;
    if !fit.shrink("caustics.photon_resolution", &mut settings.caustics.photon_resolution, &photons_fit, 8) {
        bail!(
            "the scene's {} lights need more photon G-buffers than one GPU buffer of this device holds ({} MiB) \
             even at 8×8 photons; remove lights or set caustics.enabled = false",
            scene.lights.len(),
            max_binding >> 20
        );
    }
    // The probe's directions, in a buffer of their own (not in the grid).
    let directions = settings.caustics.environment_directions as u64;
    let probe_photons_fit = |res: u64| directions * res * res * PHOTON_BYTES * PHOTON_KINDS <= max_binding;
    let resolution = &mut settings.caustics.environment_resolution;
    if !fit.shrink("caustics.environment_resolution", resolution, &probe_photons_fit, 4) {
        bail!(
            "caustics.environment_directions = {directions} need more photon G-buffers than one GPU buffer of this \
             device holds ({} MiB) even at 4×4 photons each; use fewer directions",
            max_binding >> 20
        );
    }
    // The caustic splat's fixed-point sums of both levels in one buffer: a coarser caustic
    // buffer (64 bytes a caustic texel: 33 MiB at 1080p and the default divisor 2).
    let frame = (output.width * output.supersample, output.height * output.supersample);
    let requested = settings.caustics.buffer_divisor;
    let divisor = &mut settings.caustics.buffer_divisor;
    while *divisor < MAX_CAUSTIC_DIVISOR && crate::specular::caustics::sum_bytes(frame, *divisor) > max_binding {
        *divisor += 1;
    }
    if *divisor != requested {
        fit.warnings.push(format!(
            "caustics.buffer_divisor = {requested} needs more GPU memory in one buffer than this device binds ({} \
             MiB); using {}",
            max_binding >> 20,
            *divisor
        ));
    }
    // The specular stage's impostors or cube faces, and the planar reflectors' views at the
    // frame's size, in one buffer: coarser slices.
    let slices = specular_slices(scene, &settings.specular);
    let planar = planar_bytes(scene, &settings.specular, &output);
    let slices_fit = |res: u64| slices * res * res * 8 + planar <= max_binding;
    let (name, side) = match settings.specular.intersection {
        Intersection::Impostor | Intersection::Planar => {
            ("specular.impostor_resolution", &mut settings.specular.impostor_resolution)
        }
        Intersection::Cube | Intersection::LayeredCube => {
            ("specular.cube_resolution", &mut settings.specular.cube_resolution)
        }
    };
    if !fit.shrink(name, side, &slices_fit, 16) {
        bail!(
            "the scene's traced objects need {slices} impostor slices (or cube faces), more than one GPU buffer of \
             this device holds ({} MiB) even at 16×16 texels; trace fewer objects or set specular.enabled = false",
            max_binding >> 20
        );
    }
    (crate::methods::entry(settings.method).fit)(&mut settings, &mut fit)?;
    check_scene_buffers(scene, device)?;
    let estimate = estimate(scene, &settings, &output);
    let budget = session.limits.gpu_bytes();
    if estimate.total() > budget {
        bail!(
            "rendering this session needs about {} MiB of GPU memory ({}), more than `limits.gpu_mib` = {} \
             (raise it with --set limits.gpu_mib=N, or lower the output size or the settings named)",
            estimate.total() >> 20,
            estimate.largest(),
            budget >> 20
        );
    }
    Ok((settings, output, warnings))
}

/// Slices of the specular stage's views: per traced instance and every other instance, one
/// impostor or six cube faces.
fn specular_slices(scene: &Scene, specular: &SpecularSettings) -> u64 {
    let traced = scene.instances.iter().filter(|i| crate::specular::traces_instance(scene, specular, i)).count() as u64;
    let others = (scene.instances.len() as u64).saturating_sub(1);
    traced * others * crate::specular::impostors::slices_per_pair(specular.intersection) as u64
}

/// Bytes of the planar reflectors' views (`specular.intersection = "planar"`): one or two per
/// flat traced instance, at the internal frame size.
fn planar_bytes(scene: &Scene, specular: &SpecularSettings, output: &OutputSize) -> u64 {
    let views: u32 = crate::specular::planar::reflectors(scene, specular).iter().map(|r| r.views()).sum();
    let ss = output.supersample;
    views as u64 * crate::raster::shared_view_bytes((output.width * ss, output.height * ss))
}

/// The scene's own buffers and textures: geometry in single bindings, textures in two arrays.
fn check_scene_buffers(scene: &Scene, device: DeviceLimits) -> Result<()> {
    let (vertices, indices, triangles) = geometry_counts(scene);
    for (what, bytes) in [
        (format!("{vertices} vertices"), vertices * VERTEX_BYTES),
        (format!("{indices} indices"), indices * INDEX_BYTES),
        (format!("{triangles} placed triangles"), triangles * TRIANGLE_BYTES),
        (format!("{} placed primitives", scene.instances.len()), scene.instances.len() as u64 * INSTANCE_BYTES),
        (format!("{} materials", scene.materials.len()), scene.materials.len() as u64 * MATERIAL_BYTES),
    ] {
        if bytes > device.max_binding {
            bail!(
                "the scene's {what} need {} MiB in one GPU buffer; this device binds at most {} MiB",
                bytes >> 20,
                device.max_binding >> 20
            );
        }
    }
    let srgb = scene.textures.iter().filter(|t| t.srgb).count();
    let linear = scene.textures.len() - srgb;
    if srgb.max(linear) > device.max_array_layers as usize {
        bail!(
            "the scene has {srgb} colour and {linear} data textures; this device holds at most {} of each",
            device.max_array_layers
        );
    }
    Ok(())
}

/// Vertices and indices of all primitives, triangles of all instances.
fn geometry_counts(scene: &Scene) -> (u64, u64, u64) {
    let vertices = scene.primitives.iter().map(|p| p.positions.len() as u64).sum();
    let indices = scene.primitives.iter().map(|p| p.indices.len() as u64).sum();
    let triangles = scene.instances.iter().map(|i| scene.primitives[i.primitive].indices.len() as u64 / 3).sum();
    (vertices, indices, triangles)
}

/// The largest GPU allocations of a session, by what sizes them.
struct Estimate(Vec<(&'static str, u64)>);

impl Estimate {
    fn total(&self) -> u64 {
        self.0.iter().map(|(_, b)| b).sum()
    }

    /// The two largest items, in MiB.
    fn largest(&self) -> String {
        let mut items = self.0.clone();
        items.sort_by_key(|(_, b)| std::cmp::Reverse(*b));
        let shown: Vec<String> = items.iter().take(2).map(|(what, b)| format!("{what}: {} MiB", b >> 20)).collect();
        shown.join(", ")
    }
}

/// GPU bytes of `scene` rendered at `output` with `settings`, item by item.
fn estimate(scene: &Scene, settings: &RenderSettings, output: &OutputSize) -> Estimate {
    let layers = shadow_layer_count(scene);
    let (vertices, indices, triangles) = geometry_counts(scene);
    let internal = output.width as u64 * output.height as u64 * (output.supersample as u64).pow(2);
    let texture_bytes: u64 = scene.textures.iter().map(|t| t.width as u64 * t.height as u64 * 4 * 4 / 3).sum();
    let res = settings.shadows.resolution as u64;
    let mut items = vec![
        ("screen targets (output size × supersample²)", internal * SCREEN_BYTES),
        ("output images", output.width as u64 * output.height as u64 * OUTPUT_BYTES),
        ("shadow maps (lights × shadows.resolution²)", layers * (res * res * 8 + VIEW_BYTES)),
        (
            "geometry",
            vertices * VERTEX_BYTES
                + indices * INDEX_BYTES
                + triangles * TRIANGLE_BYTES
                + scene.instances.len() as u64 * INSTANCE_BYTES,
        ),
        ("textures", texture_bytes),
    ];
    let side = crate::specular::impostors::slice_resolution(&settings.specular) as u64;
    items.push((
        "specular impostors or cube faces (slices × resolution²), planar views",
        specular_slices(scene, &settings.specular) * side * side * 8 + planar_bytes(scene, &settings.specular, output),
    ));
    // The caustics' photon G-buffers, where the specular stage runs.
    let traced = scene.materials.iter().any(|m| settings.specular.traces(m.metallic, m.roughness, m.transmission));
    if traced && settings.caustics.enabled {
        let c = &settings.caustics;
        let texels = |sources: u64, res: u32| sources * res as u64 * res as u64;
        use crate::specular::caustics::{
            GRID_BYTES_PER_SLOT, GRID_HEADER_WORDS, GRID_HEADS, PHOTON_BYTES, PHOTON_KINDS, SPLAT_LIST_BYTES,
        };
        let photon_bytes = (PHOTON_BYTES + SPLAT_LIST_BYTES) * PHOTON_KINDS;
        let lights = texels(scene.lights.len() as u64, c.photon_resolution);
        let directions = texels(c.environment_directions as u64, c.environment_resolution);
        items.push((
            "caustic photons (lights × photon_resolution² + environment_directions × environment_resolution²)",
            (lights + directions) * photon_bytes,
        ));
        let ss = output.supersample;
        let frame = (output.width * ss, output.height * ss);
        items.push((
            "caustic splat sums (64 bytes a caustic-buffer texel)",
            crate::specular::caustics::sum_bytes(frame, c.buffer_divisor),
        ));
        if lights > 0 {
            items.push((
                "the lights' photons' world-space grid (heads, listed photons, entries)",
                (GRID_HEADER_WORDS + 2 * GRID_HEADS) * 4 + lights * PHOTON_KINDS * GRID_BYTES_PER_SLOT,
            ));
        }
    }
    items.extend((crate::methods::entry(settings.method).estimate)(settings, internal, layers));
    Estimate(items)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};
    use mrshade_core::HdrImage;
    use mrshade_core::flags::Realness;

    const SMALL_DEVICE: DeviceLimits =
        DeviceLimits { max_binding: 128 << 20, max_texture_side: 8192, max_array_layers: 256, max_texture_3d: 2048 };

    fn session(lights: usize, width: u32) -> Session {
        let mut scene = Scene::default();
        for i in 0..lights {
            scene.lights.push(mrshade_scene::Light {
                name: format!("lamp{i}"),
                kind: LightKind::Point,
                intensity: Vec3::ONE,
                world_from_light: Mat4::IDENTITY,
                realness: Realness::Real,
            });
        }
        let height = width * 3 / 4;
        Session {
            origin: "test".into(),
            scene,
            camera: 0,
            background: HdrImage::filled(1, 1, [0.0; 3]),
            exposure: 1.0,
            environment: None,
            output: OutputSize { width, height, supersample: 1, frames: 1 },
            settings: RenderSettings::default(),
            limits: Default::default(),
            warnings: Vec::new(),
            sequence: None,
            inserts: Vec::new(),
            folder: None,
        }
    }

    #[test]
    fn oversized_maps_are_halved_with_a_warning() {
        let (fitted, _, warnings) = fit_to_device(&session(1, 640), SMALL_DEVICE).unwrap();
        // 12 layers × 2048² × 8 B = 384 MiB > 128 MiB: 1024² (96 MiB) fits.
        assert_eq!(fitted.shadows.resolution, 1024);
        assert!(warnings.iter().any(|w| w.contains("shadows.resolution = 2048")), "{warnings:?}");
        let (same, _, none) = fit_to_device(&session(0, 640), SMALL_DEVICE).unwrap();
        assert_eq!(same, RenderSettings::default());
        assert!(none.is_empty());
    }

    #[test]
    fn what_cannot_shrink_is_an_error_naming_the_input() {
        // 10,000 point lights: 120,000 layers do not fit even at 64² texels.
        let err = fit_to_device(&session(10_000, 64), SMALL_DEVICE).unwrap_err().to_string();
        assert!(err.contains("10000 lights") && err.contains("120000"), "{err}");
        // Supersampling shrinks first; a too-large output is an error.
        let mut big = session(0, 4096);
        big.output.supersample = 4;
        let (_, output, warnings) = fit_to_device(&big, SMALL_DEVICE).unwrap();
        assert_eq!(output.supersample, 1);
        assert!(warnings.iter().any(|w| w.contains("output.supersample = 4")), "{warnings:?}");
        let err = fit_to_device(&session(0, 16384), SMALL_DEVICE).unwrap_err().to_string();
        assert!(err.contains("16384×12288"), "{err}");
    }

    #[test]
    fn oversized_photon_maps_are_halved_and_impossible_ones_refused() {
        // 1024 probe directions × 512² photons × 4 kinds × 48 B = 48 GiB: 32² (192 MiB) does
        // not fit 128 MiB either; 16² (48 MiB) does.
        let mut s = session(1, 640);
        s.settings.caustics.environment_directions = 1024;
        s.settings.caustics.environment_resolution = 512;
        let (fitted, _, warnings) = fit_to_device(&s, SMALL_DEVICE).unwrap();
        assert_eq!(fitted.caustics.environment_resolution, 16);
        assert!(warnings.iter().any(|w| w.contains("caustics.environment_resolution = 512")), "{warnings:?}");
        // A 1 MiB device: a 64×48 frame and its shadow maps fit; 1024 × 4² photons (3 MiB) do not.
        let mut small = session(1, 64);
        small.settings.caustics = s.settings.caustics;
        let tiny = DeviceLimits { max_binding: 1 << 20, ..SMALL_DEVICE };
        let err = fit_to_device(&small, tiny).unwrap_err().to_string();
        assert!(err.contains("caustics.environment_directions = 1024"), "{err}");
    }

    #[test]
    fn the_lights_photons_fit_with_their_grid() {
        // 20 lights × 128² photons × 4 kinds: 60 MiB of photon G-buffer fit 128 MiB, but the
        // grid's entries (27 × 4 B a photon, 135 MiB) do not; 64² (34 MiB) do.
        let (fitted, _, warnings) = fit_to_device(&session(20, 640), SMALL_DEVICE).unwrap();
        assert_eq!(fitted.caustics.photon_resolution, 64);
        assert!(warnings.iter().any(|w| w.contains("caustics.photon_resolution = 128")), "{warnings:?}");
    }

    #[test]
    fn the_caustic_splat_sums_fit_one_buffer() {
        // 4096×3072 at divisor 2: (2048·1536 + 256·192) texels × 64 B = 195 MiB, more than
        // 128 MiB; divisor 3 (1366·1024 + 171·128 texels, 87 MiB) fits.
        assert_eq!(crate::specular::caustics::sum_bytes((4096, 3072), 2), (2048 * 1536 + 256 * 192) * 64);
        let (fitted, _, warnings) = fit_to_device(&session(1, 4096), SMALL_DEVICE).unwrap();
        assert_eq!(fitted.caustics.buffer_divisor, 3);
        assert!(warnings.iter().any(|w| w.contains("caustics.buffer_divisor = 2")), "{warnings:?}");
        let (fitted, _, _) = fit_to_device(&session(1, 640), SMALL_DEVICE).unwrap();
        assert_eq!(fitted.caustics.buffer_divisor, 2);
    }

    #[test]
    fn the_specular_slices_shrink_to_one_buffer() {
        // 4 mirror balls among 20 instances: 4 × 19 pairs × 6 cube faces × 512² × 8 B =
        // 912 MiB; 128² texels (57 MiB) fit 128 MiB.
        let mut s = session(1, 640);
        s.scene.materials.push(mrshade_scene::Material::default());
        s.scene.materials.push(mrshade_scene::Material { metallic: 1.0, roughness: 0.0, ..Default::default() });
        s.scene.primitives.push(mrshade_scene::Primitive { material: 0, ..Default::default() });
        s.scene.primitives.push(mrshade_scene::Primitive { material: 1, ..Default::default() });
        for i in 0..20 {
            s.scene.instances.push(mrshade_scene::Instance {
                node_name: format!("n{i}"),
                primitive: usize::from(i < 4),
                world_from_object: Mat4::IDENTITY,
                realness: Realness::Virtual,
                skin: None,
                morph_weights: Vec::new(),
            });
        }
        s.settings.specular.intersection = mrshade_core::settings::Intersection::Cube;
        let (fitted, _, warnings) = fit_to_device(&s, SMALL_DEVICE).unwrap();
        assert_eq!(fitted.specular.cube_resolution, 128);
        assert!(warnings.iter().any(|w| w.contains("specular.cube_resolution = 512")), "{warnings:?}");
        // Impostors: one slice per pair, 152 MiB at 512²: 256² fits.
        s.settings.specular.intersection = mrshade_core::settings::Intersection::Impostor;
        let (fitted, _, _) = fit_to_device(&s, SMALL_DEVICE).unwrap();
        assert_eq!(fitted.specular.impostor_resolution, 256);
    }

    #[test]
    fn dlpv_visibility_maps_must_fit_one_buffer() {
        // dlpv.virtual_bounce at 64³ cells over the content's own size: 32³ parts × 2 KiB =
        // 64 MiB of visibility maps, one buffer; refused on a 16 MiB device, taken on 128 MiB.
        let mut s = session(1, 64);
        s.settings.method = mrshade_core::settings::Method::Dlpv;
        s.settings.dlpv.virtual_bounce = true;
        s.settings.dlpv.resolution = 64;
        s.settings.dlpv.extent = 1.0;
        let small = DeviceLimits { max_binding: 16 << 20, ..SMALL_DEVICE };
        let err = fit_to_device(&s, small).unwrap_err().to_string();
        assert!(err.contains("dlpv.virtual_bounce") && err.contains("64 MiB"), "{err}");
        s.limits.gpu_mib = 4096;
        fit_to_device(&s, SMALL_DEVICE).unwrap();
        s.settings.dlpv.virtual_bounce = false;
        fit_to_device(&s, small).unwrap();
    }

    #[test]
    fn the_gpu_budget_is_checked_before_allocation() {
        let mut s = session(0, 4096);
        s.limits.gpu_mib = 256;
        let err = fit_to_device(&s, DeviceLimits { max_binding: 1 << 40, ..SMALL_DEVICE }).unwrap_err().to_string();
        assert!(err.contains("`limits.gpu_mib` = 256") && err.contains("screen targets"), "{err}");
        // The defaults render 1080p with room to spare.
        fit_to_device(&session(2, 1920), SMALL_DEVICE).unwrap();
    }
}

//! Impostor sets (reflections spec §2.16.1–§2.16.2): for every traced instance, every other
//! instance seen from its centre through an orthographic camera fitted to that instance's
//! box, rasterised into one slice of a shared visibility array each frame. A flat instance
//! (a desk) is seen along its thin axis, the manual "world up" alignment the thesis used for
//! its desk, chosen here automatically. With `intersection = "cube"` or `"layered-cube"`
//! (spec §2.14, §2.15) each pair has six slices instead: the faces of a 90° cube map at the
//! traced instance's centre, in the order of `scene_gpu::cube_faces`. With `"planar"` (spec
//! §2.13) each flat reflector also has the view of its mirrored camera (two for a real one:
//! the whole world and the real-only one), after the pairs' slices, at the frame's size.

use super::planar::{self, Reflector};
use crate::raster::{Casters, RasterViews, Rasterizer, VIEW_ALIGN, ViewSpec, shared_view_bytes};
use crate::scene_gpu::Geometry;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};
use mrshade_core::flags::Realness;
use mrshade_core::settings::{Intersection, SpecularSettings};
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;
use wgpu::util::DeviceExt;

/// Mirrors `Impostor` in tracing.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuImpostor {
    /// Orthographic (an impostor) or one cube face's perspective, reversed depth (near → 1).
    pub clip_from_world: Mat4,
    /// Instance drawn, first texel of its slice, side in texels, unused.
    /// (a planar view: reflector, first texel, width, height).
    pub info: UVec4,
    /// Cube faces: the traced instance's centre, where the cube is; w: the faces' near plane
    /// (0 for an impostor). A planar view: its clip plane.
    pub eye: Vec4,
    /// The drawn instance's world box, where a layered cube is marched (w unused).
    pub seen_min: Vec4,
    /// See `seen_min`.
    pub seen_max: Vec4,
}

/// An instance whose thinnest side is below this fraction of its longest is flat: it is seen
/// along its thin axis, so that its one large face fills the impostor.
const FLAT_RATIO: f32 = 0.25;

/// Slices per (traced instance, seen instance) pair: 1 impostor or 6 cube faces.
pub fn slices_per_pair(intersection: Intersection) -> u32 {
    match intersection {
        Intersection::Impostor | Intersection::Planar => 1,
        Intersection::Cube | Intersection::LayeredCube => 6,
    }
}

/// Side of each slice, texels.
pub fn slice_resolution(settings: &SpecularSettings) -> u32 {
    match settings.intersection {
        Intersection::Impostor | Intersection::Planar => settings.impostor_resolution,
        Intersection::Cube | Intersection::LayeredCube => settings.cube_resolution,
    }
}

/// The impostors (or cube faces) of every traced instance.
pub struct Impostors {
    /// (traced instance, instance it sees) per pair.
    pairs: Vec<(usize, usize)>,
    intersection: Intersection,
    resolution: u32,
    /// One per slice.
    views: RasterViews,
    /// `GpuImpostor` per slice.
    pub table: wgpu::Buffer,
    /// Visibility texels of every slice, `resolution²` each.
    pub texels: wgpu::Buffer,
    /// Slice range per instance: first, count (0 for untraced instances).
    pub ranges: Vec<(u32, u32)>,
    /// The slices no longer show where the instances are (at first, and after a move).
    stale: bool,
    /// The flat reflectors and the first of their views (index into `planar_views`).
    reflectors: Vec<(Reflector, usize)>,
    /// The mirrored cameras' views, in table order after the pairs' slices.
    planar_views: RasterViews,
    /// Per instance: its planar views' slices (whole world, real-only), or `u32::MAX`.
    pub planar_slices: Vec<[u32; 2]>,
    /// The camera the planar views were drawn for (`None`: not yet, or a reflector moved).
    planar_camera: Option<Mat4>,
    planar_stale: bool,
}

impl Impostors {
    /// The slices of every (traced instance, other instance) pair, `resolution²` texels each,
    /// then the views of the flat `reflectors` at the frame's `size` (perspective, clipped at
    /// the camera's `near` plane).
    #[allow(clippy::too_many_arguments, reason = "the slices of the pairs and of the planar reflectors")]
    pub fn new(
        ctx: &GpuContext,
        rasterizer: &Rasterizer,
        geometry: &Geometry,
        traced: &[bool],
        settings: &SpecularSettings,
        reflectors: &[Reflector],
        size: (u32, u32),
        near: f32,
    ) -> Self {
        let n = geometry.instance_count();
        let per_pair = slices_per_pair(settings.intersection);
        let resolution = slice_resolution(settings);
        let mut pairs = Vec::new();
        let mut ranges = vec![(0, 0); n];
        for (s, _) in traced.iter().enumerate().filter(|(_, t)| **t) {
            ranges[s] = (pairs.len() as u32 * per_pair, (n as u32 - 1) * per_pair);
            pairs.extend((0..n).filter(|&o| o != s).map(|o| (s, o)));
        }
        let slice = resolution as u64 * resolution as u64;
        let slices = pairs.len() as u64 * per_pair as u64;
        let pair_bytes = (slices * slice * 8).next_multiple_of(VIEW_ALIGN);
        let planar_count: u32 = reflectors.iter().map(Reflector::views).sum();
        let view_bytes = shared_view_bytes(size);
        let texels = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("specular/impostor_texels"),
            size: (pair_bytes + planar_count as u64 * view_bytes).max(8),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let gpu = impostor_table(geometry, &pairs, settings.intersection, resolution);
        let specs: Vec<ViewSpec> = gpu
            .iter()
            .enumerate()
            .map(|(k, imp)| {
                let (_, first, count) = geometry.instance_triangles(imp.info.x as usize);
                ViewSpec {
                    size: (resolution, resolution),
                    casters: Casters::Range { first, count },
                    clip_from_world: imp.clip_from_world,
                    near: cube_near(imp),
                    offset: k as u64 * slice * 8,
                }
            })
            .collect();
        let views = rasterizer.views(ctx, geometry, "specular/impostors", Some(&texels), &specs);
        // The planar views: the mirrored cameras are set each frame (`update_planar`).
        let first_planar = gpu.len() as u32;
        let mut planar_specs = Vec::new();
        let mut planar_slices = vec![[u32::MAX; 2]; n];
        let mut planar_table = Vec::new();
        let mut placed = Vec::new();
        for r in reflectors {
            placed.push((*r, planar_specs.len()));
            let worlds: &[(Casters, usize)] =
                if r.real { &[(Casters::All, 0), (Casters::Only(Realness::Real), 1)] } else { &[(Casters::All, 0)] };
            for &(casters, k) in worlds {
                let index = planar_specs.len() as u64;
                let offset = pair_bytes + index * view_bytes;
                planar_slices[r.instance][k] = first_planar + index as u32;
                planar_table.push(GpuImpostor {
                    info: UVec4::new(r.instance as u32, (offset / 8) as u32, size.0, size.1),
                    ..GpuImpostor::zeroed()
                });
                planar_specs.push(ViewSpec { size, casters, clip_from_world: Mat4::IDENTITY, near, offset });
            }
        }
        let planar_views = rasterizer.views(ctx, geometry, "specular/planar", Some(&texels), &planar_specs);
        let mut all = gpu;
        all.extend(planar_table);
        let table = ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("specular/impostors"),
            contents: bytemuck::cast_slice(&pad(all)),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        Self {
            pairs,
            intersection: settings.intersection,
            resolution,
            views,
            table,
            texels,
            ranges,
            stale: true,
            reflectors: placed,
            planar_views,
            planar_slices,
            planar_camera: None,
            planar_stale: false,
        }
    }

    /// Aims every flat reflector's views at the camera `clip_from_world` (at `eye`) mirrored
    /// about its plane, when the camera or an instance moved.
    pub fn update_planar(&mut self, queue: &wgpu::Queue, geometry: &Geometry, clip_from_world: Mat4, eye: Vec3) {
        if self.planar_views.is_empty() || (self.planar_camera == Some(clip_from_world) && !geometry.moved()) {
            return;
        }
        self.planar_camera = Some(clip_from_world);
        self.planar_stale = true;
        let first_slice = self.views.len() as u64;
        let record_bytes = std::mem::size_of::<GpuImpostor>() as u64;
        let eye_offset = std::mem::offset_of!(GpuImpostor, eye) as u64;
        for &(r, first_view) in &self.reflectors {
            let plane = planar::world_plane(geometry.transform(r.instance), r.object_plane);
            let (lo, hi) = geometry.world_box(r.instance);
            // Clears the mirror itself and what merely touches it by a hair of its size.
            let margin = 1e-4 * (hi - lo).length();
            let (mirrored, clip_plane) = planar::mirrored_view(clip_from_world, eye, plane, margin);
            for k in 0..r.views() as usize {
                self.planar_views.set_clip_plane(first_view + k, clip_plane);
                self.planar_views.set_clip_from_world(queue, first_view + k, mirrored);
                // clip_from_world and, after info, the clip plane in `eye`.
                let record = (first_slice + (first_view + k) as u64) * record_bytes;
                queue.write_buffer(&self.table, record, bytemuck::bytes_of(&mirrored));
                queue.write_buffer(&self.table, record + eye_offset, bytemuck::bytes_of(&clip_plane));
            }
        }
    }

    /// Fits every slice's camera to where the instances are now, if any moved or deformed
    /// (the thesis: an update "is only required for a change in the alignment", §2.16.2).
    pub fn update(&mut self, queue: &wgpu::Queue, geometry: &Geometry) {
        if !geometry.moved() && !self.stale {
            return;
        }
        self.stale = true;
        let gpu = impostor_table(geometry, &self.pairs, self.intersection, self.resolution);
        for (i, imp) in gpu.iter().enumerate().take(self.views.len()) {
            self.views.set_clip_from_world(queue, i, imp.clip_from_world);
        }
        if !gpu.is_empty() {
            queue.write_buffer(&self.table, 0, bytemuck::cast_slice(&gpu));
        }
    }

    /// Rasterises every slice when they are stale.
    pub fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        if self.stale && !self.views.is_empty() {
            rasterizer.record(rec, "specular/impostors", [&self.views]);
        }
        self.stale = false;
        if self.planar_stale {
            rasterizer.record(rec, "specular/planar", [&self.planar_views]);
        }
        self.planar_stale = false;
    }
}

fn pad(mut gpu: Vec<GpuImpostor>) -> Vec<GpuImpostor> {
    if gpu.is_empty() {
        gpu.push(GpuImpostor::zeroed());
    }
    gpu
}

/// The near-plane distance of a cube face's perspective (0 for an orthographic impostor),
/// kept in its unused `eye.w`.
fn cube_near(imp: &GpuImpostor) -> f32 {
    imp.eye.w
}

/// Every slice's record: per pair, one impostor or six cube faces.
fn impostor_table(
    geometry: &Geometry,
    pairs: &[(usize, usize)],
    intersection: Intersection,
    resolution: u32,
) -> Vec<GpuImpostor> {
    let slice = resolution * resolution;
    let mut table = Vec::new();
    for &(s, o) in pairs {
        let (traced, seen) = (geometry.world_box(s), geometry.world_box(o));
        let record = |clip_from_world: Mat4, eye: Vec4| GpuImpostor {
            clip_from_world,
            info: UVec4::new(o as u32, 0, resolution, 0),
            eye,
            seen_min: seen.0.extend(0.0),
            seen_max: seen.1.extend(0.0),
        };
        match intersection {
            Intersection::Impostor | Intersection::Planar => {
                table.push(record(impostor_clip_from_world(traced, seen), Vec4::ZERO))
            }
            Intersection::Cube | Intersection::LayeredCube => {
                let eye = (traced.0 + traced.1) * 0.5;
                // Nothing else is inside the traced instance: a near plane well within it.
                let near = 1e-3 * (traced.1 - traced.0).length().max(1e-3);
                let faces =
                    crate::scene_gpu::cube_faces(eye, std::f32::consts::FRAC_PI_2 + crate::scene_gpu::FOV_MARGIN, near);
                table.extend(faces.map(|f| record(f, eye.extend(near))));
            }
        }
    }
    for (k, imp) in table.iter_mut().enumerate() {
        imp.info.y = k as u32 * slice;
    }
    table
}

/// The orthographic camera at the centre of `specular` looking at `seen` (or along its thin
/// axis when it is flat), fitted to `seen`'s box, with reversed depth.
pub fn impostor_clip_from_world(specular: (Vec3, Vec3), seen: (Vec3, Vec3)) -> Mat4 {
    let eye = (specular.0 + specular.1) * 0.5;
    let centre = (seen.0 + seen.1) * 0.5;
    let extent = seen.1 - seen.0;
    let thin = if extent.x <= extent.y && extent.x <= extent.z {
        0
    } else if extent.y <= extent.z {
        1
    } else {
        2
    };
    let dir = if extent[thin] < FLAT_RATIO * extent.max_element() {
        let mut axis = Vec3::ZERO;
        axis[thin] = if centre[thin] - eye[thin] >= 0.0 { 1.0 } else { -1.0 };
        axis
    } else {
        (centre - eye).try_normalize().unwrap_or(Vec3::NEG_Y)
    };
    let view = crate::scene_gpu::look_to(eye, dir);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { seen.0.x } else { seen.1.x },
            if i & 2 == 0 { seen.0.y } else { seen.1.y },
            if i & 4 == 0 { seen.0.z } else { seen.1.z },
        );
        let v = view.transform_point3(corner);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    // A margin so that faces on the box's sides stay inside the depth range.
    let margin = 1e-3 * (hi - lo).max_element().max(1e-6);
    let (lo, hi) = (lo - Vec3::splat(margin), hi + Vec3::splat(margin));
    // View space looks down −z: depth = −z. Near and far swapped for reversed depth.
    let proj = glam::camera::rh::proj::directx::orthographic(lo.x, hi.x, lo.y, hi.y, -lo.z, -hi.z);
    proj * view
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_desk_is_seen_from_above_with_its_top_nearest() {
        let sphere = (Vec3::new(-0.1, 0.0, -0.1), Vec3::new(0.1, 0.2, 0.1));
        let desk = (Vec3::new(-1.0, -0.05, -0.5), Vec3::new(1.0, 0.0, 0.5));
        let m = impostor_clip_from_world(sphere, desk);
        let top = m.project_point3(Vec3::new(0.3, 0.0, 0.2));
        let bottom = m.project_point3(Vec3::new(0.3, -0.05, 0.2));
        assert!(top.z > bottom.z, "reversed depth: the top ({}) is nearer than the bottom ({})", top.z, bottom.z);
        for p in [desk.0, desk.1, Vec3::new(-1.0, 0.0, 0.5)] {
            let c = m.project_point3(p);
            assert!(c.x.abs() <= 1.0 && c.y.abs() <= 1.0 && (0.0..=1.0).contains(&c.z), "{p} → {c}");
        }
        // Seen straight down: x and z of the desk map to the image, y to depth only.
        let a = m.project_point3(Vec3::new(0.3, 0.0, 0.2));
        let b = m.project_point3(Vec3::new(0.3, -0.05, 0.2));
        assert!((a.truncate() - b.truncate()).length() < 1e-5);
    }

    #[test]
    fn a_box_beside_is_seen_along_the_line_between_centres() {
        let sphere = (Vec3::splat(-0.1), Vec3::splat(0.1));
        let cube = (Vec3::new(0.9, -0.1, -0.1), Vec3::new(1.1, 0.1, 0.1));
        let m = impostor_clip_from_world(sphere, cube);
        let near = m.project_point3(Vec3::new(0.9, 0.0, 0.0));
        let far = m.project_point3(Vec3::new(1.1, 0.0, 0.0));
        assert!(near.z > far.z);
        assert!(
            near.truncate().length() < 1e-5 && far.truncate().length() < 1e-5,
            "the centre line is the image centre"
        );
    }
}

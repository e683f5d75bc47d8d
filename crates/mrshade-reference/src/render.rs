//! The image loop: camera rays with box-filtered sub-pixel positions (as the benchmark's
//! answers), rows in parallel on every core, the caustics of punctual lights traced from the
//! lights ([`crate::caustics`]) and added to the same pixel sums, and the differential
//! composite.

use crate::camera::Pinhole;
use crate::caustics::{self, CausticSettings};
use crate::environment::EnvironmentLight;
use crate::geometry::Geometry;
use crate::integrator::Tracer;
use crate::sampler::PathSampler;
use glam::Vec3;
use mrshade_core::settings::CompositeSettings;
use mrshade_core::{Differential, HdrImage};
use mrshade_scene::Session;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// A finished reference render.
#[derive(Clone, Debug)]
pub struct ReferenceImage {
    /// The composite: linear camera values, photo plus the α-scaled (or additive) difference
    /// on real pixels, `exposure·L_rv` on virtual ones, mixed by virtual coverage.
    pub composite: HdrImage,
    /// Mean scene radiance with the virtual content, over all samples.
    pub l_rv: HdrImage,
    /// Mean scene radiance without it.
    pub l_r: HdrImage,
    /// Fraction of each pixel's camera rays whose first hit is virtual.
    pub coverage: Vec<f32>,
    /// Mean composite α of each pixel's real part (1 where additive).
    pub alpha: HdrImage,
}

/// Per-pixel sums over its samples.
#[derive(Clone, Copy, Default)]
struct PixelSums {
    all: Differential<Vec3>,
    real: Differential<Vec3>,
    real_count: u32,
    virtual_rv: Vec3,
    virtual_count: u32,
}

/// Renders `session` in its rest pose (skinned and morphing instances deformed) with its
/// `[reference]` settings. `progress(rows_done, rows)` is called from worker threads as rows
/// finish.
pub fn render(session: &Session, progress: &(dyn Fn(u32, u32) + Sync)) -> ReferenceImage {
    render_with(session, None, &CausticSettings::default(), progress)
}

/// Renders `session` with its scene in `pose` (a frame of its animations: instances, lights
/// and the camera moved, skins and morph targets deformed). The BVH is built for the pose.
pub fn render_pose(
    session: &Session,
    pose: &mrshade_scene::ScenePose,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> ReferenceImage {
    render_with(session, Some(pose), &CausticSettings::default(), progress)
}

/// Renders `session` in `pose` (`None`: the rest pose, as [`render`]) with the caustics pass
/// as `caustics` says. `progress` counts camera rows; the caustics follow the last row.
pub fn render_with(
    session: &Session,
    pose: Option<&mrshade_scene::ScenePose>,
    caustics: &CausticSettings,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> ReferenceImage {
    match pose {
        Some(pose) => render_scene(session, &session.scene.posed(pose), caustics, progress),
        None if session.scene.has_deformations() => {
            render_scene(session, &session.scene.posed(&session.scene.rest_pose()), caustics, progress)
        }
        None => render_scene(session, &session.scene, caustics, progress),
    }
}

fn render_scene(
    session: &Session,
    scene: &mrshade_scene::Scene,
    caustic_settings: &CausticSettings,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> ReferenceImage {
    let settings = session.settings.reference;
    let geometry = Geometry::new(scene);
    let environment = session.environment.as_ref().map(EnvironmentLight::new);
    let tracer = Tracer { scene, geometry: &geometry, environment: environment.as_ref(), settings };
    let (width, height) = (session.output.width, session.output.height);
    let camera = Pinhole::new(&scene.cameras[session.camera], width, height);
    let rows_done = AtomicU32::new(0);
    let mut sums: Vec<PixelSums> = (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row: Vec<PixelSums> = (0..width)
                .map(|x| {
                    let pixel = y * width + x;
                    let mut sums = PixelSums::default();
                    for i in 0..settings.spp {
                        let sampler = PathSampler::new(pixel, i, settings.seed);
                        let [jx, jy] = sampler.pixel();
                        let dir = camera.ray(x as f32 + jx, y as f32 + jy);
                        let result = tracer.trace_camera(camera.origin, dir, &sampler);
                        let l = result.radiance;
                        sums.all += l;
                        if result.sees_virtual {
                            sums.virtual_rv += l.rv;
                            sums.virtual_count += 1;
                        } else {
                            sums.real += l;
                            sums.real_count += 1;
                        }
                    }
                    sums
                })
                .collect();
            progress(rows_done.fetch_add(1, Ordering::Relaxed) + 1, height);
            row
        })
        .collect();
    let photons =
        caustic_settings.photons_per_light.unwrap_or_else(|| caustics::default_photons(width, height, settings.spp));
    if let Some(image) = caustics::render(&tracer, &camera, width, height, photons) {
        // The caustics are pixel means; the sums are over `spp` camera samples. Each part goes
        // where the composite reads it (real or virtual surface), as a camera sample's would.
        let n = settings.spp as f32;
        let times = |d: Differential<Vec3>| Differential { rv: d.rv * n, r: d.r * n };
        for (s, c) in sums.iter_mut().zip(image) {
            s.all += times(c.all);
            s.real += times(c.real);
            s.virtual_rv += c.virtual_rv * n;
        }
    }
    finish(session, &session.settings.composite, &sums)
}

/// The composite of the per-pixel sums (TVCG Eq. 1–2, as the real-time composite pass), with
/// α computed from each pixel's converged `L_r`, not per sample: a noisy per-sample `L_r` in
/// the denominator would bias it.
fn finish(session: &Session, composite: &CompositeSettings, sums: &[PixelSums]) -> ReferenceImage {
    let (width, height) = (session.output.width, session.output.height);
    let n = session.settings.reference.spp as f32;
    let exposure = session.exposure;
    let mut out = ReferenceImage {
        composite: HdrImage::filled(width, height, [0.0; 3]),
        l_rv: HdrImage::filled(width, height, [0.0; 3]),
        l_r: HdrImage::filled(width, height, [0.0; 3]),
        coverage: vec![0.0; sums.len()],
        alpha: HdrImage::filled(width, height, [1.0; 3]),
    };
    for (i, s) in sums.iter().enumerate() {
        let photo = Vec3::from(session.background.pixels[i]);
        out.l_rv.pixels[i] = (s.all.rv / n).to_array();
        out.l_r.pixels[i] = (s.all.r / n).to_array();
        let coverage = s.virtual_count as f32 / n;
        out.coverage[i] = coverage;
        let mut real_part = photo;
        if s.real_count > 0 {
            let rv = s.real.rv / s.real_count as f32;
            let r = s.real.r / s.real_count as f32;
            let alpha = Vec3::from_array(std::array::from_fn(|c| composite.alpha(photo[c], exposure * r[c])));
            real_part = photo + alpha * exposure * (rv - r);
            out.alpha.pixels[i] = alpha.to_array();
        }
        let value = if s.virtual_count > 0 {
            real_part * (1.0 - coverage) + exposure * s.virtual_rv / s.virtual_count as f32 * coverage
        } else {
            real_part
        };
        out.composite.pixels[i] = value.max(Vec3::ZERO).to_array();
    }
    out
}

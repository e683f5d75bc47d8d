//! Caustics of punctual lights by light tracing.
//!
//! A point, spot or directional light seen through a mirror or smooth glass is a delta
//! function at a point: a camera path that reaches a diffuse surface cannot find it (a shadow
//! ray toward the light stops at the glass, and a BSDF-sampled direction hits the light's
//! image with probability zero). So those paths are traced from the light: photons leave each
//! punctual light toward the objects with a delta lobe (`emission`), follow mirror
//! reflections and Fresnel-chosen refractions (absorbed inside volumes by Beer–Lambert, as
//! camera paths are), and at every vertex where they meet a smooth lobe after at least one
//! delta event they are connected to the pinhole camera and splatted into the pixel that
//! sees the vertex.
//!
//! The partition (see also [`crate::integrator`]): camera paths carry every path except the
//! `L S+ D …` paths from punctual lights (their shadow rays stop at glass, and they cannot
//! hit a point light); this pass carries exactly `L S+ D E`, the caustics seen directly by
//! the camera, where each `S` is a delta lobe (mirror, smooth glass reflection or refraction)
//! and `D` a smooth lobe (diffuse or glossy; the connection evaluates only those). Left out of
//! both: `L S+ D D+ E` (caustic light bounced diffusely again), `L S+ D S+ E` (a caustic seen
//! in a mirror or through glass) and caustics of the probe and of emissive surfaces beyond
//! what camera paths find by BSDF sampling.
//!
//! Differential: a photon of a real light is traced in both worlds, shared while it meets
//! only real surfaces and split where it first meets a virtual one (the `rv` half continues
//! from the virtual surface, the `r` half through it, on the same numbers), exactly as camera
//! paths; a virtual light's photons exist only in `L_rv`. So a virtual mirror adds a caustic
//! to `L_rv` alone, and a virtual object that blocks a real caustic removes it from `L_rv`
//! alone.
//!
//! Determinism: photons are numbered per light, each on fixed sample numbers; batches of them
//! run in parallel and return their splats, which are summed in batch order.

mod emission;

use crate::camera::Pinhole;
use crate::integrator::{Lanes, Tracer, leaves_correctly};
use crate::sampler::{PathSampler, Slot};
use crate::surface::Surface;
use emission::{Emitter, Targets};
use glam::{Vec2, Vec3};
use mrshade_core::Differential;
use mrshade_core::flags::Realness;
use rayon::prelude::*;

/// How many photons the caustics pass traces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CausticSettings {
    /// Photons per punctual light (0: no caustics). `None`: [`default_photons`].
    pub photons_per_light: Option<u64>,
}

/// The default photon count per light: one for every four camera samples of the image
/// (`width·height·spp / 4`), at least one batch. Photons are aimed at the delta objects, so
/// most of them make caustics; where those cover a tenth of the image, its pixels get about
/// 2.5 photons per camera sample. A photon that crosses glass costs about two camera paths
/// (it bounces inside), so a light adds a quarter to a half of the camera pass: measured
/// about +35% on `desk-glass` and +25% on `desk-mirror` with one spot (160×120, 32 spp; the
/// ignored test `cost_of_the_caustics_pass_on_benchmark_scenes`). Scenes without both
/// punctual lights and delta surfaces they can reach pay nothing.
pub fn default_photons(width: u32, height: u32, spp: u32) -> u64 {
    (width as u64 * height as u64 * spp as u64 / 4).max(BATCH)
}

/// Photons per parallel task.
const BATCH: u64 = 1 << 12;
/// Tasks whose splats are gathered before they are summed (bounds the splats held at once).
const ROUND: usize = 256;

/// What the caustics add to one pixel, in the units of the pixel's mean radiance.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CausticPixel {
    /// To `L_rv` and `L_r`.
    pub all: Differential<Vec3>,
    /// The part on real surfaces the camera sees in the world with the virtual objects (the
    /// composite's real part).
    pub real: Differential<Vec3>,
    /// The part on virtual surfaces (the composite's virtual part).
    pub virtual_rv: Vec3,
}

/// One connection to the camera.
#[derive(Clone, Copy, Debug)]
struct Splat {
    pixel: u32,
    value: Differential<Vec3>,
    /// The vertex is virtual.
    on_virtual: bool,
    /// The camera sees the vertex in the world with the virtual objects.
    seen_rv: bool,
}

/// A photon between bounces.
#[derive(Clone, Copy, Debug)]
struct Photon {
    origin: Vec3,
    dir: Vec3,
    /// Power carried (over the number of photons).
    power: Vec3,
    /// Product of the delta events' weights, for Russian roulette.
    throughput: Vec3,
    /// Index of the vertex it is about to hit (0: the first).
    bounce: u32,
    absorption: Vec3,
    lanes: Lanes,
}

/// Traces the caustics of `tracer`'s scene as `camera` sees them, or returns `None` at once
/// where there are none to trace (no punctual light, no delta material, no photons).
pub(crate) fn render(
    tracer: &Tracer,
    camera: &Pinhole,
    width: u32,
    height: u32,
    photons: u64,
) -> Option<Vec<CausticPixel>> {
    if photons == 0 || tracer.scene.lights.is_empty() {
        return None;
    }
    let targets = Targets::new(tracer.scene)?;
    let emitters: Vec<(u32, Emitter)> = (tracer.scene.lights.iter().enumerate())
        .filter_map(|(i, l)| Emitter::new(l, &targets).map(|e| (i as u32, e)))
        .collect();
    if emitters.is_empty() {
        return None;
    }
    let tasks: Vec<(usize, u64)> =
        (0..emitters.len()).flat_map(|e| (0..photons.div_ceil(BATCH)).map(move |b| (e, b * BATCH))).collect();
    let mut image = vec![CausticPixel::default(); width as usize * height as usize];
    let scale = 1.0 / photons as f32;
    for round in tasks.chunks(ROUND) {
        let splats: Vec<Vec<Splat>> = round
            .par_iter()
            .map(|&(e, first)| {
                let (light, emitter) = &emitters[e];
                let mut out = Vec::new();
                for i in first..(first + BATCH).min(photons) {
                    let sampler = PathSampler::photon(*light, i, tracer.settings.seed);
                    let pick = sampler.get(0, Slot::LightU);
                    let [u, v] = sampler.pixel();
                    let Some(p) = emitter.emit(pick, Vec2::new(u, v)) else { continue };
                    let realness = tracer.scene.lights[*light as usize].realness;
                    let photon = Photon {
                        origin: p.origin,
                        dir: p.dir,
                        power: p.power * scale,
                        throughput: Vec3::ONE,
                        bounce: 0,
                        absorption: Vec3::ZERO,
                        lanes: if realness == Realness::Virtual { Lanes::Rv } else { Lanes::Both },
                    };
                    PhotonTracer { tracer, camera }.trace(photon, &sampler, &mut out);
                }
                out
            })
            .collect();
        for s in splats.iter().flatten() {
            let px = &mut image[s.pixel as usize];
            px.all += s.value;
            if s.on_virtual {
                px.virtual_rv += s.value.rv;
            } else {
                px.real.rv += s.value.rv;
                if s.seen_rv {
                    px.real.r += s.value.r;
                }
            }
        }
    }
    Some(image)
}

struct PhotonTracer<'a> {
    tracer: &'a Tracer<'a>,
    camera: &'a Pinhole,
}

impl PhotonTracer<'_> {
    /// Follows `p` through delta events, splatting at each smooth vertex after the first.
    fn trace(&self, mut p: Photon, sampler: &PathSampler, out: &mut Vec<Splat>) {
        let t = self.tracer;
        loop {
            let Some(hit) = t.geometry.intersect(t.scene, p.origin, p.dir, f32::INFINITY, p.lanes.world()) else {
                return;
            };
            let realness = t.geometry.triangles[hit.triangle].realness;
            if p.lanes == Lanes::Both && realness == Realness::Virtual {
                self.trace(Photon { lanes: Lanes::Rv, ..p }, sampler, out);
                self.trace(Photon { lanes: Lanes::R, ..p }, sampler, out);
                return;
            }
            p.power *= (-p.absorption * hit.t).exp();
            let surface = Surface::new(t.scene, t.geometry, &hit, p.origin, p.dir);
            // The first vertex's smooth lobes are direct light: the camera paths' part.
            if p.bounce > 0 {
                self.connect(&p, &surface, out);
            }
            // The vertex after this one would be scattering vertex `bounce + 2`.
            if p.bounce + 1 >= t.settings.max_bounces {
                return;
            }
            let wo = surface.frame.to_local(-p.dir);
            let xi = [Slot::BsdfLobe, Slot::BsdfU, Slot::BsdfV].map(|s| sampler.get(p.bounce, s));
            // The light tracer continues through delta events only; a smooth lobe's share of
            // the light goes on as `L S+ D D…`, left out (module docs).
            let Some(s) = surface.bsdf.sample(wo, xi).filter(|s| s.delta) else { return };
            let Some(dir) = leaves_correctly(&surface, &s) else { return };
            // Delta events are symmetric here: mirror reflection, and refraction without the
            // 1/η² radiance scaling the camera paths also leave out (the two agree wherever
            // camera and lights are in air), so the camera's sampling weight is the photon's.
            p.power *= s.weight;
            p.throughput *= s.weight;
            if s.crossed && !surface.bsdf.thin {
                p.absorption = if surface.bsdf.front { surface.absorption } else { Vec3::ZERO };
            }
            if p.bounce + 1 >= t.settings.roulette_from {
                let survive = p.throughput.max_element().clamp(0.05, 0.95);
                if sampler.get(p.bounce, Slot::Roulette) >= survive {
                    return;
                }
                p.power /= survive;
                p.throughput /= survive;
            }
            p.origin = surface.spawn(dir);
            p.dir = dir;
            p.bounce += 1;
        }
    }

    /// Splats the light `p` brings to `surface`, scattered by its smooth lobes toward the
    /// camera, into the pixel that sees it.
    fn connect(&self, p: &Photon, surface: &Surface, out: &mut Vec<Splat>) {
        if !surface.bsdf.has_smooth_lobes() {
            return;
        }
        let to_camera = self.camera.origin - surface.position;
        let distance = to_camera.length();
        let wc = to_camera / distance;
        let cos_camera = wc.dot(surface.geometric);
        let cos_light = -p.dir.dot(surface.geometric);
        if cos_camera <= 0.0 || cos_light <= 0.0 {
            return;
        }
        let Some(projection) = self.camera.project(surface.position) else { return };
        let fr = &surface.frame;
        // f(camera, light)·cos θ_light (shading normal), as the camera path's light sample
        // evaluates it at this vertex.
        let f = surface.bsdf.eval(fr.to_local(wc), fr.to_local(-p.dir));
        if f == Vec3::ZERO {
            return;
        }
        // Photon density is per unit of true area (geometric cosine at the light's side); the
        // camera's solid angle per area is cos θ_camera / d². The ratio of the cosines is the
        // adjoint correction for shading normals (Veach 1997, §5.3).
        let value = p.power * f * (cos_camera / cos_light * projection.importance / (distance * distance));
        if !value.is_finite() {
            return;
        }
        let open = self.tracer.open(surface, wc, distance);
        let rv = p.lanes != Lanes::R && open.rv;
        let r = p.lanes != Lanes::Rv && open.r;
        if !rv && !r {
            return;
        }
        let pick = |on: bool| if on { value } else { Vec3::ZERO };
        out.push(Splat {
            pixel: projection.pixel,
            value: Differential { rv: pick(rv), r: pick(r) },
            on_virtual: surface.realness == Realness::Virtual,
            seen_rv: open.rv,
        });
    }
}

//! Differential path tracing: one path, scored twice.
//!
//! A camera path is traced through the world with the virtual objects. While it meets only
//! real surfaces it is also a path of the real-only world, so it is shared: every light
//! sample it takes is scored for `L_rv` (blocked by real or virtual objects; virtual lamps
//! count) and for `L_r` (blocked by real objects only; real light only), and its next
//! direction is the same for both. Where it first meets a virtual object it splits: the `rv`
//! lane continues from the virtual surface, the `r` lane continues through it, as if it were
//! not there, with the same random numbers. This is differential path tracing in the sense of
//! Franke's comparison (`franke-delta-radiance.md`) and Blender's shadow catcher: both halves
//! come from the same paths, so their difference is free of the noise they share, and with no
//! virtual content they are the same number for every path.
//!
//! Light sampling: every punctual light at every smooth bounce, and the probe by importance
//! sampling with multiple importance sampling against the BSDF (power heuristic, Veach 1997).
//!
//! The partition with [`crate::caustics`]: a punctual light is a point (or a direction), so a
//! camera path reaches it only by a shadow ray from a smooth (non-mirror) lobe, and shadow
//! rays stop at every surface, glass included. Camera paths therefore carry every path
//! `L X … E` whose vertex next to a punctual light `L` scatters it through a smooth lobe, and
//! none of the paths `L S+ D … E` whose first vertices are mirror or smooth-glass events; the
//! light tracer carries `L S+ D E` of those (the caustics seen directly), so no path is
//! counted twice. `L S+ D` followed by more bounces (`L S+ D D+ E`, `L S+ D S+ E`: a caustic
//! lighting another diffuse surface, or seen in a mirror or through glass) is in neither and
//! is missing. Shadow rays must never pass through glass as if it were transparent: that would
//! count caustic light twice (and with the wrong geometry).

use crate::bsdf::BsdfSample;
use crate::environment::EnvironmentLight;
use crate::geometry::{Geometry, World};
use crate::lights::incident;
use crate::sampler::{PathSampler, Slot};
use crate::surface::Surface;
use glam::{Vec2, Vec3};
use mrshade_core::Differential;
use mrshade_core::flags::Realness;
use mrshade_core::settings::ReferenceSettings;
use mrshade_scene::Scene;

/// Which halves a path feeds (camera paths and caustic photons alike).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lanes {
    /// Shared: it has met no virtual object yet.
    Both,
    /// The `L_rv` half after a split.
    Rv,
    /// The `L_r` half after a split.
    R,
}

impl Lanes {
    pub(crate) fn world(self) -> World {
        if self == Lanes::R { World::RealOnly } else { World::RealAndVirtual }
    }
}

/// A path's state between bounces.
#[derive(Clone, Copy, Debug)]
struct PathState {
    origin: Vec3,
    dir: Vec3,
    throughput: Vec3,
    bounce: u32,
    /// Density of the BSDF sample that chose `dir` (0: camera ray or mirror event), for MIS.
    bsdf_pdf: f32,
    /// Absorption coefficient of the volume the ray travels in.
    absorption: Vec3,
    lanes: Lanes,
}

/// What one camera sample returns.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathResult {
    /// Radiance with and without the virtual content.
    pub radiance: Differential<Vec3>,
    /// The camera ray's first hit is a virtual object.
    pub sees_virtual: bool,
}

/// Everything a path reads.
pub struct Tracer<'a> {
    /// The loaded scene (materials, textures, lights).
    pub scene: &'a Scene,
    /// Its triangles and BVH.
    pub geometry: &'a Geometry,
    /// The real probe, if any.
    pub environment: Option<&'a EnvironmentLight>,
    /// Depth and roulette.
    pub settings: ReferenceSettings,
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

impl Tracer<'_> {
    /// Traces the camera ray `origin + t·dir` with the sample numbers of `sampler`.
    pub fn trace_camera(&self, origin: Vec3, dir: Vec3, sampler: &PathSampler) -> PathResult {
        let mut result = PathResult::default();
        let state = PathState {
            origin,
            dir,
            throughput: Vec3::ONE,
            bounce: 0,
            bsdf_pdf: 0.0,
            absorption: Vec3::ZERO,
            lanes: Lanes::Both,
        };
        self.trace(state, sampler, &mut result);
        result
    }

    fn trace(&self, mut state: PathState, sampler: &PathSampler, out: &mut PathResult) {
        loop {
            let hit = self.geometry.intersect(self.scene, state.origin, state.dir, f32::INFINITY, state.lanes.world());
            let Some(hit) = hit else {
                self.add_environment(&state, out);
                return;
            };
            let realness = self.geometry.triangles[hit.triangle].realness;
            if state.lanes == Lanes::Both && realness == Realness::Virtual {
                out.sees_virtual |= state.bounce == 0;
                self.trace(PathState { lanes: Lanes::Rv, ..state }, sampler, out);
                self.trace(PathState { lanes: Lanes::R, ..state }, sampler, out);
                return;
            }
            // Beer–Lambert absorption along the segment inside a volume.
            state.throughput *= (-state.absorption * hit.t).exp();
            let surface = Surface::new(self.scene, self.geometry, &hit, state.origin, state.dir);
            add(out, state.lanes, Differential { rv: true, r: true }, realness, state.throughput * surface.emission);
            if state.bounce >= self.settings.max_bounces {
                return;
            }
            let wo = surface.frame.to_local(-state.dir);
            if surface.bsdf.has_smooth_lobes() {
                self.sample_lights(&state, &surface, wo, sampler, out);
            }
            let xi = [Slot::BsdfLobe, Slot::BsdfU, Slot::BsdfV].map(|s| sampler.get(state.bounce, s));
            let Some(s) = surface.bsdf.sample(wo, xi) else { return };
            let Some(dir) = leaves_correctly(&surface, &s) else { return };
            state.throughput *= s.weight;
            if s.crossed && !surface.bsdf.thin {
                state.absorption = if surface.bsdf.front { surface.absorption } else { Vec3::ZERO };
            }
            // Russian roulette (unbiased: survivors are reweighted).
            if state.bounce + 1 >= self.settings.roulette_from {
                let survive = state.throughput.max_element().clamp(0.05, 0.95);
                if sampler.get(state.bounce, Slot::Roulette) >= survive {
                    return;
                }
                state.throughput /= survive;
            }
            state.origin = surface.spawn(dir);
            state.dir = dir;
            state.bsdf_pdf = if s.delta { 0.0 } else { s.pdf };
            state.bounce += 1;
        }
    }

    /// The probe seen by a ray that left the scene, weighted against light sampling.
    fn add_environment(&self, state: &PathState, out: &mut PathResult) {
        let Some(env) = self.environment else { return };
        let radiance = env.radiance(state.dir);
        let weight = if state.bsdf_pdf > 0.0 { power_heuristic(state.bsdf_pdf, env.pdf(state.dir)) } else { 1.0 };
        add(out, state.lanes, Differential { rv: true, r: true }, Realness::Real, state.throughput * radiance * weight);
    }

    /// Next-event estimation: every punctual light, and one probe direction (MIS).
    fn sample_lights(
        &self,
        state: &PathState,
        surface: &Surface,
        wo: Vec3,
        sampler: &PathSampler,
        out: &mut PathResult,
    ) {
        for light in &self.scene.lights {
            if state.lanes == Lanes::R && light.realness == Realness::Virtual {
                continue;
            }
            let Some(inc) = incident(light, surface.position) else { continue };
            let f = self.eval(surface, wo, inc.dir);
            if f == Vec3::ZERO {
                continue;
            }
            let visible = self.visibility(state.lanes, surface, inc.dir, inc.distance);
            add(out, state.lanes, visible, light.realness, state.throughput * f * inc.irradiance);
        }
        let Some(env) = self.environment else { return };
        let xi = Vec2::new(sampler.get(state.bounce, Slot::LightU), sampler.get(state.bounce, Slot::LightV));
        let Some(s) = env.sample(xi) else { return };
        let f = self.eval(surface, wo, s.dir);
        if f == Vec3::ZERO {
            return;
        }
        let weight = power_heuristic(s.pdf, surface.bsdf.pdf(wo, surface.frame.to_local(s.dir)));
        let visible = self.visibility(state.lanes, surface, s.dir, f32::INFINITY);
        add(out, state.lanes, visible, Realness::Real, state.throughput * f * s.radiance * (weight / s.pdf));
    }

    /// `f·cos` toward world direction `wi`, zero below the geometric surface (no light leaks
    /// through interpolated normals).
    fn eval(&self, surface: &Surface, wo: Vec3, wi: Vec3) -> Vec3 {
        if wi.dot(surface.geometric) <= 0.0 {
            return Vec3::ZERO;
        }
        surface.bsdf.eval(wo, surface.frame.to_local(wi))
    }

    /// Whether the segment toward a light is open in each lane's world.
    fn visibility(&self, lanes: Lanes, surface: &Surface, dir: Vec3, distance: f32) -> Differential<bool> {
        let v = self.open(surface, dir, distance);
        match lanes {
            Lanes::Both => v,
            Lanes::Rv => Differential { rv: v.rv, r: false },
            Lanes::R => Differential { rv: false, r: v.r },
        }
    }

    /// Whether the segment from `surface` along `dir` over `distance` (infinite: a ray) is free
    /// of real objects (`r`) and of any (`rv`).
    pub(crate) fn open(&self, surface: &Surface, dir: Vec3, distance: f32) -> Differential<bool> {
        let origin = surface.spawn(dir);
        let t_max = if distance.is_finite() { (distance - 1e-4 * (1.0 + distance)).max(0.0) } else { f32::INFINITY };
        self.geometry.visibility(self.scene, origin, dir, t_max)
    }
}

/// The world direction of a BSDF sample, or `None` where it would leave on the wrong side of
/// the true surface (a reflection below it, a refraction above it).
pub(crate) fn leaves_correctly(surface: &Surface, s: &BsdfSample) -> Option<Vec3> {
    let dir = surface.frame.to_world(s.wi).normalize();
    let above = dir.dot(surface.geometric) > 0.0;
    (above != s.crossed).then_some(dir)
}

/// Adds `value` to the halves the path feeds where the light is visible; light from a virtual
/// source exists only in `L_rv`.
fn add(out: &mut PathResult, lanes: Lanes, visible: Differential<bool>, source: Realness, value: Vec3) {
    if value == Vec3::ZERO {
        return;
    }
    if lanes != Lanes::R && visible.rv {
        out.radiance.rv += value;
    }
    if lanes != Lanes::Rv && visible.r && source == Realness::Real {
        out.radiance.r += value;
    }
}

//! Where caustic photons start. Only photons whose first hit is a mirror or smooth glass can
//! become caustics, so a light emits only toward the objects that have such a lobe: toward the
//! union of their bounding spheres (cones seen from a point or spot light, disks across a
//! directional light's beam). A cone or disk is picked in proportion to its measure and
//! sampled uniformly, so the density at a direction (or point) is the number of cones (disks)
//! holding it over their total measure: known exactly, and non-zero toward every delta
//! object. The photons are as unbiased as uniform emission, and far fewer of them are wasted
//! on the rest of the scene.

use crate::bsdf::MIRROR_ALPHA;
use crate::lights::spot_factor;
use glam::{Vec2, Vec3};
use mrshade_core::color::srgb_to_linear;
use mrshade_scene::{Light, LightKind, Material, Scene, TextureRef};
use std::f32::consts::PI;

/// More target spheres than this are merged into one: the mixture's density costs one test
/// per sphere per photon.
const MAX_TARGETS: usize = 32;

/// A bounding sphere.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
}

/// An axis-aligned box, grown point by point.
#[derive(Clone, Copy, Debug)]
struct Box3 {
    min: Vec3,
    max: Vec3,
}

impl Box3 {
    const EMPTY: Box3 = Box3 { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn union(self, other: Box3) -> Box3 {
        Box3 { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// The sphere around the box, padded a little past the intersection tests' tolerances.
    fn sphere(&self) -> Sphere {
        let radius = 0.5 * (self.max - self.min).length();
        Sphere { center: 0.5 * (self.min + self.max), radius: radius + 1e-3 * (1.0 + radius) }
    }
}

/// The objects that can start a caustic, and the whole scene.
#[derive(Clone, Debug)]
pub struct Targets {
    /// Bounding spheres of the instances with a delta lobe (real and virtual).
    pub spheres: Vec<Sphere>,
    /// Bounding sphere of everything (directional photons start outside it).
    pub scene: Sphere,
}

impl Targets {
    /// The targets of `scene`, or `None` when no material can reflect or refract through a
    /// delta lobe (then there are no caustics to trace).
    pub fn new(scene: &Scene) -> Option<Targets> {
        let delta: Vec<bool> = scene.materials.iter().map(|m| has_delta_lobe(scene, m)).collect();
        if !delta.contains(&true) {
            return None;
        }
        let (mut boxes, mut all) = (Vec::new(), Box3::EMPTY);
        for inst in &scene.instances {
            let prim = &scene.primitives[inst.primitive];
            let mut b = Box3::EMPTY;
            for &i in &prim.indices {
                b.grow(inst.world_from_object.transform_point3(prim.positions[i as usize]));
            }
            if b.is_empty() {
                continue;
            }
            all = all.union(b);
            if delta[prim.material] {
                boxes.push(b);
            }
        }
        if boxes.is_empty() {
            return None;
        }
        if boxes.len() > MAX_TARGETS {
            boxes = vec![boxes.iter().fold(Box3::EMPTY, |a, &b| a.union(b))];
        }
        Some(Targets { spheres: boxes.iter().map(Box3::sphere).collect(), scene: all.sphere() })
    }
}

/// Whether some point of `m` can scatter through a delta lobe as [`crate::bsdf`] classifies
/// them: smooth glass (transmission is always smooth) or mirror reflection (GGX α below
/// [`MIRROR_ALPHA`]). A metallic-roughness texture only scales roughness and metalness down,
/// so its smallest texel bounds them.
pub fn has_delta_lobe(scene: &Scene, m: &Material) -> bool {
    // The texture is read only where the factors alone do not decide (it may be large).
    let floor = || m.metallic_roughness_texture.map_or((1.0, 1.0), |t| texture_min(scene, t));
    if m.transmission > 0.0 && (m.metallic < 1.0 || m.metallic * floor().1 < 1.0) {
        return true;
    }
    let smooth = |roughness: f32| roughness * roughness < MIRROR_ALPHA;
    let reflects = m.metallic > 0.0 || m.specular > 0.0;
    reflects && (smooth(m.roughness) || smooth(m.roughness * floor().0))
}

/// The smallest green and blue texel values of a texture, linear.
fn texture_min(scene: &Scene, t: TextureRef) -> (f32, f32) {
    let tex = &scene.textures[t.texture];
    let (g, b) = tex.rgba8.chunks_exact(4).fold((255u8, 255u8), |(g, b), c| (g.min(c[1]), b.min(c[2])));
    let decode = |v: u8| if tex.srgb { srgb_to_linear(v as f32 / 255.0) } else { v as f32 / 255.0 };
    (decode(g), decode(b))
}

/// A cone of directions; `cos_max = −1` is the whole sphere.
#[derive(Clone, Copy, Debug)]
struct Cone {
    axis: Vec3,
    cos_max: f32,
}

impl Cone {
    const SPHERE: Cone = Cone { axis: Vec3::Z, cos_max: -1.0 };

    fn solid_angle(&self) -> f32 {
        2.0 * PI * (1.0 - self.cos_max)
    }

    fn half_angle(&self) -> f32 {
        self.cos_max.clamp(-1.0, 1.0).acos()
    }

    fn contains(&self, d: Vec3) -> bool {
        d.dot(self.axis) >= self.cos_max
    }

    /// A direction uniform in the cone.
    fn sample(&self, u: Vec2) -> Vec3 {
        let cos = 1.0 - u.x * (1.0 - self.cos_max);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (a, b) = self.axis.any_orthonormal_pair();
        (a * (sin * phi.cos()) + b * (sin * phi.sin()) + self.axis * cos).normalize()
    }
}

/// How a light's photons are spread.
#[derive(Clone, Debug)]
enum Spread {
    /// From `position`, directions uniform over the union of `cones`.
    Directions { position: Vec3, cones: Vec<Cone> },
    /// Along `dir`, positions uniform over the union of `disks` across the beam (each the
    /// cross-section of a target sphere), starting outside `scene`.
    Parallel { dir: Vec3, disks: Vec<Sphere>, scene: Sphere },
}

/// A photon as it leaves its light.
#[derive(Clone, Copy, Debug)]
pub struct Emitted {
    /// Start of the first segment.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Radiant intensity over the direction density (point, spot) or irradiance over the area
    /// density (directional): the photon's power times the number of photons.
    pub power: Vec3,
}

/// One light's photon source.
#[derive(Clone, Debug)]
pub struct Emitter {
    spread: Spread,
    /// Cumulative measures (solid angles or areas) of the cones or disks; the last is the total.
    cdf: Vec<f32>,
    intensity: Vec3,
    /// Axis and inner and outer cone angles of a spot light.
    spot: Option<(Vec3, f32, f32)>,
}

impl Emitter {
    /// The photon source of `light` aimed at `targets`, or `None` where the light cannot
    /// reach any of them (a spot cone that misses them all, a black light).
    pub fn new(light: &Light, targets: &Targets) -> Option<Emitter> {
        if light.intensity.max_element() <= 0.0 {
            return None;
        }
        let (spread, measures): (Spread, Vec<f32>) = match light.kind {
            LightKind::Directional => {
                let disks = targets.spheres.clone();
                let areas = disks.iter().map(|s| PI * s.radius * s.radius).collect();
                (Spread::Parallel { dir: light.direction(), disks, scene: targets.scene }, areas)
            }
            LightKind::Point | LightKind::Spot { .. } => {
                let position = light.position();
                let mut cones = cones_toward(position, &targets.spheres);
                if let LightKind::Spot { outer_cone, .. } = light.kind {
                    // Only cones that overlap the spot's; the spot's own cone if it is smaller.
                    let spot = Cone { axis: light.direction(), cos_max: outer_cone.cos() };
                    let angle = |c: &Cone| c.axis.dot(spot.axis).clamp(-1.0, 1.0).acos();
                    cones.retain(|c| c.cos_max <= -1.0 || angle(c) < c.half_angle() + outer_cone);
                    if cones.is_empty() {
                        return None;
                    }
                    if spot.solid_angle() < cones.iter().map(Cone::solid_angle).sum() {
                        cones = vec![spot];
                    }
                }
                let angles = cones.iter().map(Cone::solid_angle).collect();
                (Spread::Directions { position, cones }, angles)
            }
        };
        let cdf = measures
            .iter()
            .scan(0.0f32, |sum, &m| {
                *sum += m;
                Some(*sum)
            })
            .collect();
        let spot = match light.kind {
            LightKind::Spot { inner_cone, outer_cone } => Some((light.direction(), inner_cone, outer_cone)),
            _ => None,
        };
        Some(Emitter { spread, cdf, intensity: light.intensity, spot })
    }

    /// A photon from three uniform numbers (`pick` chooses the cone or disk), or `None` where
    /// it carries nothing (outside a spot's cone).
    pub fn emit(&self, pick: f32, u: Vec2) -> Option<Emitted> {
        let total = *self.cdf.last()?;
        let k = self.cdf.partition_point(|&c| c <= pick * total).min(self.cdf.len() - 1);
        match &self.spread {
            Spread::Directions { position, cones } => {
                let dir = cones[k].sample(u);
                // The sampled cone holds `dir` by construction (whatever rounding says).
                let cover = 1 + cones.iter().enumerate().filter(|&(j, c)| j != k && c.contains(dir)).count();
                let factor = self.spot.map_or(1.0, |(axis, inner, outer)| spot_factor(dir.dot(axis), inner, outer));
                (factor > 0.0).then(|| Emitted {
                    origin: *position,
                    dir,
                    power: self.intensity * (factor * total / cover as f32),
                })
            }
            Spread::Parallel { dir, disks, scene } => {
                let (e1, e2) = dir.any_orthonormal_pair();
                let (r, phi) = (disks[k].radius * u.x.sqrt(), 2.0 * PI * u.y);
                let q = disks[k].center + e1 * (r * phi.cos()) + e2 * (r * phi.sin());
                let inside = |s: &Sphere| {
                    let w = q - s.center;
                    (w - *dir * w.dot(*dir)).length_squared() <= s.radius * s.radius
                };
                let cover = 1 + disks.iter().enumerate().filter(|&(j, s)| j != k && inside(s)).count();
                // Back along the beam to outside the scene's sphere: nothing lies before it.
                let back = (q - scene.center).dot(*dir) + scene.radius * 1.01 + 1e-3;
                Some(Emitted { origin: q - *dir * back, dir: *dir, power: self.intensity * (total / cover as f32) })
            }
        }
    }
}

/// The cones of directions from `position` toward each sphere; the whole sphere of directions
/// where the light is inside one or the cones add up to more.
fn cones_toward(position: Vec3, spheres: &[Sphere]) -> Vec<Cone> {
    let mut cones = Vec::with_capacity(spheres.len());
    for s in spheres {
        let to = s.center - position;
        let d = to.length();
        if d <= s.radius {
            return vec![Cone::SPHERE];
        }
        let sin = s.radius / d;
        cones.push(Cone { axis: to / d, cos_max: (1.0 - sin * sin).max(0.0).sqrt() });
    }
    if cones.iter().map(Cone::solid_angle).sum::<f32>() >= 4.0 * PI { vec![Cone::SPHERE] } else { cones }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use mrshade_core::flags::Realness;

    fn light(kind: LightKind, world_from_light: Mat4) -> Light {
        Light { name: "l".into(), kind, intensity: Vec3::ONE, world_from_light, realness: Realness::Real }
    }

    /// The mean photon power over many photons: the light's total power toward the targets'
    /// union (point light: intensity × solid angle, for any overlap of the cones).
    fn mean_power(e: &Emitter, n: u32) -> f32 {
        let mut sum = 0.0f64;
        for i in 0..n {
            let [a, b, c] = [0, 1, 2].map(|d| sobol_burley::sample(i, d, 5));
            if let Some(p) = e.emit(a, Vec2::new(b, c)) {
                sum += p.power.x as f64;
            }
        }
        (sum / n as f64) as f32
    }

    #[test]
    fn overlapping_cones_are_counted_once() {
        // Two spheres that overlap as seen from the light: the union's solid angle is what the
        // mean power estimates, checked by counting directions on a fine uniform grid.
        let spheres = vec![
            Sphere { center: Vec3::new(0.0, 0.0, -3.0), radius: 1.0 },
            Sphere { center: Vec3::new(0.8, 0.0, -3.0), radius: 1.0 },
        ];
        let targets = Targets { spheres: spheres.clone(), scene: Sphere { center: Vec3::ZERO, radius: 10.0 } };
        let e = Emitter::new(&light(LightKind::Point, Mat4::IDENTITY), &targets).unwrap();
        let cones = cones_toward(Vec3::ZERO, &spheres);
        let n = 1 << 16;
        let hits = (0..n)
            .filter(|&i| {
                let d = Cone::SPHERE.sample(Vec2::new(sobol_burley::sample(i, 0, 1), sobol_burley::sample(i, 1, 1)));
                cones.iter().any(|c| c.contains(d))
            })
            .count();
        let union = 4.0 * PI * hits as f32 / n as f32;
        let got = mean_power(&e, n);
        assert!((got - union).abs() < 0.01 * union, "{got} vs {union}");
    }

    #[test]
    fn delta_lobes_are_smooth_glass_and_mirrors() {
        let scene = Scene::default();
        let m = |metallic, roughness, specular, transmission| Material {
            metallic,
            roughness,
            specular,
            transmission,
            ..Material::default()
        };
        assert!(has_delta_lobe(&scene, &m(1.0, 0.0, 1.0, 0.0)), "mirror");
        assert!(has_delta_lobe(&scene, &m(0.0, 0.0, 1.0, 0.0)), "smooth plastic");
        assert!(has_delta_lobe(&scene, &m(0.0, 0.6, 1.0, 1.0)), "rough glass is traced smooth");
        assert!(!has_delta_lobe(&scene, &m(1.0, 0.2, 1.0, 0.0)), "rough metal");
        assert!(!has_delta_lobe(&scene, &m(0.0, 0.0, 0.0, 0.0)), "Lambert");
        assert!(!has_delta_lobe(&scene, &m(1.0, 0.5, 1.0, 1.0)), "rough metal with transmission: no glass lobe");
    }

    #[test]
    fn a_spot_aimed_away_from_every_target_emits_nothing() {
        let targets = Targets {
            spheres: vec![Sphere { center: Vec3::new(0.0, -2.0, 0.0), radius: 0.5 }],
            scene: Sphere { center: Vec3::ZERO, radius: 10.0 },
        };
        let up = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
        let spot = LightKind::Spot { inner_cone: 0.2, outer_cone: 0.4 };
        assert!(Emitter::new(&light(spot, up), &targets).is_none());
        let down = Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2);
        assert!(Emitter::new(&light(spot, down), &targets).is_some());
    }

    #[test]
    fn directional_photons_carry_irradiance_times_the_beam_area() {
        let s = Sphere { center: Vec3::new(1.0, 0.0, 0.0), radius: 0.5 };
        let targets = Targets { spheres: vec![s], scene: Sphere { center: Vec3::ZERO, radius: 4.0 } };
        let e = Emitter::new(&light(LightKind::Directional, Mat4::IDENTITY), &targets).unwrap();
        let p = e.emit(0.3, Vec2::new(0.4, 0.9)).unwrap();
        assert!((p.power.x - PI * 0.25).abs() < 1e-5);
        // It starts outside the scene, on the light's side, and heads down −Z.
        assert!(p.origin.z >= 4.0 && p.dir == Vec3::NEG_Z);
    }
}

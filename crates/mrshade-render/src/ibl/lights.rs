//! The probe split into directional lights by median cut (Debevec 2005): regions of equal
//! power, each a light from its power-weighted mean direction carrying the region's
//! irradiance at normal incidence. `dlpv` draws reflective shadow maps from them (Franke
//! §2.12.1: real lights "extracted from a hemispherical image").

use crate::random::Pcg32;
use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::color::luminance;
use mrshade_core::flags::Realness;
use mrshade_core::math::{dir_from_equirect_uv, equirect_texel_solid_angle, probe_from_world};
use mrshade_scene::{Environment, Light, LightKind};

/// Width of the probe level that is cut (coarser is enough for 64 lights).
const CUT_WIDTH: u32 = 128;

/// A region of texels `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy)]
struct Region {
    x0: u32,
    x1: u32,
    y0: u32,
    y1: u32,
}

/// `count` (a power of two) directional lights whose sum approximates `env`'s light, in world
/// space; regions without power give no light.
pub fn probe_lights(env: &Environment, count: u32) -> Vec<Light> {
    probe_lights_with_spread(env, count).into_iter().map(|(light, _)| light).collect()
}

/// `probe_lights` with each light's angular radius (rad): that of a uniform cap whose mean
/// direction cosine is the region's power-weighted one (a sun's few texels: near 0; a
/// broad sky's region: tens of degrees), how sharp a shadow the light casts.
pub fn probe_lights_with_spread(env: &Environment, count: u32) -> Vec<(Light, f32)> {
    ProbeRegions::new(env, count).lights_with_spread()
}

/// The probe's median-cut regions with power (`probe_lights`' split), kept to draw lights
/// from: each region's light at its power-weighted mean direction (`lights_with_spread`), or
/// at a direction drawn within it in proportion to its texels' power (`sampled`).
pub struct ProbeRegions {
    /// The probe at the width it is cut at.
    image: HdrImage,
    world_from_probe: Mat3,
    /// The regions with power: (region, Σ L dω, power-weighted direction sum).
    regions: Vec<(Region, Vec3, Vec3)>,
    intensity: f32,
}

impl ProbeRegions {
    /// `env` cut into `count` regions (a power of two; none for 0).
    pub fn new(env: &Environment, count: u32) -> Self {
        let width = env.image.width.clamp(4, CUT_WIDTH);
        let image = env.image.resized(width, width / 2);
        let mut regions = Vec::new();
        if count > 0 {
            regions.push(Region { x0: 0, x1: image.width, y0: 0, y1: image.height });
        }
        while !regions.is_empty() && (regions.len() as u32) < count {
            regions = regions.iter().flat_map(|r| split(&image, *r)).collect();
        }
        let regions = regions
            .into_iter()
            .filter_map(|r| {
                let (dir, sum) = summed(&image, r);
                (sum.max_element() > 0.0 && dir.length_squared() > 0.0).then_some((r, sum, dir))
            })
            .collect();
        let world_from_probe = probe_from_world(env.rotation_deg).transpose();
        Self { image, world_from_probe, regions, intensity: env.intensity }
    }

    /// One light per region at its power-weighted mean direction, with its angular radius.
    pub fn lights_with_spread(&self) -> Vec<(Light, f32)> {
        self.regions
            .iter()
            .map(|(_, sum, dir)| {
                // A cap of half-angle α has mean cosine (1 + cos α)/2.
                let mean_cosine = dir.length() / luminance((*sum).into()).max(1e-12);
                (self.light(*dir, *sum), (2.0 * mean_cosine - 1.0).clamp(-1.0, 1.0).acos())
            })
            .collect()
    }

    /// One light per region, as `lights_with_spread` in the same order, but from a direction
    /// drawn within the region in proportion to its texels' power (a texel, then a point in
    /// it, by the hash of `sample` and the region): the mean of a shadow test over many
    /// samples is the region's power-weighted visibility, which one direction per region
    /// only approximates (stratified Monte Carlo over the probe).
    pub fn sampled(&self, sample: u32) -> Vec<Light> {
        self.regions
            .iter()
            .enumerate()
            .map(|(i, (r, sum, _))| {
                // Halton points (bases 2, 3, 5) over the samples, each region's shifted by its
                // own random offset (Cranley–Patterson): successive samples fill the region
                // evenly, where independent ones clump.
                let mut random = Pcg32::new(i as u64);
                let u = [2, 3, 5].map(|base| (radical_inverse(sample, base) + random.next_f32()).fract());
                let target = u[0] * luminance((*sum).into());
                let (mut x, mut y) = (r.x0, r.y0);
                let mut acc = 0.0;
                'texels: for ty in r.y0..r.y1 {
                    let dw = equirect_texel_solid_angle(ty, self.image.width, self.image.height);
                    for tx in r.x0..r.x1 {
                        acc += luminance(self.image.get(tx, ty)) * dw;
                        (x, y) = (tx, ty);
                        if acc >= target {
                            break 'texels;
                        }
                    }
                }
                let uv = Vec2::new(
                    (x as f32 + u[1]) / self.image.width as f32,
                    (y as f32 + u[2]) / self.image.height as f32,
                );
                self.light(dir_from_equirect_uv(uv), *sum)
            })
            .collect()
    }

    /// The light from probe direction `dir` carrying `sum` (Σ L dω).
    fn light(&self, dir: Vec3, sum: Vec3) -> Light {
        let shines = -(self.world_from_probe * dir.normalize());
        Light {
            name: "probe light".into(),
            kind: LightKind::Directional,
            intensity: sum * self.intensity,
            world_from_light: Mat4::from_quat(Quat::from_rotation_arc(Vec3::NEG_Z, shines)),
            realness: Realness::Real,
        }
    }
}

/// `i`'s digits in `base` mirrored about the point: the Halton sequence's coordinate.
fn radical_inverse(mut i: u32, base: u32) -> f32 {
    let (mut value, mut scale) = (0.0f32, 1.0 / base as f32);
    while i > 0 {
        value += (i % base) as f32 * scale;
        i /= base;
        scale /= base as f32;
    }
    value
}

fn texel_direction(image: &HdrImage, x: u32, y: u32) -> Vec3 {
    dir_from_equirect_uv(Vec2::new((x as f32 + 0.5) / image.width as f32, (y as f32 + 0.5) / image.height as f32))
}

/// Power-weighted direction sum and `Σ L dω` of a region.
fn summed(image: &HdrImage, r: Region) -> (Vec3, Vec3) {
    let (mut dir, mut sum) = (Vec3::ZERO, Vec3::ZERO);
    for y in r.y0..r.y1 {
        let dw = equirect_texel_solid_angle(y, image.width, image.height);
        for x in r.x0..r.x1 {
            let l = image.get(x, y);
            dir += texel_direction(image, x, y) * luminance(l) * dw;
            sum += Vec3::from(l) * dw;
        }
    }
    (dir, sum)
}

/// Halves `r` across its longer angular side at the power median; a region one texel wide
/// and high is returned twice, the second empty.
fn split(image: &HdrImage, r: Region) -> [Region; 2] {
    let theta = std::f32::consts::PI * (r.y0 + r.y1) as f32 * 0.5 / image.height as f32;
    let angular_width = (r.x1 - r.x0) as f32 * theta.sin() * 2.0;
    let across_x = angular_width >= (r.y1 - r.y0) as f32 && r.x1 - r.x0 > 1 || r.y1 - r.y0 == 1;
    let (lo, hi) = if across_x { (r.x0, r.x1) } else { (r.y0, r.y1) };
    if hi - lo < 2 {
        return [r, Region { x0: r.x0, x1: r.x0, y0: r.y0, y1: r.y0 }];
    }
    // Power of every column (or row) of the region.
    let power: Vec<f32> = (lo..hi)
        .map(|i| {
            let line = if across_x { Region { x0: i, x1: i + 1, ..r } } else { Region { y0: i, y1: i + 1, ..r } };
            let mut p = 0.0;
            for y in line.y0..line.y1 {
                let dw = equirect_texel_solid_angle(y, image.width, image.height);
                p += (line.x0..line.x1).map(|x| luminance(image.get(x, y))).sum::<f32>() * dw;
            }
            p
        })
        .collect();
    let total: f32 = power.iter().sum();
    let mut cut = lo + (hi - lo) / 2;
    if total > 0.0 {
        let mut acc = 0.0;
        for (i, p) in power.iter().enumerate() {
            acc += p;
            if acc >= total * 0.5 {
                cut = (lo + i as u32 + 1).clamp(lo + 1, hi - 1);
                break;
            }
        }
    }
    if across_x {
        [Region { x1: cut, ..r }, Region { x0: cut, ..r }]
    } else {
        [Region { y1: cut, ..r }, Region { y0: cut, ..r }]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lights_carry_the_probes_power_and_point_away_from_its_sun() {
        // A dim uniform sky and a bright texel block straight up (+Y): the total irradiance is
        // kept, and the brightest light shines down.
        let mut image = HdrImage::filled(64, 32, [0.1; 3]);
        for y in 0..2 {
            for x in 0..64 {
                image.pixels[y * 64 + x] = [50.0; 3];
            }
        }
        let env = Environment { image: image.clone(), rotation_deg: 30.0, intensity: 2.0 };
        let lights = probe_lights(&env, 8);
        assert_eq!(lights.len(), 8);
        let total: Vec3 = lights.iter().map(|l| l.intensity).sum();
        let (_, want) = summed(&image, Region { x0: 0, x1: 64, y0: 0, y1: 32 });
        assert!((total - want * 2.0).abs().max_element() < 1e-3 * want.x * 2.0, "{total} vs {want}");
        let brightest = lights.iter().max_by(|a, b| a.intensity.x.total_cmp(&b.intensity.x)).unwrap();
        assert!(brightest.direction().dot(Vec3::NEG_Y) > 0.95, "{}", brightest.direction());
        assert!(probe_lights(&env, 0).is_empty());
        // The sun's lights are narrow, the sky's broad.
        let spreads = probe_lights_with_spread(&env, 8);
        let sun = spreads.iter().max_by(|a, b| a.0.intensity.x.total_cmp(&b.0.intensity.x)).unwrap();
        let sky = spreads.iter().min_by(|a, b| a.0.intensity.x.total_cmp(&b.0.intensity.x)).unwrap();
        assert!(sun.1 < 0.2 && sky.1 > 0.4, "sun {} sky {}", sun.1, sky.1);
    }

    #[test]
    fn drawn_lights_carry_their_regions_power_and_average_to_their_mean_direction() {
        // A sky whose brightness rises toward the zenith, turned by 30°: each region's drawn
        // light carries the region's whole power, and over many samples the mean of the drawn
        // directions (drawn in proportion to power) is the region's power-weighted mean
        // direction, the one its fixed light points along.
        let image = HdrImage {
            pixels: (0..64 * 32).map(|i| [1.0 + 4.0 * (1.0 - (i / 64) as f32 / 32.0); 3]).collect(),
            ..HdrImage::filled(64, 32, [0.0; 3])
        };
        let env = Environment { image, rotation_deg: 30.0, intensity: 1.5 };
        let regions = ProbeRegions::new(&env, 8);
        let fixed = regions.lights_with_spread();
        assert_eq!(fixed.len(), 8);
        let samples = 512;
        let mut mean = vec![Vec3::ZERO; fixed.len()];
        for sample in 0..samples {
            let drawn = regions.sampled(sample);
            assert_eq!(drawn.len(), fixed.len());
            for (k, (light, (f, _))) in drawn.iter().zip(&fixed).enumerate() {
                assert_eq!(light.intensity, f.intensity, "light {k} keeps its region's power");
                mean[k] += light.direction();
            }
        }
        for (k, (f, spread)) in fixed.iter().enumerate() {
            let m = mean[k].normalize();
            let off = m.dot(f.direction()).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(
                off < 1.5,
                "light {k}: the drawn directions' mean is {off:.2}° from the region's (spread {:.1}°)",
                spread.to_degrees()
            );
        }
        // Different samples, different directions; the same sample, the same.
        assert_ne!(regions.sampled(1)[0].direction(), regions.sampled(2)[0].direction());
        assert_eq!(regions.sampled(3)[0].direction(), regions.sampled(3)[0].direction());
    }
}

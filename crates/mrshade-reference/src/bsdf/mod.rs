//! The glTF 2.0 material as a BSDF (glTF 2.0 Appendix B, `KHR_materials_specular`,
//! `_transmission`, `_ior`): a mix of
//! - a metal: GGX reflection with Schlick Fresnel toward the base color (weight `metallic`);
//! - an opaque dielectric: Lambert diffuse and GGX reflection, mixed by Schlick Fresnel with
//!   `F0 = ((ior−1)/(ior+1))²·specularColor·specular`, `F90 = specular` (weight
//!   `(1−metallic)(1−transmission)`); `specular = 0` leaves a pure Lambertian surface;
//! - smooth glass: exact dielectric Fresnel between reflection and refraction, the refracted
//!   light tinted by the base color (weight `(1−metallic)·transmission`).
//!
//! Reflection with roughness below 0.03 (GGX α < 10⁻³) is a perfect mirror. Transmission is
//! always smooth (rough glass is rendered as smooth; the loader's materials say which).
//! Everything is evaluated in a local frame whose +z is the shading normal turned toward the
//! viewer; `front` says whether the viewer is on the surface's outer side (for refraction).

#[cfg(test)]
mod chi_square;

use glam::{Vec2, Vec3};
use mrshade_core::brdf::{ggx_d, sample_ggx_half_vector, smith_ggx_visibility};
use mrshade_core::color::luminance;
use std::f32::consts::PI;

/// GGX α below which reflection is treated as a perfect mirror.
pub const MIRROR_ALPHA: f32 = 1e-3;

/// The material's values at one surface point.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    /// Linear base color (texture applied).
    pub base: Vec3,
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// GGX α = roughness².
    pub alpha: f32,
    /// Dielectric reflectance at normal incidence.
    pub f0: Vec3,
    /// Dielectric reflectance at grazing incidence (`specularFactor`).
    pub f90: f32,
    /// `transmissionFactor` in [0, 1].
    pub transmission: f32,
    /// Index of refraction of the inside.
    pub ior: f32,
    /// Thin-walled: refraction passes straight through (no `KHR_materials_volume`).
    pub thin: bool,
    /// Whether the viewer is on the outer side of the surface.
    pub front: bool,
}

/// A scattered direction drawn from the BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Local-frame unit direction toward where the light comes from.
    pub wi: Vec3,
    /// `f·|cos θi| / pdf`: the factor the path's throughput takes.
    pub weight: Vec3,
    /// Solid-angle density of the non-mirror lobes at `wi` (for MIS); 0 for a mirror event.
    pub pdf: f32,
    /// Mirror reflection or refraction (no light sampling could have found this direction).
    pub delta: bool,
    /// The direction went through the surface.
    pub crossed: bool,
}

fn schlick(f0: Vec3, f90: f32, cos: f32) -> Vec3 {
    f0 + (Vec3::splat(f90) - f0) * (1.0 - cos).clamp(0.0, 1.0).powi(5)
}

/// Exact unpolarised Fresnel reflectance for `cos_i` and `eta = n_incident / n_transmitted`,
/// with the cosine of the refracted direction (0 on total internal reflection).
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, f32) {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

fn cosine_hemisphere(xi: Vec2) -> Vec3 {
    let r = xi.x.sqrt();
    let phi = 2.0 * PI * xi.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - xi.x).max(0.0).sqrt())
}

impl Bsdf {
    fn opaque_dielectric_weight(&self) -> f32 {
        (1.0 - self.metallic) * (1.0 - self.transmission)
    }

    /// Whether reflection is a perfect mirror.
    pub fn is_mirror(&self) -> bool {
        self.alpha < MIRROR_ALPHA
    }

    /// Probabilities of choosing the diffuse, the reflection and the glass lobe at `cos_o`.
    fn lobe_probabilities(&self, cos_o: f32) -> [f32; 3] {
        let kd = self.opaque_dielectric_weight();
        let fd = luminance(schlick(self.f0, self.f90, cos_o).to_array());
        let diffuse = kd * (1.0 - fd) * luminance(self.base.to_array()).max(0.0);
        let reflection = self.metallic + kd * fd;
        let glass = (1.0 - self.metallic) * self.transmission;
        let total = diffuse + reflection + glass;
        if total <= 0.0 { [0.0; 3] } else { [diffuse / total, reflection / total, glass / total] }
    }

    /// Whether any lobe is smooth enough for light sampling (not mirror or glass only).
    pub fn has_smooth_lobes(&self) -> bool {
        let [d, r, _] = self.lobe_probabilities(1.0);
        d > 0.0 || (r > 0.0 && !self.is_mirror())
    }

    /// Fresnel of the reflection lobe (metal and dielectric parts) at `cos = v·h`.
    fn reflection_fresnel(&self, cos: f32) -> Vec3 {
        self.metallic * schlick(self.base, 1.0, cos) + self.opaque_dielectric_weight() * schlick(self.f0, self.f90, cos)
    }

    /// `f(wo, wi)·cos θi` of the smooth (non-mirror) lobes, local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let cos_oh = wo.dot(h).max(0.0);
        let kd = self.opaque_dielectric_weight();
        let mut f = kd * (Vec3::ONE - schlick(self.f0, self.f90, cos_oh)) * self.base / PI;
        if !self.is_mirror() {
            let d = ggx_d(h.z, self.alpha);
            let vis = smith_ggx_visibility(wo.z, wi.z, self.alpha);
            f += d * vis * self.reflection_fresnel(cos_oh);
        }
        f * wi.z
    }

    /// Density with which [`Self::sample`] picks `wi` through a smooth lobe, local frame.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let [pd, pr, _] = self.lobe_probabilities(wo.z);
        let mut pdf = pd * wi.z / PI;
        if !self.is_mirror() && pr > 0.0 {
            let h = (wo + wi).normalize();
            pdf += pr * ggx_d(h.z, self.alpha) * h.z / (4.0 * wo.dot(h).max(1e-8));
        }
        pdf
    }

    /// Draws a scattered direction for `wo` from three uniform numbers.
    pub fn sample(&self, wo: Vec3, xi: [f32; 3]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let [pd, pr, pg] = self.lobe_probabilities(wo.z);
        let pick = xi[0];
        let uv = Vec2::new(xi[1], xi[2]);
        let wi = if pick < pd {
            cosine_hemisphere(uv)
        } else if pick < pd + pr {
            if self.is_mirror() {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let weight = self.reflection_fresnel(wo.z) / pr;
                return Some(BsdfSample { wi, weight, pdf: 0.0, delta: true, crossed: false });
            }
            let h = sample_ggx_half_vector(uv, self.alpha);
            2.0 * wo.dot(h) * h - wo
        } else if pg > 0.0 {
            return Some(self.sample_glass(wo, (pick - pd - pr) / pg, pg));
        } else {
            return None;
        };
        let pdf = self.pdf(wo, wi);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, delta: false, crossed: false })
    }

    /// Smooth glass: reflect with probability F, refract otherwise; `u` picks, `pg` is the
    /// probability of having chosen this lobe.
    fn sample_glass(&self, wo: Vec3, u: f32, pg: f32) -> BsdfSample {
        let eta = if self.front { 1.0 / self.ior } else { self.ior };
        let (f, cos_t) = fresnel_dielectric(wo.z, eta);
        // The lobe's weight (1 − metallic)·transmission over its probability; Fresnel cancels.
        let scale = (1.0 - self.metallic) * self.transmission / pg;
        if u < f {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return BsdfSample { wi, weight: Vec3::splat(scale), pdf: 0.0, delta: true, crossed: false };
        }
        let wi = if self.thin { -wo } else { Vec3::new(-eta * wo.x, -eta * wo.y, -cos_t) };
        BsdfSample { wi, weight: self.base * scale, pdf: 0.0, delta: true, crossed: true }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn lambert(albedo: f32) -> Bsdf {
        Bsdf {
            base: Vec3::splat(albedo),
            metallic: 0.0,
            alpha: 1.0,
            f0: Vec3::ZERO,
            f90: 0.0,
            transmission: 0.0,
            ior: 1.5,
            thin: false,
            front: true,
        }
    }

    #[test]
    fn lambert_is_albedo_over_pi() {
        let b = lambert(0.6);
        let wi = Vec3::new(0.6, 0.0, 0.8);
        assert!((b.eval(Vec3::Z, wi) - Vec3::splat(0.6 / PI * 0.8)).abs().max_element() < 1e-6);
        // Importance sampling makes every weight the albedo exactly.
        let s = b.sample(Vec3::new(0.3, 0.1, 0.9).normalize(), [0.3, 0.7, 0.2]).unwrap();
        assert!((s.weight - Vec3::splat(0.6)).abs().max_element() < 1e-5);
    }

    #[test]
    fn fresnel_matches_known_values() {
        // Normal incidence on ior 1.5: ((1.5 − 1)/(1.5 + 1))² = 0.04.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5).0 - 0.04).abs() < 1e-6);
        // Total internal reflection beyond the critical angle (41.8°) from inside.
        assert_eq!(fresnel_dielectric(0.5f32, 1.5).0, 1.0);
    }

    #[test]
    fn glass_refraction_obeys_snell_and_keeps_energy() {
        let glass = Bsdf { transmission: 1.0, alpha: 0.0, f0: Vec3::splat(0.04), f90: 1.0, ..lambert(1.0) };
        let wo = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
        let s = glass.sample(wo, [0.99, 0.0, 0.0]).unwrap();
        assert!(s.crossed && s.delta && s.wi.z < 0.0);
        // sin θt = sin θi / 1.5.
        assert!((s.wi.truncate().length() - 0.5 / 1.5).abs() < 1e-5);
        assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-5);
        // Reflection when u < F, at the mirrored direction.
        let r = glass.sample(wo, [0.0, 0.0, 0.0]).unwrap();
        assert!(!r.crossed && (r.wi - Vec3::new(-0.5, 0.0, wo.z)).length() < 1e-6);
    }

    #[test]
    fn white_furnace_rough_metal_reflects_at_most_everything() {
        let metal = Bsdf { metallic: 1.0, alpha: 0.25, ..lambert(1.0) };
        let wo = Vec3::new(0.4, 0.2, 0.894).normalize();
        let n = 200_000;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let xi = [sobol_burley::sample(i, 0, 7), sobol_burley::sample(i, 1, 7), sobol_burley::sample(i, 2, 7)];
            if let Some(s) = metal.sample(wo, xi) {
                sum += s.weight;
            }
        }
        let albedo = sum / n as f32;
        // Single-scattering GGX loses a little energy at α = 0.25, never gains.
        assert!(albedo.x < 1.0 && albedo.x > 0.9, "{albedo}");
    }
}

//! CPU versions of the microfacet BRDF terms used by the shaders (glTF 2.0 Appendix B):
//! GGX distribution, height-correlated Smith visibility, Schlick Fresnel, GGX importance
//! sampling. The GPU uses them through precomputed tables (DFG, prefiltered probe); tests use
//! them as known answers.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// GGX / Trowbridge-Reitz normal distribution, `alpha = roughness²`.
pub fn ggx_d(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let f = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    a2 / (PI * f * f).max(1e-12)
}

/// Height-correlated Smith visibility `G / (4 n·l n·v)`.
pub fn smith_ggx_visibility(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_dot_l * (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt();
    let gl = n_dot_v * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt();
    0.5 / (gv + gl).max(1e-12)
}

/// Schlick's Fresnel weight `(1 − cos)^5`.
pub fn schlick_weight(cos: f32) -> f32 {
    (1.0 - cos).clamp(0.0, 1.0).powi(5)
}

/// The `i`-th of `n` points of the Hammersley set in [0, 1)².
pub fn hammersley(i: u32, n: u32) -> Vec2 {
    Vec2::new(i as f32 / n as f32, i.reverse_bits() as f32 * 2.328_306_4e-10)
}

/// A GGX-distributed half vector around +Z for the uniform sample `xi`.
pub fn sample_ggx_half_vector(xi: Vec2, alpha: f32) -> Vec3 {
    let phi = 2.0 * PI * xi.x;
    let cos_theta = ((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y)).max(0.0).sqrt();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// Split-sum DFG term (Karis 2013): for `n·v` and roughness, the scale `A` and bias `B` such
/// that the hemispherical integral of the specular BRDF times `n·l` is `F0·A + F90·B`.
pub fn integrate_dfg(n_dot_v: f32, roughness: f32, samples: u32) -> [f32; 2] {
    let alpha = roughness * roughness;
    let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
    let (mut a, mut b) = (0.0f32, 0.0f32);
    for i in 0..samples {
        let h = sample_ggx_half_vector(hammersley(i, samples), alpha);
        let l = 2.0 * v.dot(h) * h - v;
        let (n_dot_l, n_dot_h, v_dot_h) = (l.z, h.z.max(0.0), v.dot(h).max(0.0));
        if n_dot_l > 0.0 && n_dot_h > 0.0 {
            // f·cos / pdf with pdf = D·(n·h) / (4 v·h): D cancels.
            let weight = smith_ggx_visibility(n_dot_v, n_dot_l, alpha) * 4.0 * n_dot_l * v_dot_h / n_dot_h;
            let fc = schlick_weight(v_dot_h);
            a += (1.0 - fc) * weight;
            b += fc * weight;
        }
    }
    [a / samples as f32, b / samples as f32]
}

/// The DFG table, `size × size`, rows = roughness (0 at the top), columns = `n·v`, sampled at
/// texel centres.
pub fn dfg_table(size: u32, samples: u32) -> Vec<[f32; 2]> {
    let mut out = Vec::with_capacity((size * size) as usize);
    for y in 0..size {
        let roughness = (y as f32 + 0.5) / size as f32;
        for x in 0..size {
            let n_dot_v = ((x as f32 + 0.5) / size as f32).max(1e-3);
            out.push(integrate_dfg(n_dot_v, roughness, samples));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ggx_is_normalised_over_the_hemisphere() {
        // ∫ D(h) (n·h) dω_h = 1, checked by midpoint quadrature in θ.
        for &alpha in &[0.1f32, 0.5, 1.0] {
            let steps = 20_000;
            let mut sum = 0.0f64;
            for i in 0..steps {
                let theta = (i as f32 + 0.5) / steps as f32 * PI / 2.0;
                let d = ggx_d(theta.cos(), alpha) as f64;
                sum += d * (theta.cos() * theta.sin()) as f64 * 2.0 * PI as f64;
            }
            sum *= (PI / 2.0 / steps as f32) as f64;
            assert!((sum - 1.0).abs() < 1e-2, "alpha {alpha}: {sum}");
        }
    }

    #[test]
    fn mirror_dfg_reflects_everything() {
        let [a, b] = integrate_dfg(0.7, 0.0, 64);
        assert!((a + b - 1.0).abs() < 1e-4);
    }

    #[test]
    fn rough_dfg_loses_energy_but_stays_bounded() {
        let [a, b] = integrate_dfg(0.5, 1.0, 1024);
        assert!(a + b < 1.0 && a + b > 0.4, "{a} {b}");
    }
}

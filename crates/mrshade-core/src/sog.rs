//! Sum-of-Gaussians fit of the GGX lobe (Franke §2.5, [GKD07a], Eq. 4.25–4.26): for view
//! angle θ_o and roughness, the specular transfer `T(δ) = f_r·⟨n, ω_i⟩` around the mirror
//! direction ω_r is approximated by K isotropic Gaussians `w_k G_{σ_k}(μ_k − δ)`, so that a
//! glossy reflection of the probe costs K lookups into its prefiltered pyramid.
//!
//! The thesis leaves K, N and the fitting procedure open (spec §2.5 [Gap]). Here: K = 3, the
//! lobe is split, along the plane of incidence, into three bands of equal energy; each band
//! becomes one Gaussian with the band's weight, its mean offset toward the normal as μ_k
//! (the off-specular tilt of a grazing lobe) and its angular spread as σ_k. The mixture keeps
//! the lobe's mean direction and spread exactly (the law of total variance). The lobe's
//! energy is not in the table: weights sum to one and the split-sum albedo (`dfg_table`)
//! scales the result, Fresnel included.

use crate::brdf::{hammersley, sample_ggx_half_vector, smith_ggx_visibility};
use glam::Vec3;

/// Gaussians per lobe.
pub const LOBES: usize = 3;

/// One Gaussian of a lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian {
    /// Angular offset of its centre from ω_r toward the normal (radians).
    pub mu: f32,
    /// Angular standard deviation (radians).
    pub sigma: f32,
    /// Its share of the lobe (a lobe's weights sum to one).
    pub weight: f32,
}

/// The fitted lobes on a `size × size` grid: rows = roughness, columns = `n·v`, both at
/// texel centres (as `dfg_table`), `LOBES` Gaussians per cell.
pub struct SogTable {
    /// Cells per axis.
    pub size: u32,
    /// `LOBES` per cell, cells row by row.
    pub gaussians: Vec<Gaussian>,
}

impl SogTable {
    /// Fits every cell with `samples` GGX samples.
    pub fn fit(size: u32, samples: u32) -> Self {
        let mut gaussians = Vec::with_capacity((size * size) as usize * LOBES);
        for y in 0..size {
            let roughness = (y as f32 + 0.5) / size as f32;
            for x in 0..size {
                let n_dot_v = ((x as f32 + 0.5) / size as f32).max(1e-3);
                gaussians.extend(fit_lobe(n_dot_v, roughness, samples));
            }
        }
        SogTable { size, gaussians }
    }

    /// The table as the GPU reads it: per Gaussian (μ, σ, w, 0).
    pub fn to_vec4(&self) -> Vec<[f32; 4]> {
        self.gaussians.iter().map(|g| [g.mu, g.sigma, g.weight, 0.0]).collect()
    }
}

/// A lobe sample: its offsets from ω_r (toward the normal, across the plane of incidence,
/// radians) and its share of the lobe's energy.
struct LobeSample {
    along: f32,
    across: f32,
    weight: f32,
}

/// The GGX lobe `f_r·cos` (without Fresnel) of a surface with normal +Z seen from
/// `v = (sin θ_o, 0, cos θ_o)`, importance-sampled: offsets from the mirror direction.
fn lobe_samples(n_dot_v: f32, roughness: f32, samples: u32) -> Vec<LobeSample> {
    let alpha = (roughness * roughness).max(1e-4);
    let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
    let mirror = Vec3::new(-v.x, 0.0, v.z);
    // Toward the normal within the plane of incidence (+x for a grazing view), and across.
    let toward = Vec3::new(mirror.z, 0.0, -mirror.x);
    let across = Vec3::Y;
    let mut out = Vec::with_capacity(samples as usize);
    for i in 0..samples {
        let h = sample_ggx_half_vector(hammersley(i, samples), alpha);
        let l = 2.0 * v.dot(h) * h - v;
        let (n_dot_l, n_dot_h, v_dot_h) = (l.z, h.z, v.dot(h));
        if n_dot_l <= 0.0 || n_dot_h <= 0.0 || v_dot_h <= 0.0 {
            continue;
        }
        // f·cos / pdf, pdf = D·(n·h)/(4 v·h): D cancels (as in `integrate_dfg`).
        let weight = smith_ggx_visibility(n_dot_v, n_dot_l, alpha) * 4.0 * n_dot_l * v_dot_h / n_dot_h;
        let c = l.dot(mirror);
        out.push(LobeSample { along: l.dot(toward).atan2(c), across: l.dot(across).atan2(c), weight });
    }
    out
}

/// The `LOBES` Gaussians of one lobe: equal-energy bands along the plane of incidence.
pub fn fit_lobe(n_dot_v: f32, roughness: f32, samples: u32) -> [Gaussian; LOBES] {
    let mut s = lobe_samples(n_dot_v, roughness, samples);
    let total: f32 = s.iter().map(|x| x.weight).sum();
    if s.is_empty() || total <= 0.0 {
        return [Gaussian { mu: 0.0, sigma: 0.0, weight: 1.0 / LOBES as f32 }; LOBES];
    }
    s.sort_by(|a, b| a.along.total_cmp(&b.along));
    let mut out = [Gaussian { mu: 0.0, sigma: 0.0, weight: 0.0 }; LOBES];
    let mut seen = 0.0;
    let mut band: [(f32, f32, f32, f32); LOBES] = [(0.0, 0.0, 0.0, 0.0); LOBES];
    for x in &s {
        // The band that holds the middle of this sample's share of the energy.
        let k = (((seen + 0.5 * x.weight) / total) * LOBES as f32).floor().min(LOBES as f32 - 1.0) as usize;
        seen += x.weight;
        let b = &mut band[k];
        b.0 += x.weight;
        b.1 += x.weight * x.along;
        b.2 += x.weight * x.along * x.along;
        b.3 += x.weight * x.across * x.across;
    }
    for (g, (w, m1, m2, across2)) in out.iter_mut().zip(band) {
        if w <= 0.0 {
            continue;
        }
        let mu = m1 / w;
        // Isotropic: the mean of the band's variances along and across (the across mean is
        // zero by symmetry).
        let variance = 0.5 * ((m2 / w - mu * mu).max(0.0) + across2 / w);
        *g = Gaussian { mu, sigma: variance.sqrt(), weight: w / total };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLES: u32 = 4096;

    /// The lobe's own mean offset and its variance along and across the plane of incidence.
    fn moments(n_dot_v: f32, roughness: f32) -> (f32, f32) {
        let s = lobe_samples(n_dot_v, roughness, SAMPLES);
        let total: f32 = s.iter().map(|x| x.weight).sum();
        let mean = s.iter().map(|x| x.weight * x.along).sum::<f32>() / total;
        let var = s.iter().map(|x| x.weight * ((x.along - mean).powi(2) + x.across.powi(2))).sum::<f32>() / total;
        (mean, var)
    }

    #[test]
    fn weights_sum_to_one_and_bands_share_the_energy() {
        for (n_dot_v, roughness) in [(1.0, 0.1), (0.5, 0.4), (0.2, 0.8)] {
            let g = fit_lobe(n_dot_v, roughness, SAMPLES);
            let sum: f32 = g.iter().map(|g| g.weight).sum();
            assert!((sum - 1.0).abs() < 1e-4, "{n_dot_v} {roughness}: {g:?}");
            for g in g {
                assert!((g.weight - 1.0 / 3.0).abs() < 0.02, "{n_dot_v} {roughness}: {g:?}");
            }
        }
    }

    #[test]
    fn the_mixture_keeps_the_lobes_mean_and_spread() {
        for (n_dot_v, roughness) in [(0.9, 0.2), (0.5, 0.5), (0.15, 0.35)] {
            let g = fit_lobe(n_dot_v, roughness, SAMPLES);
            let (mean, var) = moments(n_dot_v, roughness);
            let mixture_mean: f32 = g.iter().map(|g| g.weight * g.mu).sum();
            // Total variance: within the Gaussians (two axes) plus between their means.
            let mixture_var: f32 = g.iter().map(|g| g.weight * (2.0 * g.sigma * g.sigma + (g.mu - mean).powi(2))).sum();
            assert!((mixture_mean - mean).abs() < 1e-4, "{n_dot_v} {roughness}: mean {mixture_mean} vs {mean}");
            assert!(
                (mixture_var - var).abs() < 1e-3 * var.max(1e-3),
                "{n_dot_v} {roughness}: var {mixture_var} vs {var}"
            );
        }
    }

    #[test]
    fn a_smooth_lobe_is_narrow_and_a_grazing_one_tilts_toward_the_normal() {
        let sharp = fit_lobe(1.0, 0.05, SAMPLES);
        assert!(sharp.iter().all(|g| g.sigma < 0.02 && g.mu.abs() < 0.02), "{sharp:?}");
        let rough = fit_lobe(1.0, 0.6, SAMPLES);
        assert!(rough.iter().all(|g| g.sigma > 0.1), "{rough:?}");
        // At normal incidence the lobe is symmetric: its bands mirror each other.
        assert!((rough[0].mu + rough[2].mu).abs() < 0.02 && rough[1].mu.abs() < 0.02, "{rough:?}");
        let grazing = fit_lobe(0.2, 0.5, SAMPLES);
        let mean: f32 = grazing.iter().map(|g| g.weight * g.mu).sum();
        assert!(mean > 0.05, "the off-specular peak: {grazing:?}");
    }

    #[test]
    fn the_table_holds_every_cell() {
        let t = SogTable::fit(4, 256);
        assert_eq!(t.gaussians.len(), 4 * 4 * LOBES);
        assert_eq!(t.to_vec4().len(), t.gaussians.len());
    }
}

//! Chi-square tests: the directions [`Bsdf::sample`] draws are distributed as [`Bsdf::pdf`]
//! says (Mitsuba's and pbrt's BSDF tests). A wrong pdf biases every MIS weight, so each lobe
//! and mix the renderer uses is checked, at a steep and a grazing view.

use super::tests::lambert;
use super::*;

const Z_BINS: usize = 10;
const PHI_BINS: usize = 20;
const SAMPLES: u32 = 400_000;

fn bin_of(wi: Vec3) -> usize {
    let z = ((wi.z * Z_BINS as f32) as usize).min(Z_BINS - 1);
    let phi = wi.y.atan2(wi.x).rem_euclid(2.0 * PI);
    let p = ((phi / (2.0 * PI) * PHI_BINS as f32) as usize).min(PHI_BINS - 1);
    z * PHI_BINS + p
}

/// Expected counts: the pdf integrated over each bin (bins of equal solid angle: uniform in
/// z = cos θ and in φ) by 96×96 midpoints (the lobes are narrow).
fn expected(bsdf: &Bsdf, wo: Vec3) -> Vec<f64> {
    let sub = 96;
    let bin_solid_angle = (1.0 / Z_BINS as f64) * (2.0 * std::f64::consts::PI / PHI_BINS as f64);
    let mut out = vec![0.0f64; Z_BINS * PHI_BINS];
    for (i, e) in out.iter_mut().enumerate() {
        let (zi, pi) = (i / PHI_BINS, i % PHI_BINS);
        let mut sum = 0.0f64;
        for a in 0..sub {
            for b in 0..sub {
                let z = (zi as f32 + (a as f32 + 0.5) / sub as f32) / Z_BINS as f32;
                let phi = (pi as f32 + (b as f32 + 0.5) / sub as f32) / PHI_BINS as f32 * 2.0 * PI;
                let r = (1.0 - z * z).max(0.0).sqrt();
                sum += bsdf.pdf(wo, Vec3::new(r * phi.cos(), r * phi.sin(), z)) as f64;
            }
        }
        *e = sum / (sub * sub) as f64 * bin_solid_angle * SAMPLES as f64;
    }
    out
}

/// Independent uniform numbers: the statistic assumes a multinomial count per bin, which a
/// stratified sequence (far more even) does not give in thin bins.
fn independent_uniform(n: u32) -> f32 {
    (crate::sampler::hash(n ^ 0x5bd1_e995) >> 8) as f32 / (1 << 24) as f32
}

/// The chi-square statistic's upper-tail z-score (Wilson–Hilferty), pooling sparse bins.
fn chi_square_z(bsdf: &Bsdf, wo: Vec3) -> f64 {
    let mut observed = vec![0.0f64; Z_BINS * PHI_BINS];
    for i in 0..SAMPLES {
        let xi = [0, 1, 2].map(|d| independent_uniform(3 * i + d));
        if let Some(s) = bsdf.sample(wo, xi).filter(|s| !s.delta) {
            assert!((s.pdf - bsdf.pdf(wo, s.wi)).abs() <= 1e-3 * s.pdf.max(1.0), "sample pdf ≠ pdf()");
            observed[bin_of(s.wi)] += 1.0;
        }
    }
    let expected = expected(bsdf, wo);
    let (mut chi2, mut dof, mut pooled_o, mut pooled_e) = (0.0f64, 0usize, 0.0f64, 0.0f64);
    for (o, e) in observed.iter().zip(&expected) {
        if *e < 5.0 {
            pooled_o += o;
            pooled_e += e;
        } else {
            chi2 += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    if pooled_e >= 5.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        dof += 1;
    } else {
        assert!(pooled_o < 20.0, "{pooled_o} samples where the pdf expects {pooled_e}");
    }
    let k = (dof - 1) as f64;
    ((chi2 / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt()
}

fn check(name: &str, bsdf: Bsdf) {
    for wo in [Vec3::new(0.3, 0.1, 0.95), Vec3::new(0.9, -0.3, 0.15)] {
        let z = chi_square_z(&bsdf, wo.normalize());
        // z < 4 ⇔ p > 3·10⁻⁵: a correct sampler fails about once in 30 000 runs (and the
        // sequence is fixed, so it never flakes).
        assert!(z < 4.0, "{name}, wo {wo}: chi-square z-score {z:.1}");
    }
}

#[test]
fn lambert_sampling_matches_its_pdf() {
    check("lambert", lambert(0.7));
}

#[test]
fn rough_metal_sampling_matches_its_pdf() {
    check("rough metal", Bsdf { metallic: 1.0, alpha: 0.1225, base: Vec3::new(0.95, 0.75, 0.45), ..lambert(1.0) });
}

#[test]
fn rough_dielectric_mix_sampling_matches_its_pdf() {
    check("rough plastic", Bsdf { alpha: 0.3, f0: Vec3::splat(0.04), f90: 1.0, ..lambert(0.5) });
    check("half metal", Bsdf { metallic: 0.5, alpha: 0.5, f0: Vec3::splat(0.04), f90: 1.0, ..lambert(0.8) });
}

#[test]
fn smooth_lobes_of_mixes_with_mirrors_and_glass_match_their_pdf() {
    // Only the diffuse part is sampled by density; the mirror and glass events are counted out.
    check("varnish", Bsdf { alpha: 0.0, f0: Vec3::splat(0.04), f90: 1.0, ..lambert(0.5) });
    check("frosted half glass", Bsdf { transmission: 0.5, f0: Vec3::splat(0.04), f90: 1.0, ..lambert(0.5) });
}

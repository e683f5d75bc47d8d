//! Sample numbers: an Owen-scrambled Sobol sequence (Burley 2020, `sobol_burley`) per pixel,
//! with a fixed dimension for every use at every bounce. Fixed dimensions keep the two lanes
//! of a split path on the same numbers (their difference stays correlated), and make a
//! render reproducible from its seed.

/// The uses of sample numbers within one bounce.
#[derive(Clone, Copy, Debug)]
pub enum Slot {
    /// Probe sample, first coordinate.
    LightU,
    /// Probe sample, second coordinate.
    LightV,
    /// Which BSDF lobe (and reflect or refract).
    BsdfLobe,
    /// BSDF direction, first coordinate.
    BsdfU,
    /// BSDF direction, second coordinate.
    BsdfV,
    /// Russian roulette.
    Roulette,
}

const SLOTS_PER_BOUNCE: u32 = 6;
/// Pixel position (2); the bounces follow.
const CAMERA_DIMENSIONS: u32 = 2;

/// The numbers of one path: sample `index` of the pixel's sequence.
pub struct PathSampler {
    seed: u32,
    index: u32,
}

/// A well-mixed 32-bit hash (Wellons' lowbias32).
pub fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

impl PathSampler {
    /// Sample `index` (< 2^16) of pixel `pixel` for the render seed `seed`.
    pub fn new(pixel: u32, index: u32, seed: u32) -> PathSampler {
        PathSampler { seed: hash(pixel ^ hash(seed.wrapping_add(0x9e37_79b9))), index }
    }

    /// The numbers of photon `photon` of light `light` for the render seed `seed`. The Sobol
    /// sequence holds 2^16 samples, so photons come in runs of 2^16, each run on its own
    /// scramble seed (independent sequences; stratified within a run).
    pub fn photon(light: u32, photon: u64, seed: u32) -> PathSampler {
        let run = (photon >> 16) as u32;
        let stream = hash(hash(light ^ 0x68e3_1da4) ^ hash(run.wrapping_add(0x1b87_3593)));
        PathSampler { seed: hash(stream ^ hash(seed.wrapping_add(0x7f4a_7c15))), index: (photon & 0xffff) as u32 }
    }

    /// The sub-pixel position in [0, 1)²; for a photon, its emission's first two numbers.
    pub fn pixel(&self) -> [f32; 2] {
        [self.dimension(0), self.dimension(1)]
    }

    /// The number for `slot` at `bounce`, in [0, 1).
    pub fn get(&self, bounce: u32, slot: Slot) -> f32 {
        self.dimension(CAMERA_DIMENSIONS + bounce * SLOTS_PER_BOUNCE + slot as u32)
    }

    fn dimension(&self, d: u32) -> f32 {
        // The sequence has 256 dimensions; beyond them another scramble seed pads it.
        let n = sobol_burley::NUM_DIMENSIONS;
        sobol_burley::sample(self.index, d % n, hash(self.seed ^ (d / n)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_uniform_and_stratified() {
        // 256 samples of one pixel: each of 16 strata of every dimension holds 16 of them.
        for slot in [Slot::LightU, Slot::Roulette] {
            let mut strata = [0u32; 16];
            for i in 0..256 {
                let v = PathSampler::new(7, i, 3).get(20, slot);
                assert!((0.0..1.0).contains(&v));
                strata[(v * 16.0) as usize] += 1;
            }
            assert!(strata.iter().all(|&c| c == 16), "{strata:?}");
        }
    }

    #[test]
    fn pixels_and_seeds_get_other_numbers() {
        let a = PathSampler::new(1, 0, 0).pixel();
        assert_ne!(a, PathSampler::new(2, 0, 0).pixel());
        assert_ne!(a, PathSampler::new(1, 0, 1).pixel());
        assert_eq!(a, PathSampler::new(1, 0, 0).pixel());
    }
}

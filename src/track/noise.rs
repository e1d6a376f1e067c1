//! A small seeded random stream for the simulations of this module: uniform and Gaussian
//! numbers, reproducible from a seed on every platform and independent of any other generator.
//!
//! ## Reference
//! G. L. Steele, D. Lea, C. H. Flood, *Fast splittable pseudorandom number generators*,
//! OOPSLA 2014, doi:10.1145/2660193.2660195 (SplitMix64); G. E. P. Box, M. E. Muller, *A note on
//! the generation of random normal deviates*, Ann. Math. Statist. 29 (1958) 610–611,
//! doi:10.1214/aoms/1177706645.

/// The increment of SplitMix64 (the golden ratio in 64 bits).
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output function: a bijective 64-bit mix.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A SplitMix64 stream keyed by `(seed, stream)`: different streams of one seed are independent
/// (the plant's parameters, its torque noise and its sensors each draw from their own).
#[derive(Debug, Clone)]
pub struct Noise {
    state: u64,
}

impl Noise {
    /// The stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        Self { state: mix64(mix64(seed.wrapping_add(GAMMA)) ^ stream.wrapping_mul(GAMMA)) }
    }

    /// The next uniform number in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(GAMMA);
        (mix64(self.state) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next uniform number in `[-1, 1)`.
    pub fn symmetric(&mut self) -> f64 {
        2.0 * self.uniform() - 1.0
    }

    /// The next standard normal number (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // in (0, 1]: the logarithm is finite
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let (mut a, mut b, mut c) = (Noise::new(7, 0), Noise::new(7, 0), Noise::new(7, 1));
        let xa: Vec<f64> = (0..5).map(|_| a.uniform()).collect();
        let xb: Vec<f64> = (0..5).map(|_| b.uniform()).collect();
        let xc: Vec<f64> = (0..5).map(|_| c.uniform()).collect();
        assert_eq!(xa, xb);
        assert_ne!(xa, xc);
        assert!(xa.iter().all(|x| (0.0..1.0).contains(x)));
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut n = Noise::new(1, 2);
        let xs: Vec<f64> = (0..20_000).map(|_| n.normal()).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03 && (var - 1.0).abs() < 0.05, "mean {mean}, variance {var}");
    }
}

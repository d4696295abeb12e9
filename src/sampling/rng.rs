//! Keyed random streams.
//!
//! Every random number in Photon comes from an [`Rng`] whose stream is named by a key such as
//! (seed, pixel, sample index): the same key gives the same numbers on any thread, so images are
//! bit-identical whatever the thread count. There is no global generator.

/// PCG32 (O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good Algorithms
/// for Random Number Generation", 2014): 64-bit LCG state, XSH-RR output.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const PCG_MULT: u64 = 6364136223846793005;

/// SplitMix64 finaliser (Steele et al. 2014): a bijective 64-bit mixer used to turn keys into
/// well-spread seeds.
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Rng {
    /// A stream keyed by `seed` and a list of indices (for example pixel and sample index).
    pub fn keyed(seed: u64, key: &[u64]) -> Self {
        let mut h = mix64(seed);
        for &k in key {
            h = mix64(h ^ k.wrapping_mul(0xD6E8_FEB8_6659_FD93));
        }
        let stream = mix64(h ^ 0x5851_F42D_4C95_7F2D);
        let mut rng = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(h);
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    pub fn next_u64(&mut self) -> u64 {
        (u64::from(self.next_u32()) << 32) | u64::from(self.next_u32())
    }

    /// Uniform in [0, 1), with 24 bits of resolution (every value exactly representable).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in [0, 1) with 53 bits of resolution.
    pub fn next_f64(&mut self) -> f64 {
        let hi = u64::from(self.next_u32()) << 21;
        let lo = u64::from(self.next_u32() >> 11);
        (hi | lo) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    pub fn next_2d(&mut self) -> glam::Vec2 {
        let x = self.next_f32();
        glam::Vec2::new(x, self.next_f32())
    }
}

/// A source of uniform random numbers in [0, 1): an [`Rng`], or one whose first numbers come
/// from a low-discrepancy sequence ([`super::halton::Prefixed`]).
pub trait Sampler {
    fn next_f32(&mut self) -> f32;

    fn next_2d(&mut self) -> glam::Vec2 {
        let x = self.next_f32();
        glam::Vec2::new(x, self.next_f32())
    }
}

impl Sampler for Rng {
    #[inline]
    fn next_f32(&mut self) -> f32 {
        Rng::next_f32(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_key_same_stream_and_different_keys_differ() {
        let a: Vec<u32> = (0..8)
            .scan(Rng::keyed(7, &[1, 2]), |r, _| Some(r.next_u32()))
            .collect();
        let b: Vec<u32> = (0..8)
            .scan(Rng::keyed(7, &[1, 2]), |r, _| Some(r.next_u32()))
            .collect();
        let c: Vec<u32> = (0..8)
            .scan(Rng::keyed(7, &[2, 1]), |r, _| Some(r.next_u32()))
            .collect();
        let d: Vec<u32> = (0..8)
            .scan(Rng::keyed(8, &[1, 2]), |r, _| Some(r.next_u32()))
            .collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
    }

    #[test]
    fn floats_are_in_unit_interval_with_the_right_mean() {
        let mut r = Rng::keyed(1, &[]);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += f64::from(x);
        }
        assert!((sum / f64::from(n) - 0.5).abs() < 0.005);
    }
}

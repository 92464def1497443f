//! Deterministic random numbers for jittered samples.

/// A counter-based generator: a hash of (stream, index) gives a uniform
/// number in [0, 1). Samples depend only on what they are for (vertex, shot,
/// cell), never on thread scheduling, so solutions are reproducible.
#[derive(Clone, Copy, Debug)]
pub struct SampleStream {
    state: u64,
}

impl SampleStream {
    /// A stream keyed by two integers.
    #[must_use]
    pub fn new(a: u64, b: u64) -> Self {
        SampleStream {
            state: mix(
                a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ mix(b.wrapping_add(0x632B_E59B_D9B4_E019))
            ),
        }
    }

    /// The next uniform number in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        (mix(self.state) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// SplitMix64's finaliser (Steele, Lea, Flood 2014).
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_mean_and_range() {
        let mut s = SampleStream::new(3, 7);
        let values: Vec<f64> = (0..100_000).map(|_| s.next_f64()).collect();
        assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        assert!((mean - 0.5).abs() < 0.005, "{mean}");
    }
}

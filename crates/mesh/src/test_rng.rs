//! A tiny deterministic generator for the workspace's unit tests (no external crates in unit
//! tests), one copy for every crate: compiled for this crate's tests and, with the
//! `test-util` feature, which the other crates' dev-dependencies turn on, for theirs. Not part
//! of the public API.

use glam::DVec3;

/// A linear congruential generator (Knuth's MMIX constants).
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in `[0, 1)`. (Not `Iterator::next`: the stream never ends, and the tests read
    /// it one value at a time.)
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[-0.5, 0.5)`.
    pub fn centred(&mut self) -> f64 {
        self.next() - 0.5
    }

    /// A point with coordinates in `[-1, 1)`.
    pub fn point(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
    }

    /// A vector with coordinates in `[-0.5, 0.5)`.
    pub fn vec(&mut self) -> DVec3 {
        DVec3::new(self.centred(), self.centred(), self.centred())
    }
}

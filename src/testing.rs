//! Helpers shared by the unit tests (compiled for `cfg(test)` only).

/// Deterministic pseudo-random numbers for tests: xorshift64 (shifts 13, 7,
/// 17), no dependency. A seed gives the same sequence on every platform, so
/// the tests that use it (solver checks, fuzzing of the readers) see the same
/// numbers on every run.
pub(crate) struct Rng(u64);

impl Rng {
    /// A generator started at `seed` (not 0: xorshift stays at 0).
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A number in `0..n` (0 for `n == 0`).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// A number in `[-1, 1)` (53 random bits).
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

#[test]
fn rng_is_xorshift64() {
    let mut rng = Rng::new(1);
    // 1 → 1 ^ 1<<13 = 8193; ^ 8193>>7 = 8257; ^ 8257<<17 = 1082269761
    assert_eq!(rng.next(), 1_082_269_761);
    let mut a = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut b = Rng::new(0x9e37_79b9_7f4a_7c15);
    for _ in 0..100 {
        let n = a.below(7);
        assert!(n < 7);
        assert_eq!(n as u64, b.next() % 7);
        let u = a.unit();
        assert!((-1.0..1.0).contains(&u));
        b.next();
    }
    assert_eq!(a.below(0), 0);
}

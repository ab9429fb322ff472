//! Deterministic random streams.
//!
//! Every random draw of the simulator comes from a ChaCha8 stream whose seed is derived from the
//! simulation seed and a key (the purpose, a scan counter, a ray-chunk index) by SplitMix64
//! mixing. Streams never depend on thread scheduling or on how many other streams were used, so
//! adding a sensor does not change the robot's trajectory and a scan is identical on 1 or 64
//! threads.

use rand::SeedableRng;
use rand::rngs::ChaCha8Rng;

/// Purpose keys of the simulator's independent streams.
pub(crate) mod key {
    /// Motion (speed noise).
    pub const MOTION: u64 = 0x6d6f_7469_6f6e;
    /// Proprioception (roll process, power, vibration, bumper noise).
    pub const PROPRIO: u64 = 0x7072_6f70_7269;
    /// Pose-stream noise.
    pub const POSE: u64 = 0x706f_7365;
    /// Range scans (further keyed by scan counter and chunk).
    pub const SCAN: u64 = 0x7363_616e;
}

/// SplitMix64 finaliser: a bijective 64-bit mixer.
#[inline]
pub(crate) fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A ChaCha8 stream keyed by `(seed, keys...)`.
pub(crate) fn stream(seed: u64, keys: &[u64]) -> ChaCha8Rng {
    let mut h = mix(seed);
    for &k in keys {
        h = mix(h ^ k);
    }
    ChaCha8Rng::seed_from_u64(h)
}

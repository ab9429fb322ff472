//! Per-candidate visibility of the disc's targets, one bit per disc entry.

/// Sets bit `k`.
#[inline]
pub(super) fn set_bit(v: &mut [u64], k: usize) {
    v[k / 64] |= 1 << (k % 64);
}

/// Bit `k`.
#[inline]
pub(super) fn get_bit(v: &[u64], k: usize) -> bool {
    v[k / 64] >> (k % 64) & 1 == 1
}

/// Sets or clears bit `k`.
#[inline]
pub(super) fn put_bit(v: &mut [u64], k: usize, on: bool) {
    if on {
        set_bit(v, k);
    } else {
        v[k / 64] &= !(1 << (k % 64));
    }
}

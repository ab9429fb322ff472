//! The fixed-capacity ring buffer every estimator stores its window in, and the scalar samples of
//! the proprioceptive stream kept in such rings.

use super::common::SkipCounts;

/// A fixed-capacity FIFO: the storage is a boxed slice allocated once, so pushing can never
/// allocate. Pushing onto a full ring drops the oldest element.
#[derive(Clone, Debug)]
pub(super) struct Ring<T> {
    buf: Box<[T]>,
    head: usize,
    len: usize,
}

impl<T: Copy + Default> Ring<T> {
    pub(super) fn new(capacity: usize) -> Self {
        Self {
            buf: vec![T::default(); capacity.max(1)].into_boxed_slice(),
            head: 0,
            len: 0,
        }
    }

    pub(super) fn capacity(&self) -> usize {
        self.buf.len()
    }

    pub(super) fn len(&self) -> usize {
        self.len
    }

    pub(super) fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    /// Appends `v`; returns true when the ring was full and its oldest element was dropped.
    pub(super) fn push_back(&mut self, v: T) -> bool {
        let cap = self.buf.len();
        let dropped = self.len == cap;
        if dropped {
            self.head = (self.head + 1) % cap;
            self.len -= 1;
        }
        let k = (self.head + self.len) % cap;
        self.buf[k] = v;
        self.len += 1;
        dropped
    }

    pub(super) fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let v = self.buf[self.head];
        self.head = (self.head + 1) % self.buf.len();
        self.len -= 1;
        Some(v)
    }

    pub(super) fn get(&self, i: usize) -> Option<T> {
        (i < self.len).then(|| self.buf[(self.head + i) % self.buf.len()])
    }

    pub(super) fn front(&self) -> Option<T> {
        self.get(0)
    }

    pub(super) fn back(&self) -> Option<T> {
        self.len.checked_sub(1).and_then(|i| self.get(i))
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = T> + Clone + '_ {
        (0..self.len).map(move |i| self.buf[(self.head + i) % self.buf.len()])
    }

    /// The number of leading elements for which `pred` holds (the ring must be partitioned by
    /// it, as `slice::partition_point` requires): a binary search, O(log len).
    pub(super) fn partition_point(&self, pred: impl Fn(&T) -> bool) -> usize {
        let (mut lo, mut hi) = (0, self.len);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if pred(&self.buf[(self.head + mid) % self.buf.len()]) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }
}

/// A scalar sample of the proprioceptive stream.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Scalar {
    pub(super) stamp: f64,
    pub(super) value: f64,
}

/// Pushes `s` onto a scalar ring with the same validation as the pose track; false when skipped.
pub(super) fn push_scalar(ring: &mut Ring<Scalar>, s: Scalar, skips: &mut SkipCounts) -> bool {
    if !(s.stamp.is_finite() && s.value.is_finite()) {
        skips.non_finite += 1;
        return false;
    }
    if let Some(last) = ring.back()
        && s.stamp <= last.stamp
    {
        skips.out_of_order += 1;
        return false;
    }
    if ring.push_back(s) {
        skips.overrun += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_drops_oldest_when_full() {
        let mut r: Ring<u32> = Ring::new(3);
        assert!(!r.push_back(1));
        assert!(!r.push_back(2));
        assert!(!r.push_back(3));
        assert!(r.push_back(4));
        assert_eq!(r.iter().collect::<Vec<_>>(), vec![2, 3, 4]);
        assert_eq!(r.pop_front(), Some(2));
        assert_eq!(r.front(), Some(3));
        assert_eq!(r.back(), Some(4));
        assert_eq!(r.capacity(), 3);
    }
}

//! Small helpers on cell rectangles and world rectangles (growing, union, intersection) used by
//! every incremental update of the map. Candidates for `strider-core::grid` later.

use serde::{Deserialize, Serialize};
use strider_core::{Cell, CellRect, Point2};

/// The smallest rectangle holding both `a` and `b`.
pub fn union(a: CellRect, b: CellRect) -> CellRect {
    if a.is_empty() {
        return b;
    }
    if b.is_empty() {
        return a;
    }
    let (ai1, aj1) = max_corner(a);
    let (bi1, bj1) = max_corner(b);
    from_corners(
        Cell::new(a.min.i.min(b.min.i), a.min.j.min(b.min.j)),
        Cell::new(ai1.max(bi1), aj1.max(bj1)),
    )
}

/// The rectangle holding `r` and the cell `c`.
pub fn include(r: Option<CellRect>, c: Cell) -> CellRect {
    let one = CellRect::new(c, 1, 1);
    r.map_or(one, |r| union(r, one))
}

/// The intersection of `a` and `b`, `None` when they do not overlap.
pub fn intersection(a: CellRect, b: CellRect) -> Option<CellRect> {
    let (ai1, aj1) = max_corner(a);
    let (bi1, bj1) = max_corner(b);
    let lo = Cell::new(a.min.i.max(b.min.i), a.min.j.max(b.min.j));
    let hi = (ai1.min(bi1), aj1.min(bj1));
    (lo.i <= hi.0 && lo.j <= hi.1 && !a.is_empty() && !b.is_empty())
        .then(|| from_corners(lo, Cell::new(hi.0, hi.1)))
}

/// `r` grown by `n` cells on every side.
pub fn expand(r: CellRect, n: u32) -> CellRect {
    CellRect::new(
        r.min.offset(-(n as i32), -(n as i32)),
        r.width + 2 * n,
        r.height + 2 * n,
    )
}

/// `r` extended to cover `needed`: each side that `needed` passes moves out to `needed`'s
/// edge plus `margin` cells; the other sides stay where they are (growing every side by the
/// margin each time would inflate a rectangle that grows often without bound).
pub fn grown_to_cover(r: CellRect, needed: CellRect, margin: u32) -> CellRect {
    if r.is_empty() {
        return expand(needed, margin);
    }
    if needed.is_empty() {
        return r;
    }
    let m = margin as i32;
    let (ri1, rj1) = max_corner(r);
    let (ni1, nj1) = max_corner(needed);
    let side = |mine: i32, theirs: i32, outward: i32| {
        if (theirs as i64 - mine as i64) * outward as i64 > 0 {
            theirs.saturating_add(outward * m)
        } else {
            mine
        }
    };
    from_corners(
        Cell::new(
            side(r.min.i, needed.min.i, -1),
            side(r.min.j, needed.min.j, -1),
        ),
        Cell::new(side(ri1, ni1, 1), side(rj1, nj1, 1)),
    )
}

/// The rectangle from its lowest and highest cell (both inclusive).
pub fn from_corners(lo: Cell, hi: Cell) -> CellRect {
    CellRect::new(
        lo,
        (hi.i as i64 - lo.i as i64 + 1).max(0) as u32,
        (hi.j as i64 - lo.j as i64 + 1).max(0) as u32,
    )
}

/// The highest cell (inclusive) of a non-empty rectangle, as `(i, j)`.
pub fn max_corner(r: CellRect) -> (i32, i32) {
    (r.min.i + r.width as i32 - 1, r.min.j + r.height as i32 - 1)
}

/// Copies the part of `src` (a raster over `src_rect`) that lies in `dst_rect` into a new raster
/// over `dst_rect`; `dst_rect` must lie inside `src_rect`.
pub fn crop<T: Copy>(src: &[T], src_rect: CellRect, dst_rect: CellRect) -> Vec<T> {
    let mut out = Vec::with_capacity(dst_rect.len());
    let (di, dj) = (
        (dst_rect.min.i - src_rect.min.i) as usize,
        (dst_rect.min.j - src_rect.min.j) as usize,
    );
    let sw = src_rect.width as usize;
    for row in 0..dst_rect.height as usize {
        let start = (dj + row) * sw + di;
        out.extend_from_slice(&src[start..start + dst_rect.width as usize]);
    }
    out
}

/// An axis-aligned rectangle in world coordinates (metres), e.g. the exploration bounds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorldRect {
    /// Lower-left corner.
    pub min: Point2,
    /// Upper-right corner.
    pub max: Point2,
}

impl WorldRect {
    /// A rectangle from two corners (any order).
    pub fn new(a: Point2, b: Point2) -> Self {
        Self {
            min: Point2::new(a.x.min(b.x), a.y.min(b.y)),
            max: Point2::new(a.x.max(b.x), a.y.max(b.y)),
        }
    }
    /// True when the point lies inside (boundary included).
    pub fn contains(&self, p: Point2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }
    /// True when the centre of `c` (cell size `d`) lies inside.
    pub fn contains_cell(&self, c: Cell, d: f64) -> bool {
        self.contains(c.center(d))
    }
}

/// Exploration bounds: a cell counts (as unknown to gain, as a goal) only when it is inside.
/// `None` means unbounded.
pub(crate) fn in_bounds(bounds: Option<&WorldRect>, c: Cell, d: f64) -> bool {
    bounds.is_none_or(|b| b.contains_cell(c, d))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Growing to cover keeps the rectangle, covers what is needed, moves only the sides
        /// that were passed, and stays within the needed hull plus the margin however often it
        /// grows.
        #[test]
        fn grown_to_cover_moves_only_the_sides_passed(
            steps in proptest::collection::vec((-30i32..30, -30i32..30, 1u32..20, 1u32..20), 1..40),
            margin in 0u32..10,
        ) {
            let mut r = CellRect::new(Cell::new(0, 0), 5, 5);
            let mut hull = r;
            for (i, j, w, h) in steps {
                let needed = CellRect::new(Cell::new(i, j), w, h);
                let g = grown_to_cover(r, needed, margin);
                prop_assert_eq!(intersection(g, r), Some(r));
                prop_assert_eq!(intersection(g, needed), Some(needed));
                let (ri1, rj1) = max_corner(r);
                let (gi1, gj1) = max_corner(g);
                let (ni1, nj1) = max_corner(needed);
                prop_assert!(g.min.i == r.min.i || g.min.i == needed.min.i - margin as i32);
                prop_assert!(g.min.j == r.min.j || g.min.j == needed.min.j - margin as i32);
                prop_assert!(gi1 == ri1 || gi1 == ni1 + margin as i32);
                prop_assert!(gj1 == rj1 || gj1 == nj1 + margin as i32);
                hull = union(hull, needed);
                r = g;
                prop_assert_eq!(intersection(r, expand(hull, margin)), Some(r));
            }
        }
    }

    #[test]
    fn union_intersection_expand() {
        let a = CellRect::new(Cell::new(-2, -2), 3, 3);
        let b = CellRect::new(Cell::new(0, 0), 4, 2);
        let u = union(a, b);
        assert_eq!(u, CellRect::new(Cell::new(-2, -2), 6, 4));
        assert_eq!(
            intersection(a, b),
            Some(CellRect::new(Cell::new(0, 0), 1, 1))
        );
        assert_eq!(intersection(a, CellRect::new(Cell::new(5, 5), 1, 1)), None);
        assert_eq!(expand(a, 2), CellRect::new(Cell::new(-4, -4), 7, 7));
        let src: Vec<usize> = (0..u.len()).collect();
        let c = crop(&src, u, b);
        assert_eq!(c, vec![14, 15, 16, 17, 20, 21, 22, 23]);
    }
}

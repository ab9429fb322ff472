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

//! Erosion and dilation redone only near the cells that changed, for class maps kept from one
//! learning update to the next. Both operations are local: after s steps a cell depends on the
//! cells within s (erosion) or s·n_size (dilation) of it, so only the cells close to a change can
//! differ from the last result. The results equal the whole-map operations' (property tests
//! compare them).

use super::{TerrainCell, dilate_in_place, eroded_at};

/// Side of the blocks [`recompute_near`] groups the changes in, cells.
const BLOCK: usize = 32;

/// Recomputes `dst` = the `steps`-step erosion of `src` (a `w`-wide map) at the cells within
/// `steps` of the cells `changed`, the only ones it can have changed there, each read
/// off `src` directly ([`eroded_at`]): scattered changes cost a few squares each
/// instead of a block's window. Returns the cells of `dst` that changed, ascending.
pub fn erode_near(
    src: &[TerrainCell],
    dst: &mut [TerrainCell],
    w: usize,
    changed: &[u32],
    steps: usize,
) -> Vec<u32> {
    let mut out = Vec::new();
    if w == 0 || src.len() != dst.len() {
        return out;
    }
    let h = src.len() / w;
    let side = 2 * steps.min(w.max(h)) + 1;
    if changed.len().saturating_mul(side * side) >= src.len() {
        // So many changes that their squares would cover the map several times: every cell
        // once, in order.
        for n in 0..h * w {
            record(dst, n, eroded_at(src, w, h, n % w, n / w, steps), &mut out);
        }
        return out;
    }
    for &k in changed {
        let (x, y) = (k as usize % w, k as usize / w);
        if y >= h {
            continue;
        }
        let (x0, x1) = (x.saturating_sub(steps), (x + steps).min(w - 1));
        for ny in y.saturating_sub(steps)..=(y + steps).min(h - 1) {
            for nx in x0..=x1 {
                // A cell near several changes is computed again, to the same value: it is
                // listed once, when it first changes.
                let v = eroded_at(src, w, h, nx, ny, steps);
                record(dst, ny * w + nx, v, &mut out);
            }
        }
    }
    out.sort_unstable();
    out
}

/// Sets `dst[k]` to `v`, listing `k` in `out` when that changes it.
#[inline]
fn record(dst: &mut [TerrainCell], k: usize, v: TerrainCell, out: &mut Vec<u32>) {
    if dst[k] != v {
        dst[k] = v;
        out.push(k as u32);
    }
}

/// Recomputes `dst` = `op(src)` near the cells `changed` of a `w`-wide map, for an
/// operation that reads no farther than `reach` cells. The map is cut into blocks of [`BLOCK`]
/// cells; in each block, only the rectangle spanning the cells within `reach` of its changes
/// can differ, and it is computed on its window grown by `reach` (in `scratch`), whose own
/// edge can disturb only that margin, which is not copied back. A lone change costs a window
/// of (4·reach + 1)² cells instead of a whole block's. `op` gets the window, its width and its
/// cells that are not unknown. Returns the cells of `dst` that changed, ascending.
fn recompute_near(
    src: &[TerrainCell],
    dst: &mut [TerrainCell],
    w: usize,
    changed: &[u32],
    reach: usize,
    scratch: &mut Vec<TerrainCell>,
    mut op: impl FnMut(&mut [TerrainCell], usize, &[u32]),
) -> Vec<u32> {
    let mut out = Vec::new();
    if w == 0 || src.len() != dst.len() {
        return out;
    }
    let h = src.len() / w;
    let areas = touched_areas(changed, w, h, reach);
    let windows: usize = areas.iter().map(|a| window(a, reach, w, h).len()).sum();
    if windows >= src.len() {
        return recompute_everywhere(src, dst, scratch, op, w);
    }
    let mut support = Vec::new();
    for area in areas {
        let win = window(&area, reach, w, h);
        let (wx0, wy0, wx1, wy1) = (win.x0, win.y0, win.x1, win.y1);
        let ww = wx1 - wx0;
        scratch.clear();
        for y in wy0..wy1 {
            scratch.extend_from_slice(&src[y * w + wx0..y * w + wx1]);
        }
        support.clear();
        support.extend(
            (0..scratch.len() as u32).filter(|&k| scratch[k as usize] != TerrainCell::Unknown),
        );
        op(scratch, ww, &support);
        for y in area.y0..area.y1 {
            for x in area.x0..area.x1 {
                record(
                    dst,
                    y * w + x,
                    scratch[(y - wy0) * ww + (x - wx0)],
                    &mut out,
                );
            }
        }
    }
    out.sort_unstable();
    out
}

/// A rectangle of cells, `x0..x1` × `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Area {
    x0: usize,
    y0: usize,
    x1: usize,
    y1: usize,
}

impl Area {
    fn len(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }

    fn union(self, o: Area) -> Area {
        Area {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }
}

/// `area` grown by `reach`, within the `w` × `h` map.
fn window(area: &Area, reach: usize, w: usize, h: usize) -> Area {
    Area {
        x0: area.x0.saturating_sub(reach),
        y0: area.y0.saturating_sub(reach),
        x1: (area.x1 + reach).min(w),
        y1: (area.y1 + reach).min(h),
    }
}

/// `dst` = `op(src)` over the whole map, when the windows near the changes would hold more
/// cells than the map (`scratch` keeps the old `dst` to list the cells that changed).
fn recompute_everywhere(
    src: &[TerrainCell],
    dst: &mut [TerrainCell],
    scratch: &mut Vec<TerrainCell>,
    mut op: impl FnMut(&mut [TerrainCell], usize, &[u32]),
    w: usize,
) -> Vec<u32> {
    scratch.clear();
    scratch.extend_from_slice(dst);
    dst.copy_from_slice(src);
    let support: Vec<u32> = (0..dst.len() as u32)
        .filter(|&k| dst[k as usize] != TerrainCell::Unknown)
        .collect();
    op(dst, w, &support);
    (0..dst.len() as u32)
        .filter(|&k| dst[k as usize] != scratch[k as usize])
        .collect()
}

/// Per block within `reach` of the cells `changed`, in block order: the smallest rectangle of
/// the block holding every cell of it within `reach` of a change.
fn touched_areas(changed: &[u32], w: usize, h: usize, reach: usize) -> Vec<Area> {
    let bw = w.div_ceil(BLOCK);
    let mut parts: Vec<(usize, Area)> = Vec::new();
    for &k in changed {
        let (x, y) = (k as usize % w, k as usize / w);
        if y >= h {
            continue;
        }
        let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(w - 1) + 1);
        let (y0, y1) = (y.saturating_sub(reach), (y + reach).min(h - 1) + 1);
        for by in y0 / BLOCK..=(y1 - 1) / BLOCK {
            for bx in x0 / BLOCK..=(x1 - 1) / BLOCK {
                let part = Area {
                    x0: x0.max(bx * BLOCK),
                    y0: y0.max(by * BLOCK),
                    x1: x1.min((bx + 1) * BLOCK),
                    y1: y1.min((by + 1) * BLOCK),
                };
                parts.push((by * bw + bx, part));
            }
        }
    }
    parts.sort_unstable_by_key(|&(b, _)| b);
    let mut areas: Vec<Area> = Vec::new();
    let mut last = None;
    for (b, part) in parts {
        match areas.last_mut() {
            Some(a) if last == Some(b) => *a = a.union(part),
            _ => areas.push(part),
        }
        last = Some(b);
    }
    areas
}

/// Recomputes `dst` = the dilation of `src` ([`dilate_in_place`] with `n_size`, `n_steps`; a
/// `w`-wide map) near the storage cells `changed`, with [`recompute_near`]. `scratch` is
/// working memory kept between calls. Returns the cells of `dst` that changed, ascending.
#[allow(clippy::too_many_arguments)]
pub fn dilate_near(
    src: &[TerrainCell],
    dst: &mut [TerrainCell],
    w: usize,
    changed: &[u32],
    n_size: usize,
    n_steps: usize,
    scratch: &mut Vec<TerrainCell>,
) -> Vec<u32> {
    recompute_near(
        src,
        dst,
        w,
        changed,
        n_steps.saturating_mul(n_size),
        scratch,
        |v, ww, s| dilate_in_place(v, ww, s, n_size, n_steps),
    )
}

#[cfg(test)]
mod tests {
    use super::super::{ClassId, erode_in_place};
    use super::*;
    use proptest::prelude::*;

    fn cell_of(code: u8) -> TerrainCell {
        match code {
            0 => TerrainCell::Unknown,
            1 => TerrainCell::Eroded,
            c => TerrainCell::Class(ClassId(u32::from(c - 2))),
        }
    }

    fn known(values: &[TerrainCell]) -> Vec<u32> {
        (0..values.len() as u32)
            .filter(|&k| values[k as usize] != TerrainCell::Unknown)
            .collect()
    }

    proptest! {
        /// After changes to the source, erosion and dilation redone near them equal the
        /// whole-map operations.
        #[test]
        fn recomputed_near_changes_equals_whole_map(
            w in 1usize..80,
            h in 1usize..80,
            seed_codes in proptest::collection::vec(2u8..5, 1..64),
            edits in proptest::collection::vec((0usize..6400, 0u8..5), 0..30),
            steps in 1usize..4,
            size in 1usize..3,
        ) {
            // Patches of classes (so that erosion keeps some), some unknown and eroded.
            let before: Vec<TerrainCell> = (0..w * h)
                .map(|k| {
                    let (x, y) = (k % w, k / w);
                    cell_of(seed_codes[(x / 7 + 3 * (y / 5)) % seed_codes.len()])
                })
                .collect();
            let erode_all = |v: &[TerrainCell]| {
                let mut v = v.to_vec();
                let s = known(&v);
                erode_in_place(&mut v, w, &s, steps);
                v
            };
            let dilate_all = |v: &[TerrainCell]| {
                let mut v = v.to_vec();
                let s = known(&v);
                dilate_in_place(&mut v, w, &s, size, steps);
                v
            };
            let mut eroded = erode_all(&before);
            let mut dilated = dilate_all(&eroded);
            let mut after = before.clone();
            let mut changed = Vec::new();
            for (k, c) in edits {
                let k = k % (w * h);
                if after[k] != cell_of(c) {
                    after[k] = cell_of(c);
                    changed.push(k as u32);
                }
            }
            changed.sort_unstable();
            changed.dedup();
            let mut scratch = Vec::new();
            let mut by_blocks = eroded.clone();
            let t_changed = erode_near(&after, &mut eroded, w, &changed, steps);
            prop_assert_eq!(&eroded, &erode_all(&after));
            let t_by_blocks = recompute_near(&after, &mut by_blocks, w, &changed, steps,
                &mut scratch, |v, ww, s| erode_in_place(v, ww, s, steps));
            prop_assert_eq!(&by_blocks, &eroded);
            prop_assert_eq!(&t_by_blocks, &t_changed);
            let src = eroded.clone();
            recompute_near(&src, &mut dilated, w, &t_changed, steps * size, &mut scratch,
                |v, ww, s| dilate_in_place(v, ww, s, size, steps));
            prop_assert_eq!(dilated, dilate_all(&eroded));
        }
    }
}

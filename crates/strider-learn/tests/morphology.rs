//! Tests of class-map erosion and dilation (Prágr22 Eq. 25–26, decision 18).

use strider_core::grid::{Cell, CellRect};
use strider_learn::igng::ClassId;
use strider_learn::morphology::{MorphologyError, TerrainCell, dilate, erode, from_classes};
use strider_map::descriptors::Raster;

const U: TerrainCell = TerrainCell::Unknown;
const E: TerrainCell = TerrainCell::Eroded;

fn c(id: u32) -> TerrainCell {
    TerrainCell::Class(ClassId(id))
}

/// A raster at an arbitrary offset from rows given top (j = 0) first.
fn raster(rows: &[Vec<TerrainCell>]) -> Raster<TerrainCell> {
    let h = rows.len() as u32;
    let w = rows[0].len() as u32;
    Raster {
        rect: CellRect::new(Cell::new(-7, 12), w, h),
        values: rows.iter().flatten().copied().collect(),
    }
}

fn filled(
    w: usize,
    h: usize,
    mut f: impl FnMut(usize, usize) -> TerrainCell,
) -> Raster<TerrainCell> {
    let mut rows: Vec<Vec<TerrainCell>> = Vec::with_capacity(h);
    for y in 0..h {
        rows.push((0..w).map(|x| f(x, y)).collect());
    }
    raster(&rows)
}

/// A `size` × `size` raster with the square `span` × `span` of `inside` on `outside`.
fn block(
    size: usize,
    span: std::ops::Range<usize>,
    inside: TerrainCell,
    outside: TerrainCell,
) -> Raster<TerrainCell> {
    filled(size, size, |x, y| {
        if span.contains(&x) && span.contains(&y) {
            inside
        } else {
            outside
        }
    })
}

fn at(r: &Raster<TerrainCell>, x: usize, y: usize) -> TerrainCell {
    r.values[y * r.rect.width as usize + x]
}

#[test]
fn one_cell_wide_line_is_eroded_completely() {
    // Class 1 line (column 5) through a class-0 field.
    let r = filled(11, 11, |x, _| if x == 5 { c(1) } else { c(0) });
    let e = erode(&r, 1).unwrap();
    for y in 0..11 {
        assert_eq!(at(&e, 5, y), E);
        // Its class-0 neighbours border a different class too.
        assert_eq!(at(&e, 4, y), E);
        assert_eq!(at(&e, 6, y), E);
    }
    assert!(e.values.iter().all(|&v| v != c(1)));
    // Interior class-0 cells away from the line and the raster edge survive.
    assert_eq!(at(&e, 2, 5), c(0));
}

#[test]
fn five_by_five_block_shrinks_to_three_by_three() {
    let r = block(9, 2..7, c(3), c(0));
    let e = erode(&r, 1).unwrap();
    let block: Vec<(usize, usize)> = (0..9)
        .flat_map(|y| (0..9).map(move |x| (x, y)))
        .filter(|&(x, y)| at(&e, x, y) == c(3))
        .collect();
    let expected: Vec<(usize, usize)> = (3..6).flat_map(|y| (3..6).map(move |x| (x, y))).collect();
    assert_eq!(block, expected);
    // The block's former border is ∅.
    for k in 2..7 {
        assert_eq!(at(&e, k, 2), E);
        assert_eq!(at(&e, 2, k), E);
    }
    // Two steps leave only the centre.
    let e2 = erode(&r, 2).unwrap();
    assert_eq!(e2.values.iter().filter(|&&v| v == c(3)).count(), 1);
    assert_eq!(at(&e2, 4, 4), c(3));
}

#[test]
fn unknown_and_outside_neighbours_erode_unknown_cells_stay() {
    // 3x3 known block in an unknown field: only its centre survives; the raster edge counts as
    // unknown, so a fully known 3x3 raster keeps only its centre as well.
    let r = block(5, 1..4, c(1), U);
    let e = erode(&r, 1).unwrap();
    assert_eq!(e.values.iter().filter(|&&v| v == c(1)).count(), 1);
    assert_eq!(at(&e, 2, 2), c(1));
    assert_eq!(e.values.iter().filter(|&&v| v == U).count(), 16);
    let full = filled(3, 3, |_, _| c(1));
    let e = erode(&full, 1).unwrap();
    assert_eq!(e.values.iter().filter(|&&v| v == c(1)).count(), 1);
}

#[test]
fn dilation_restores_an_eroded_block_border() {
    // A 5x5 class-2 block on unknown ground: erosion leaves 3x3 + an eroded ring; dilation gives
    // the ring back and leaves the unknown cells unknown.
    let r = block(9, 2..7, c(2), U);
    let e = erode(&r, 1).unwrap();
    assert_eq!(e.values.iter().filter(|&&v| v == E).count(), 16);
    for n_size in [1, 2] {
        let d = dilate(&e, n_size, 3).unwrap();
        assert_eq!(d, r, "n_size = {n_size}");
    }
}

#[test]
fn dilation_never_overwrites_classes_or_unknown() {
    // Pseudo-random map of classes 0..3, unknown and eroded cells.
    let mut s = 12345u64;
    let r = filled(23, 17, |_, _| {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        match (s >> 33) % 6 {
            0 => U,
            1 | 2 => E,
            k => c(k as u32 - 3),
        }
    });
    let d = dilate(&r, 2, 3).unwrap();
    for (a, b) in r.values.iter().zip(&d.values) {
        match a {
            TerrainCell::Eroded => assert!(*b == E || b.class().is_some()),
            other => assert_eq!(b, other),
        }
    }
    // Deterministic.
    assert_eq!(d, dilate(&r, 2, 3).unwrap());
    assert_eq!(erode(&r, 2).unwrap(), erode(&r, 2).unwrap());
}

#[test]
fn dilation_picks_the_majority_and_grows_one_window_per_step() {
    // Row: C1 C1 C4 ∅ ∅ ∅ ∅ ∅ with n_size = 2: the window x-2..=x+2 of x = 3 holds C1 (x=1) and
    // C4 (x=2): a tie → the lowest id, 1; x = 4 sees C4 only; x ≥ 5 sees no class yet.
    let r = raster(&[vec![c(1), c(1), c(4), E, E, E, E, E]]);
    let d1 = dilate(&r, 2, 1).unwrap();
    assert_eq!(d1.values, vec![c(1), c(1), c(4), c(1), c(4), E, E, E]);
    // Second step: x = 5 sees C4 (x=4) and C1 (x=3) → tie → 1; x = 6 sees C4 (x=4) → 4.
    let d2 = dilate(&r, 2, 2).unwrap();
    assert_eq!(d2.values, vec![c(1), c(1), c(4), c(1), c(4), c(1), c(4), E]);
    // Majority: ∅ surrounded by three C7 and two C2 takes C7.
    let r = raster(&[vec![c(7), c(2), U], vec![c(7), E, c(2)], vec![c(7), U, U]]);
    assert_eq!(at(&dilate(&r, 1, 1).unwrap(), 1, 1), c(7));
    // No class in reach: stays ∅.
    let r = raster(&[vec![c(1), U, U, E]]);
    assert_eq!(at(&dilate(&r, 1, 5).unwrap(), 3, 0), E);
}

#[test]
fn erode_then_dilate_on_two_regions() {
    // Left half class 0, right half class 1, all known: after erosion and dilation every cell
    // has a class again and the boundary is still a straight vertical line.
    let r = filled(12, 10, |x, _| if x < 6 { c(0) } else { c(1) });
    let e = erode(&r, 2).unwrap();
    let d = dilate(&e, 2, 3).unwrap();
    for y in 0..10 {
        for x in 0..12 {
            let expect = if x < 6 { c(0) } else { c(1) };
            assert_eq!(at(&d, x, y), expect, "({x}, {y})");
        }
    }
}

#[test]
fn shape_mismatch_is_an_error() {
    let r = Raster {
        rect: CellRect::new(Cell::new(0, 0), 3, 3),
        values: vec![U; 8],
    };
    assert_eq!(
        erode(&r, 1),
        Err(MorphologyError::ShapeMismatch {
            expected: 9,
            got: 8
        })
    );
    assert!(dilate(&r, 1, 1).is_err());
    assert!(from_classes(r.rect, &[None; 4]).is_err());
    let ok = from_classes(
        r.rect,
        &[
            Some(ClassId(1)),
            None,
            None,
            None,
            None,
            None,
            None,
            None,
            None,
        ],
    )
    .unwrap();
    assert_eq!(ok.values[0], c(1));
    assert_eq!(ok.values[1], U);
    assert_eq!(ok.get(Cell::new(0, 0)), Some(&c(1)));
}

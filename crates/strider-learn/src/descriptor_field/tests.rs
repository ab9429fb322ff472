use super::*;
use proptest::prelude::*;
use strider_core::Rgb8;
use strider_map::MapParams;
use strider_map::descriptors::{color_histograms, histogram_reach};

#[test]
fn from_raster_skips_absent_and_non_finite() {
    let rect = CellRect::new(Cell::new(-1, -1), 2, 2);
    let r = Raster {
        rect,
        values: vec![
            Some([1.0, 2.0]),
            None,
            Some([f32::NAN, 0.0]),
            Some([0.5, 0.5]),
        ],
    };
    let f = DescriptorField::from_raster(&r);
    assert_eq!(f.dim(), 2);
    assert_eq!(f.get(Cell::new(-1, -1)), Some(&[1.0, 2.0][..]));
    assert_eq!(f.get(Cell::new(0, -1)), None);
    assert_eq!(f.get(Cell::new(-1, 0)), None);
    assert_eq!(f.get(Cell::new(0, 0)), Some(&[0.5, 0.5][..]));
    assert_eq!(f.described_count(), 2);
    assert_eq!(f.rejected(), 1);
    assert_eq!(f.get(Cell::new(5, 5)), None);
}

#[test]
fn storage_rect_is_an_aligned_cover() {
    let r = CellRect::new(Cell::new(-3, 70), 10, 1);
    let s = storage_rect(r);
    assert_eq!(s, CellRect::new(Cell::new(-64, 64), 128, 64));
    let edge = CellRect::new(Cell::new(i32::MAX - 2, i32::MIN), 3, 2);
    let s = storage_rect(edge);
    assert!(s.contains(Cell::new(i32::MAX, i32::MIN)) && s.contains(edge.min));
    assert!(storage_rect(CellRect::new(Cell::new(5, 5), 0, 0)).is_empty());
}

#[test]
fn set_keeps_row_major_order_and_survives_relayout() {
    let mut f = DescriptorField::empty(CellRect::new(Cell::new(0, 0), 10, 10), 1);
    assert!(f.set(Cell::new(5, 5), &[1.0]));
    assert!(f.set(Cell::new(1, 0), &[2.0]));
    assert!(!f.set(Cell::new(2, 2), &[f64::INFINITY]));
    assert!(!f.set(Cell::new(20, 0), &[1.0]), "outside the rectangle");
    let cells: Vec<Cell> = f.described().map(|(n, _)| f.storage().cell(n)).collect();
    assert_eq!(cells, vec![Cell::new(1, 0), Cell::new(5, 5)]);
    f.resize(CellRect::new(Cell::new(-100, 0), 200, 10));
    assert_eq!(f.get(Cell::new(5, 5)), Some(&[1.0][..]));
    assert_eq!(f.get(Cell::new(1, 0)), Some(&[2.0][..]));
    f.resize(CellRect::new(Cell::new(3, 0), 5, 10));
    assert_eq!(f.get(Cell::new(1, 0)), None, "left the rectangle");
    assert_eq!(f.described_count(), 1);
    assert!(f.set(Cell::new(4, 1), &[3.0]), "a freed slot is reused");
    assert_eq!(f.get(Cell::new(5, 5)), Some(&[1.0][..]));
}

#[test]
fn forgotten_changes_read_empty_now_and_start_older_consumers_over() {
    let mut f = DescriptorField::empty(CellRect::new(Cell::new(0, 0), 10, 10), 1);
    f.set(Cell::new(1, 1), &[1.0]);
    let old = f.version();
    f.set(Cell::new(1, 1), &[2.0]);
    f.set(Cell::new(2, 2), &[3.0]);
    assert_eq!(f.changes_since(old).map(|c| c.count()), Some(1));
    assert_eq!(f.added_since(old).map(<[u32]>::len), Some(1));
    let now = f.version();
    f.forget_changes();
    assert_eq!(f.changes_since(now).map(|c| c.count()), Some(0));
    assert_eq!(f.added_since(now), Some(&[][..]));
    assert!(f.changes_since(old).is_none() && f.added_since(old).is_none());
    // Changes after it are logged as before.
    f.set(Cell::new(2, 2), &[4.0]);
    let logged: Vec<(usize, Vec<f64>)> = f
        .changes_since(now)
        .unwrap()
        .map(|(n, d)| (n, d.to_vec()))
        .collect();
    assert_eq!(
        logged,
        vec![(f.storage().index(Cell::new(2, 2)).unwrap(), vec![3.0])]
    );
    assert_eq!(f.get(Cell::new(1, 1)), Some(&[2.0][..]));
}

fn full(map: &ElevationMap, r_hist: f64) -> DescriptorField {
    match map.known_bounds() {
        Some(rect) => DescriptorField::from_raster(&color_histograms(map, rect, r_hist)),
        None => DescriptorField::empty(CellRect::new(Cell::new(0, 0), 0, 0), 9),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// After any sequence of map writes, the incrementally refreshed field equals the field
    /// computed from scratch, descriptor for descriptor and in the same order.
    #[test]
    fn refresh_equals_full_computation(
        batches in prop::collection::vec(
            prop::collection::vec((-40i32..40, -30i32..30, 0u8..4), 1..60),
            1..6,
        )
    ) {
        let mut map = ElevationMap::new(MapParams::default());
        let r_hist = map.params().r_hist;
        let reach = histogram_reach(r_hist, map.cell_size());
        let mut field = DescriptorField::empty(CellRect::new(Cell::new(0, 0), 0, 0), 9);
        let mut seen = map.changes().revision();
        let palette = [Rgb8([200, 30, 30]), Rgb8([30, 200, 30]), Rgb8([90, 90, 90]), Rgb8([250, 250, 250])];
        for batch in batches {
            for (i, j, col) in batch {
                // Blobs rather than single cells, so that histograms pass the half-known rule.
                for dj in 0..7 {
                    for di in 0..7 {
                        map.set_cell(Cell::new(i + di, j + dj), 0.0, 0.01, palette[col as usize]);
                    }
                }
            }
            let rect = map.known_bounds().expect("cells were written");
            let changed = map.changes().changed_since(seen);
            field.refresh(&map, rect, &changed, reach, |m, r| color_histograms(m, r, r_hist));
            seen = map.changes().revision();
            let want = full(&map, r_hist);
            prop_assert!(field == want);
            prop_assert!(want.described_count() > 0);
        }
    }
}

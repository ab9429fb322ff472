use super::sight::{crosses_below, touches_sight_line};
use super::*;
use crate::observability::{ray_clear, ray_clear_in};
use crate::params::MapParams;
use crate::testing::{block, flat};
use approx::assert_abs_diff_eq;
use strider_core::grid::disc_offsets;
use strider_core::{Point2, Rgb8};
fn params() -> MapParams {
    MapParams {
        cell_size: 0.1,
        tile_size: 8,
        r_sensor: 0.2, // disc of 13 cells
        r_robot: 0.0,
        sensor_height: 0.3,
        ..MapParams::default()
    }
}

#[test]
fn cell_information_counts_unknown_neighbours() {
    let mut m = ElevationMap::new(params());
    assert_abs_diff_eq!(
        cell_information(&m, Cell::new(0, 0), None),
        1.0,
        epsilon = 1e-6
    );
    flat(&mut m, [Cell::new(1, 0), Cell::new(1, 1)]);
    assert_abs_diff_eq!(
        cell_information(&m, Cell::new(0, 0), None),
        7.0 / 9.0,
        epsilon = 1e-6
    );
    assert_abs_diff_eq!(
        cell_information(&m, Cell::new(1, 0), None),
        0.0,
        epsilon = 1e-6
    );
    // Bounds: the cell itself outside gives nothing; neighbours outside do not count.
    let b = WorldRect::new(Point2::new(-0.1, -0.1), Point2::new(0.1, 1.0));
    assert_abs_diff_eq!(
        cell_information(&m, Cell::new(0, 0), Some(&b)),
        6.0 / 9.0,
        epsilon = 1e-6
    );
    assert_abs_diff_eq!(
        cell_information(&m, Cell::new(2, 0), Some(&b)),
        0.0,
        epsilon = 1e-6
    );
}

#[test]
fn model_information_on_a_strip() {
    // A known 1-cell-wide strip j = 0, i ∈ [-5, 5]; the disc of radius 2 cells around (0, 0)
    // holds 13 cells: 5 known (the strip), 8 unknown. Unknown (0, ±1), (±1, ±1): neighbours
    // include 3 known strip cells → k = 5, I = 6/9; (0, ±2): k = 8 → 1; and (±1, ±1) → k = 5.
    let mut m = ElevationMap::new(params());
    flat(&mut m, block(-5, 0, 11, 1));
    let expected = 2.0 * (6.0 / 9.0 * 3.0) + 2.0 * 1.0;
    assert_abs_diff_eq!(
        model_information(&m, Cell::new(0, 0), None),
        expected,
        epsilon = 1e-6
    );
    // A tall known wall cell between the robot and (0, 2) hides it.
    m.set_cell(Cell::new(0, 1), 2.0, 1e-4, Rgb8::default());
    let hidden = expected - 6.0 / 9.0 - 1.0 - 2.0 * (1.0 / 9.0);
    // (0,1) became known: it no longer counts, (0,2) is hidden behind it and the unknown
    // cells (±1, 1) lost one unknown neighbour each.
    assert_abs_diff_eq!(
        model_information(&m, Cell::new(0, 0), None),
        hidden,
        epsilon = 1e-6
    );
}

#[test]
fn information_gain_on_candidates() {
    let mut m = ElevationMap::new(params());
    // Known 11 × 11 square: interior cells see no unknown cell within 2 cells.
    flat(&mut m, block(-5, -5, 11, 11));
    let reach = Reachability::compute(&m, Cell::new(0, 0));
    let g = information_gain(&m, &reach, None);
    // Candidates: every cell except the border ring (no known neighbour on all sides is
    // fine; the border ring is passable too) → 121 evaluated.
    assert_eq!(g.candidates, 121);
    // Cells with an unknown cell within 2 cells: the outer two rings (121 − 7·7).
    assert_eq!(g.cells.len(), 121 - 49);
    let corner = g
        .cells
        .iter()
        .find(|&&(c, _)| c == Cell::new(5, 5))
        .unwrap()
        .1;
    assert_abs_diff_eq!(corner, model_information(&m, Cell::new(5, 5), None));
    // With a stride of 2 only even lattice cells are evaluated.
    let mut m2 = m.clone();
    m2.set_info_gain_stride(2);
    let g2 = information_gain(&m2, &reach, None);
    assert_eq!(g2.candidates, 25);
    // Bounds that exclude everything beyond the square leave nothing to gain.
    let b = WorldRect::new(Point2::new(-0.5, -0.5), Point2::new(0.6, 0.6));
    assert!(information_gain(&m, &reach, Some(&b)).cells.is_empty());
}

/// Applies `edits` (never to the robot's cell (0, 0)), then evaluates Eq. 11 through the
/// cache and afresh.
fn edit_and_evaluate(
    m: &mut ElevationMap,
    cache: &mut GainCache,
    edits: &[(i32, i32, f32)],
) -> (InfoGain, InfoGain) {
    for &(i, j, z) in edits {
        if (i, j) != (0, 0) {
            m.set_cell(Cell::new(i, j), z, 1e-4, Rgb8::default());
        }
    }
    m.update_passability();
    let reach = Reachability::compute(m, Cell::new(0, 0));
    (
        cache.compute(m, &reach, None),
        information_gain(m, &reach, None),
    )
}

/// The cache's result equals the fresh evaluation's.
fn same_gains(
    cached: &InfoGain,
    fresh: &InfoGain,
) -> Result<(), proptest::test_runner::TestCaseError> {
    proptest::prop_assert_eq!(cached.candidates, fresh.candidates);
    proptest::prop_assert_eq!(&cached.cells, &fresh.cells);
    Ok(())
}

#[test]
fn cache_reuses_unchanged_candidates_and_follows_changes() {
    let mut m = ElevationMap::new(MapParams {
        r_sensor: 0.3,
        ..params()
    });
    flat(&mut m, block(-10, -10, 21, 21));
    let reach = Reachability::compute(&m, Cell::new(0, 0));
    let mut cache = GainCache::new(0.01);
    let first = cache.compute(&m, &reach, None);
    assert_eq!(first.cells, information_gain(&m, &reach, None).cells);
    assert!(cache.last_evaluated() > 0);
    // Nothing changed: everything comes from the cache.
    let again = cache.compute(&m, &reach, None);
    assert_eq!(again.cells, first.cells);
    assert_eq!(cache.last_evaluated(), 0);
    // A change below the hysteresis is ignored; above it only nearby candidates are
    // re-evaluated and the result is exact again.
    m.set_cell(Cell::new(9, 9), 0.005, 1e-4, Rgb8::default());
    m.update_passability();
    cache.compute(&m, &reach, None);
    assert_eq!(cache.last_evaluated(), 0);
    m.set_cell(Cell::new(9, 9), 0.2, 1e-4, Rgb8::default());
    m.set_cell(Cell::new(11, 9), 0.0, 1e-4, Rgb8::default());
    m.update_passability();
    let reach = Reachability::compute(&m, Cell::new(0, 0));
    let after = cache.compute(&m, &reach, None);
    let (evaluated, updated) = (cache.last_evaluated(), cache.last_updated());
    assert!(
        updated > 0,
        "nearby candidates are updated, not re-evaluated"
    );
    assert!(
        evaluated + updated < after.candidates,
        "{evaluated} {updated}"
    );
    assert_eq!(after.cells, information_gain(&m, &reach, None).cells);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// Delta updates are exact: on a fixed-size patchy map with walls, random edits
    /// (unknown cells becoming known, known cells rising or sinking) leave the cache equal
    /// to a fresh evaluation.
    #[test]
    fn cache_updates_equal_fresh_evaluation(
        init in proptest::collection::vec((proptest::bool::weighted(0.6), 0.0f32..0.6), 625),
        steps in proptest::collection::vec(
            proptest::collection::vec((-12..=12i32, -12..=12i32, 0.0f32..0.6), 1..12),
            1..6,
        ),
        dz in proptest::prop_oneof![proptest::strategy::Just(0.0f64), 0.0f64..0.05],
    ) {
        let mut m = ElevationMap::new(MapParams { r_sensor: 0.6, ..params() });
        for (k, &(known, z)) in init.iter().enumerate() {
            let c = Cell::new(k as i32 % 25 - 12, k as i32 / 25 - 12);
            // Corners pin the known bounds so the view never grows.
            let corner = c.i.abs() == 12 && c.j.abs() == 12;
            if known || corner || c == Cell::new(0, 0) {
                let z = if c == Cell::new(0, 0) { 0.0 } else { z };
                m.set_cell(c, z, 1e-4, Rgb8::default());
            }
        }
        m.update_passability();
        let mut cache = GainCache::new(dz);
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        let first = cache.compute(&m, &reach, None);
        proptest::prop_assert_eq!(first.cells, information_gain(&m, &reach, None).cells);
        for edits in steps {
            let (cached, fresh) = edit_and_evaluate(&mut m, &mut cache, &edits);
            if dz == 0.0 {
                same_gains(&cached, &fresh)?;
            }
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]
    /// With dz = 0 the cache equals a fresh evaluation after every step of a random
    /// sequence of map edits (new cells, raised cells, the map growing).
    #[test]
    fn cache_equals_fresh_evaluation(
        steps in proptest::collection::vec(
            proptest::collection::vec((-12..12i32, -12..12i32, 0.0f32..0.5), 1..30),
            1..6,
        ),
    ) {
        let mut m = ElevationMap::new(MapParams { r_sensor: 0.4, ..params() });
        flat(&mut m, block(-2, -2, 5, 5));
        let mut cache = GainCache::new(0.0);
        for edits in steps {
            let (cached, fresh) = edit_and_evaluate(&mut m, &mut cache, &edits);
            same_gains(&cached, &fresh)?;
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// The shadow-direction shortcut is exact: I_model equals the sum over every unknown
    /// target of I_cell when its ray (cast unconditionally) is clear.
    #[test]
    fn shadow_pruning_is_exact(
        heights in proptest::collection::vec(0.0f32..0.6, 144),
        known in proptest::collection::vec(proptest::bool::weighted(0.6), 144),
        ci in 0..12i32, cj in 0..12i32,
    ) {
        let mut m = ElevationMap::new(MapParams { r_sensor: 0.5, ..params() });
        for k in 0..144 {
            if known[k] || k == (cj * 12 + ci) as usize {
                m.set_cell(Cell::new(k as i32 % 12, k as i32 / 12), heights[k], 1e-4, Rgb8::default());
            }
        }
        let c = Cell::new(ci, cj);
        let ef = m.elevation(c).unwrap();
        let mut brute = 0.0;
        for (di, dj) in disc_offsets(0.5, 0.1) {
            let t = c.offset(di, dj);
            if m.is_observed(t) {
                continue;
            }
            let clear = ray_clear(c, t, ef as f64 + 0.3, ef as f64, 0.1, |x| m.elevation(x));
            if clear {
                brute += cell_information(&m, t, None);
            }
        }
        let fast = model_information(&m, c, None);
        proptest::prop_assert!((fast - brute).abs() < 1e-4, "fast {fast} brute {brute}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
    /// The two per-cell tests of the delta update agree with the sight-line test itself,
    /// on heights placed within centimetres of the sight line (the near-tangent cases):
    /// a cell that `crosses_below` blocks the line whatever else the raster holds, and a
    /// cell that does not `touches_sight_line` leaves the line's result unchanged when it
    /// is made unknown.
    #[test]
    fn delta_cell_tests_agree_with_the_sight_line(
        known in proptest::collection::vec(proptest::bool::weighted(0.2), 441),
        noise in proptest::collection::vec(-0.03f32..0.01, 441),
        ti in -10..=10i32, tj in -10..=10i32,
        (si, sj) in (-1..=1i32, -1..=1i32),
        diagonal in proptest::bool::ANY,
        along in 0.0f64..1.0, dz in -0.03f64..0.03,
        h in 0.05f64..0.8,
    ) {
        let rect = CellRect::new(Cell::new(-10, -10), 21, 21);
        let c = Cell::new(0, 0);
        let (ti, tj) = if diagonal { (ti, if tj < 0 { -ti } else { ti }) } else { (ti, tj) };
        let t = Cell::new(ti, tj);
        let (zs, zt) = (h, 0.0);
        let line_z = |p: Cell| {
            // Height of the segment where it passes closest to p's centre.
            let (dx, dy) = (ti as f64, tj as f64);
            let len2 = dx * dx + dy * dy;
            let u = if len2 > 0.0 { ((p.i as f64 * dx + p.j as f64 * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
            zs + (zt - zs) * u
        };
        // Every known cell sits near the line; x near the point `along` of it.
        let mut raster: Vec<f32> = rect
            .cells()
            .zip(known.iter().zip(&noise))
            .map(|(p, (&k, &n))| if k { (line_z(p) + n as f64) as f32 } else { f32::NAN })
            .collect();
        raster[rect.index(c).unwrap()] = 0.0;
        // x on the line at `along`, or a neighbour of that cell.
        let x = Cell::new(
            (ti as f64 * along).round() as i32 + si,
            (tj as f64 * along).round() as i32 + sj,
        );
        proptest::prop_assume!(x != c && x != t);
        let z = (line_z(x) + dz) as f32;
        let Some(kx) = rect.index(x) else {
            return Ok(());
        };
        raster[kx] = z;
        let with_x = ray_clear_in(&raster, rect, c, t, zs, zt, 0.1);
        if crosses_below(x.i, x.j, ti, tj, z as f64, zs, zt) {
            proptest::prop_assert!(!with_x, "crosses_below but the line is clear");
        }
        if !touches_sight_line(x.i, x.j, ti, tj, z as f64, zs, zt) {
            raster[kx] = f32::NAN;
            let without_x = ray_clear_in(&raster, rect, c, t, zs, zt, 0.1);
            proptest::prop_assert_eq!(with_x, without_x, "x does not touch the line but changes it");
        }
    }
}

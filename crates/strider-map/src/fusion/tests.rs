use super::*;
use crate::params::{ColorMode, MapParams};
use approx::assert_abs_diff_eq;
use strider_core::{Cell, CellRect, ColoredPoint, Point3, Rgb8};

fn cloud(origin: Point3, pts: &[(f32, f32, f32)]) -> PointCloud {
    let points = pts
        .iter()
        .map(|&(x, y, z)| ColoredPoint::new(x, y, z, [100, 150, 200]))
        .collect();
    PointCloud::new(0.0, 0, origin, points)
}

fn params() -> MapParams {
    MapParams {
        cell_size: 0.1,
        tile_size: 8,
        ..MapParams::default()
    }
}

/// A wall cell (5, 5) with top 0.5 m, seen from −x by a sensor at 0.5 m: every return on its
/// face lies below the top, lower from farther away. The ground cell (4, 5) in front is seen
/// at 0.
fn face_scan(distance: f32, face_z: f32) -> PointCloud {
    let x_face = 0.5f32;
    cloud(
        Point3::new((x_face - distance) as f64, 0.55, 0.5),
        &[
            (0.45, 0.55, 0.0),
            (0.45, 0.52, 0.0),
            (x_face + 0.001, 0.55, face_z),
        ],
    )
}

#[test]
fn face_bounds_raise_a_wall_top_and_lower_ones_do_not_pull_it_down() {
    let mut m = ElevationMap::new(params());
    let wall = Cell::new(5, 5);
    // First sight from far: the estimate starts low.
    m.fuse(&face_scan(2.0, 0.40));
    m.fuse(&face_scan(2.0, 0.40));
    assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.40, epsilon = 1e-6);
    // A nearer view sees the face higher up: the bound replaces the estimate.
    let s = m.fuse(&face_scan(0.8, 0.49));
    assert_eq!(s.face_bounds_raised, 1);
    assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.49, epsilon = 1e-6);
    // Far views again: their lower bounds are ignored, not averaged in.
    for _ in 0..5 {
        let s = m.fuse(&face_scan(2.0, 0.40));
        assert_eq!(s.face_bounds_ignored, 1);
    }
    assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.49, epsilon = 1e-6);
    // A bound within σ_z of the estimate is no news either.
    let s = m.fuse(&face_scan(0.8, 0.4905));
    assert_eq!((s.face_bounds_raised, s.face_bounds_ignored), (0, 1));
}

#[test]
fn a_face_return_on_the_edge_of_flat_ground_is_not_a_bound() {
    // Two ground cells at 0; a stray high return on the facing edge of the second is an
    // outlier (no step in the map), so it is gated, never lifting the ground.
    let mut m = ElevationMap::new(params());
    let o = Point3::new(-1.0, 0.55, 0.5);
    for _ in 0..3 {
        m.fuse(&cloud(o, &[(0.45, 0.55, 0.0), (0.55, 0.55, 0.0)]));
    }
    let s = m.fuse(&cloud(o, &[(0.45, 0.55, 0.0), (0.501, 0.55, 0.3)]));
    assert_eq!((s.face_bounds_raised, s.cells_gated), (0, 1));
    assert_abs_diff_eq!(m.elevation(Cell::new(5, 5)).unwrap(), 0.0, epsilon = 1e-6);
}

#[test]
fn kalman_matches_closed_form() {
    let p = MapParams {
        mahalanobis_gate: 1e9,
        ..params()
    };
    let mut m = ElevationMap::new(p.clone());
    // The cell (5, 5) centre at (0.55, 0.55); sensors at different heights give different
    // ranges, hence different σ_z².
    let zs = [0.10f32, 0.12, 0.09, 0.115, 0.101];
    let mut num = 0.0;
    let mut den = 0.0;
    for (k, &z) in zs.iter().enumerate() {
        let origin = Point3::new(0.55, 0.55, 0.5 + k as f64);
        let c = cloud(origin, &[(0.55, 0.55, z)]);
        let s = m.fuse(&c);
        assert_eq!(s.cells_updated, 1);
        let r2 = (origin.z - z as f64).powi(2);
        let var = p.sigma_d.powi(2) + (p.k_d * r2).powi(2);
        num += z as f64 / var;
        den += 1.0 / var;
    }
    let c = Cell::new(5, 5);
    assert_abs_diff_eq!(m.elevation(c).unwrap() as f64, num / den, epsilon = 1e-6);
    let rel = (m.variance(c).unwrap() as f64 - 1.0 / den).abs() / (1.0 / den);
    assert!(rel < 1e-4, "variance rel. error {rel}");
    assert_eq!(m.hits(c), 5);
}

#[test]
fn highest_point_per_cell_and_gate() {
    let mut m = ElevationMap::new(params());
    let o = Point3::new(0.0, 0.0, 1.0);
    let s = m.fuse(&cloud(
        o,
        &[(0.25, 0.25, 0.1), (0.22, 0.28, 0.3), (0.27, 0.21, 0.2)],
    ));
    assert_eq!(s.fused_points, 3);
    assert_eq!(s.cells_updated, 1);
    assert_eq!(m.elevation(Cell::new(2, 2)), Some(0.3));
    // A far outlier is gated: elevation unchanged, variance inflated.
    let v0 = m.variance(Cell::new(2, 2)).unwrap();
    let s = m.fuse(&cloud(o, &[(0.25, 0.25, 0.8)]));
    assert_eq!(s.cells_gated, 1);
    assert_eq!(m.elevation(Cell::new(2, 2)), Some(0.3));
    assert_abs_diff_eq!(
        m.variance(Cell::new(2, 2)).unwrap(),
        v0 + 1e-5,
        epsilon = 1e-9
    );
}

/// A wall (x ≥ 1.0, 0.5 m) seen from (0.05, 0.05, 0.5): its face returns straddle the edge
/// x = 1.0. Those pushed into cell (9, 0) near the top of the face are not below the wall's
/// scan maximum, so only ray carving can tell they are not the floor of (9, 0): beams to the
/// lower face returns cross (9, 0) close to the floor.
fn wall_scan(o: Point3) -> PointCloud {
    let mut pts = vec![(0.95, 0.05, 0.0), (0.93, 0.07, 0.001)];
    for k in 1..=9 {
        let z = 0.05 * k as f32;
        pts.push((1.004, 0.05, z));
        pts.push((0.997, 0.05, z + 0.002));
    }
    cloud(o, &pts)
}

#[test]
fn ray_carving_removes_face_returns_in_front_of_a_wall() {
    let mut m = ElevationMap::new(params());
    let s = m.fuse(&wall_scan(Point3::new(0.05, 0.05, 0.5)));
    assert!(s.carved_points > 0, "{s:?}");
    let floor = m.elevation(Cell::new(9, 0)).unwrap();
    assert!(floor.abs() < 0.01, "floor in front of the wall at {floor}");
    assert!(m.elevation(Cell::new(10, 0)).unwrap() > 0.4);
}

#[test]
fn ray_carving_lowers_a_contradicted_estimate() {
    let mut m = ElevationMap::new(params());
    // A wrong estimate from an earlier scan, confident.
    m.set_cell(Cell::new(9, 0), 0.4, 1e-6, Rgb8::new(0, 0, 0));
    let s = m.fuse(&wall_scan(Point3::new(0.05, 0.05, 0.5)));
    assert!(s.cells_carved >= 1, "{s:?}");
    let z = m.elevation(Cell::new(9, 0)).unwrap();
    assert!(z < 0.06, "carved to the lowest beam crossing, got {z}");
    // Carving never touches a cell no beam crossed below its top.
    assert!(m.elevation(Cell::new(10, 0)).unwrap() > 0.4);
}

#[test]
fn non_finite_points_are_skipped_and_counted() {
    let mut m = ElevationMap::new(params());
    let o = Point3::new(0.0, 0.0, 1.0);
    let s = m.fuse(&cloud(
        o,
        &[
            (f32::NAN, 0.0, 0.0),
            (0.0, f32::INFINITY, 0.0),
            (0.0, 0.0, f32::NEG_INFINITY),
            (0.05, 0.05, 0.0),
            (1e30, 0.0, 0.0),
        ],
    ));
    assert_eq!(s.skipped_non_finite, 3);
    assert_eq!(s.skipped_out_of_range, 1);
    assert_eq!(s.fused_points, 1);
    let s = m.fuse(&cloud(Point3::new(f64::NAN, 0.0, 0.0), &[(0.0, 0.0, 0.0)]));
    assert_eq!(s.skipped_non_finite, 1);
    let s = m.fuse(&cloud(o, &[]));
    assert_eq!(s, FuseStats::default());
    assert_eq!(m.observed_count(), 1);
}

#[test]
fn mixed_cell_rule_ignores_wall_face_returns() {
    // A wall occupies cells i ≥ 10 (x ≥ 1.0) with top at 0.5 m; the floor (z = 0) lies at
    // x < 1.0. The sensor at x = 0 sees the floor, the wall's face at x = 1.0 (noisy in x)
    // and the wall top.
    let mut m = ElevationMap::new(params());
    let o = Point3::new(0.0, 0.55, 0.8);
    let mut pts = Vec::new();
    let mut rng = 12345u64;
    let mut noise = || {
        rng = rng
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((rng >> 33) as f32 / (1u64 << 31) as f32 - 0.5) * 0.004 // ±2 mm
    };
    for k in 0..10 {
        let y = 0.51 + 0.008 * k as f32;
        for a in 0..10 {
            pts.push((0.9 + 0.01 * a as f32 + 0.005, y, noise())); // floor cell 9
            pts.push((1.0 + noise(), y, 0.05 * a as f32)); // face at x = 1.0
            pts.push((1.005 + 0.01 * a as f32, y, 0.5 + noise())); // wall top cell 10
        }
    }
    let s = m.fuse(&cloud(o, &pts));
    assert!(s.face_points > 0);
    let floor = m.elevation(Cell::new(9, 5)).unwrap();
    assert!(floor.abs() < 0.01, "floor cell corrupted: {floor}");
    let top = m.elevation(Cell::new(10, 5)).unwrap();
    assert!((top - 0.5).abs() < 0.01, "wall top {top}");
}

/// A scan of a floor, a wall and its face with coarse heights (so that equally high returns
/// with different colours share cells), a few unusable returns, from `origin`.
fn tied_scan(origin: Point3, seed: u64, n: usize) -> PointCloud {
    let mut rng = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u64 << 24) as f32
    };
    let points = (0..n)
        .map(|k| {
            let (x, y) = (next() * 3.0 - 1.0, next() * 3.0 - 1.0);
            let z = match k % 7 {
                // Face returns on the wall's edge at x = 1.5, noisy in x.
                0 => {
                    let x = 1.5 + (next() - 0.5) * 0.01;
                    let z = (next() * 11.0).floor() * 0.05;
                    return ColoredPoint::new(x, y, z, [k as u8, 7, 9]);
                }
                _ if x >= 1.5 => 0.5,
                _ => 0.0,
            } + (next() * 3.0).floor() * 0.002;
            let bad = k % 997 == 0;
            let rgb = [(k % 251) as u8, (k / 251 % 251) as u8, 40];
            ColoredPoint::new(if bad { f32::NAN } else { x }, y, z, rgb)
        })
        .collect();
    PointCloud::new(0.0, 0, origin, points)
}

#[test]
fn fusion_does_not_depend_on_the_number_of_chunks() {
    let scans: Vec<PointCloud> = (0..4)
        .map(|s| tied_scan(Point3::new(0.1 * s as f64, 0.2, 0.6), s, 3000))
        .collect();
    let run = |chunks: usize| {
        let mut m = ElevationMap::new(params());
        let stats: Vec<FuseStats> = scans.iter().map(|c| m.fuse_in_chunks(c, chunks)).collect();
        m.update_passability();
        (m, stats)
    };
    let (one, one_stats) = run(1);
    let rect = one.known_bounds().expect("cells observed");
    assert!(
        one_stats
            .iter()
            .any(|s| s.face_points > 0 && s.carved_points > 0)
    );
    assert!(one_stats.iter().all(|s| s.skipped_non_finite > 0));
    for chunks in [2, 3, 7] {
        let (m, stats) = run(chunks);
        assert_eq!(stats, one_stats, "{chunks} chunks");
        assert_eq!(m.known_bounds(), Some(rect));
        for c in rect.cells() {
            let (a, b) = (m.elevation(c), one.elevation(c));
            assert_eq!(
                a.map(f32::to_bits),
                b.map(f32::to_bits),
                "{chunks} chunks, {c:?}"
            );
            let (a, b) = (m.variance(c), one.variance(c));
            assert_eq!(
                a.map(f32::to_bits),
                b.map(f32::to_bits),
                "{chunks} chunks, {c:?}"
            );
            assert_eq!(m.color(c), one.color(c), "{chunks} chunks, {c:?}");
            assert_eq!(m.hits(c), one.hits(c), "{chunks} chunks, {c:?}");
            assert_eq!(
                m.passability(c),
                one.passability(c),
                "{chunks} chunks, {c:?}"
            );
        }
    }
}

#[test]
fn running_mean_and_first_seen_colour() {
    let o = Point3::new(0.0, 0.0, 1.0);
    let mk =
        |rgb: [u8; 3]| PointCloud::new(0.0, 0, o, vec![ColoredPoint::new(0.05, 0.05, 0.0, rgb)]);
    let mut m = ElevationMap::new(params());
    m.fuse(&mk([100, 0, 0]));
    m.fuse(&mk([200, 50, 0]));
    assert_eq!(
        m.color(Cell::new(0, 0)),
        Some(strider_core::Rgb8::new(150, 25, 0))
    );
    let mut m = ElevationMap::new(MapParams {
        color_mode: ColorMode::FirstSeen,
        ..params()
    });
    m.fuse(&mk([100, 0, 0]));
    m.fuse(&mk([200, 50, 0]));
    assert_eq!(
        m.color(Cell::new(0, 0)),
        Some(strider_core::Rgb8::new(100, 0, 0))
    );
}

#[test]
fn map_grows_into_negative_coordinates() {
    let mut m = ElevationMap::new(params());
    let o = Point3::new(0.0, 0.0, 1.0);
    m.fuse(&cloud(o, &[(-3.05, -2.05, 0.1), (2.05, 1.05, 0.2)]));
    assert_eq!(m.elevation_at(-3.05, -2.05), Some(0.1));
    assert_eq!(m.elevation(Cell::new(20, 10)), Some(0.2));
    assert_eq!(
        m.known_bounds(),
        Some(CellRect::new(Cell::new(-31, -21), 52, 32))
    );
    assert_eq!(m.elevation_layer().tile_count(), 2);
}

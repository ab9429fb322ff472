//! Ray casting against cell columns.
mod common;

use common::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_core::{Cell, Point3};
use strider_sim::{Face, Heightfield};

#[test]
fn flat_ground_hit_is_analytic() {
    let w = flat_world(100, 100, 0.05);
    let hf = Heightfield::from_world(&w).unwrap();
    let o = Point3::new(2.512, 2.487, 0.3);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..500 {
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let e: f64 = rng.random_range(-1.4..-0.1);
        let u = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
        let t = 0.3 / -u[2];
        let hit = hf.cast(o, u, 10.0);
        let expect = Point3::new(o.x + t * u[0], o.y + t * u[1], 0.0);
        let inside = expect.x >= 0.0 && expect.x < 5.0 && expect.y >= 0.0 && expect.y < 5.0;
        match hit {
            Some(h) => {
                assert!(inside);
                assert_eq!(h.face, Face::Top);
                assert!((h.range - t).abs() < 1e-9, "{} vs {t}", h.range);
                assert!(h.point.dist(expect) < 1e-9);
                assert_eq!(h.cell, Cell::containing(expect.x, expect.y, 0.05).unwrap());
            }
            None => assert!(!inside, "missed {expect:?}"),
        }
    }
    // Upward and level rays over flat ground never hit.
    assert!(hf.cast(o, [1.0, 0.2, 0.0], 100.0).is_none());
    assert!(hf.cast(o, [1.0, 0.2, 0.3], 100.0).is_none());
    // Straight down.
    let h = hf.cast(o, [0.0, 0.0, -1.0], 1.0).unwrap();
    assert!((h.range - 0.3).abs() < 1e-12);
    // Out of range.
    assert!(hf.cast(o, [1.0, 0.0, -0.1], 1.0).is_none());
}

#[test]
fn side_faces_are_hit_on_the_boundary() {
    let mut w = flat_world(100, 40, 0.05);
    // A wall 0.5 m high occupying columns 60..62 (x in [3.0, 3.1)).
    fill(&mut w, 60, 62, 0, 40, 0.5, WALL);
    let hf = Heightfield::from_world(&w).unwrap();
    let o = Point3::new(1.0, 1.0, 0.3);
    for dy in [-0.3, -0.1, 0.0, 0.05, 0.2] {
        for dz in [0.0, 0.02, -0.01] {
            let hit = hf.cast(o, [1.0, dy, dz], 10.0).unwrap();
            let t = (3.0 - o.x) / 1.0;
            let z = o.z + dz * t;
            if z >= 0.5 || z <= 0.0 {
                continue;
            }
            assert_eq!(hit.face, Face::Side);
            assert_eq!(hit.point.x, 3.0, "exactly on the boundary");
            assert!((hit.point.y - (o.y + dy * t)).abs() < 1e-9);
            assert!((hit.point.z - z).abs() < 1e-9);
            assert_eq!(hit.cell.i, 60);
        }
    }
    // Over the wall (rising ray) nothing.
    assert!(hf.cast(o, [1.0, 0.0, 0.2], 10.0).is_none());
    // From the other side, the far face.
    let o2 = Point3::new(4.5, 1.0, 0.3);
    let hit = hf.cast(o2, [-1.0, 0.1, 0.0], 10.0).unwrap();
    assert_eq!(hit.point.x, 3.1);
    assert_eq!(hit.cell.i, 61);
    // Along y, faces at j boundaries.
    let mut w = flat_world(40, 100, 0.05);
    fill(&mut w, 0, 40, 70, 71, 1.0, WALL);
    let hf = Heightfield::from_world(&w).unwrap();
    let hit = hf
        .cast(Point3::new(1.0, 1.0, 0.3), [0.2, 1.0, 0.0], 10.0)
        .unwrap();
    assert_eq!(hit.point.y, 3.5);
    assert_eq!(hit.face, Face::Side);
}

#[test]
fn wall_occludes_everything_behind_it() {
    let mut w = flat_world(120, 60, 0.05);
    fill(&mut w, 60, 62, 0, 60, 0.6, WALL);
    let hf = Heightfield::from_world(&w).unwrap();
    let o = Point3::new(1.0, 1.5, 0.3);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut hits_wall = 0;
    for _ in 0..2000 {
        let a: f64 = rng.random_range(-0.6..0.6);
        let e: f64 = rng.random_range(-0.3..0.1);
        let u = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
        if let Some(h) = hf.cast(o, u, 20.0) {
            assert!(
                h.point.x <= 3.1 + 1e-9,
                "point behind the wall: {:?}",
                h.point
            );
            hits_wall += (h.cell.i >= 60) as usize;
        }
    }
    assert!(hits_wall > 100);
    assert!(!hf.visible(o, Point3::new(4.0, 1.5, 0.0)));
    assert!(hf.visible(o, Point3::new(2.0, 1.5, 0.0)));
    // The top of the wall is visible from above, its far base is not.
    assert!(hf.visible(Point3::new(1.0, 1.5, 2.0), Point3::new(3.025, 1.5, 0.6)));
    assert!(!hf.visible(Point3::new(1.0, 1.5, 2.0), Point3::new(3.2, 1.5, 0.0)));
}

#[test]
fn outside_the_world_there_is_no_surface() {
    let w = flat_world(20, 20, 0.1);
    let hf = Heightfield::from_world(&w).unwrap();
    // From outside, a ray entering the world hits it.
    let h = hf
        .cast(Point3::new(-1.0, 1.0, 0.5), [1.0, 0.0, -0.25], 10.0)
        .unwrap();
    assert!((h.point.x - 1.0).abs() < 1e-9 && h.point.z == 0.0);
    // A ray landing outside returns nothing.
    assert!(
        hf.cast(Point3::new(1.0, 1.0, 0.5), [1.0, 0.0, -0.1], 100.0)
            .is_none()
    );
    // Entering from outside below the world's top: side face at the border.
    let mut w = flat_world(20, 20, 0.1);
    fill(&mut w, 0, 20, 0, 20, 1.0, GROUND);
    let hf = Heightfield::from_world(&w).unwrap();
    let h = hf
        .cast(Point3::new(-1.0, 1.05, 0.5), [1.0, 0.0, 0.0], 10.0)
        .unwrap();
    assert_eq!(h.face, Face::Side);
    assert_eq!(h.point.x, 0.0);
    assert_eq!(h.cell, Cell::new(0, 10));
}

/// Brute-force reference: march in tiny steps.
fn march(w: &strider_scenario::World, o: Point3, u: [f64; 3], range: f64) -> Option<f64> {
    let step = 1e-4;
    let mut t = 0.0;
    while t <= range {
        let p = Point3::new(o.x + u[0] * t, o.y + u[1] * t, o.z + u[2] * t);
        if let Some(k) = w.index_at(p.xy())
            && p.z < w.elevation[k] as f64
        {
            return Some(t);
        }
        t += step;
    }
    None
}

#[test]
fn matches_brute_force_on_rough_terrain() {
    let mut w = flat_world(30, 30, 0.1);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for z in &mut w.elevation {
        *z = rng.random_range(0.0..0.4);
    }
    let hf = Heightfield::from_world(&w).unwrap();
    for _ in 0..300 {
        let o = Point3::new(
            rng.random_range(0.2..2.8),
            rng.random_range(0.2..2.8),
            rng.random_range(0.45..0.9),
        );
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let e: f64 = rng.random_range(-1.2..0.1);
        let u = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
        let got = hf.cast(o, u, 3.0).map(|h| h.range);
        let want = march(&w, o, u, 3.0);
        match (got, want) {
            (Some(g), Some(m)) => assert!((g - m).abs() < 2e-4, "{g} vs {m}"),
            (None, None) => {}
            (g, m) => {
                // Only grazing cases at the range limit may disagree.
                let t = g.or(m).unwrap();
                assert!(t > 3.0 - 1e-3, "{g:?} vs {m:?}");
            }
        }
    }
}

/// Mostly flat ground with sparse tall spikes and a few holes, on a grid many blocks wide: rays
/// cross many blocks above their maxima (the skipping path) and must meet the same face of the
/// same cell at the same range as when stepping through every cell. (Brute-force marching is
/// no reference here: low rays over flat ground graze cell edges finer than its step.)
#[test]
fn block_skipping_equals_cell_by_cell_traversal() {
    let mut w = flat_world(83, 77, 0.05);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for z in &mut w.elevation {
        let u: f64 = rng.random_range(0.0..1.0);
        *z = if u < 0.01 {
            rng.random_range(0.1..0.6)
        } else if u < 0.015 {
            f32::NAN
        } else {
            rng.random_range(0.0..0.02)
        };
    }
    let hf = Heightfield::from_world(&w).unwrap();
    let reference = hf.clone().without_block_skipping();
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..20_000 {
        let o = Point3::new(
            rng.random_range(-0.5..4.6),
            rng.random_range(-0.5..4.3),
            rng.random_range(0.05..0.5),
        );
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let e: f64 = rng.random_range(-0.5..0.2);
        let u = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
        match (hf.cast(o, u, 3.0), reference.cast(o, u, 3.0)) {
            (Some(g), Some(r)) => {
                hits += 1;
                assert!((g.range - r.range).abs() < 1e-9, "{g:?} vs {r:?}");
                assert_eq!((g.cell, g.face), (r.cell, r.face));
            }
            (None, None) => misses += 1,
            (g, r) => panic!("{g:?} vs {r:?}: o {o:?} u {u:?}"),
        }
    }
    assert!(hits > 5000 && misses > 1000, "{hits} hits, {misses} misses");
}

//! The per-cell Kalman update of fusion (decision 2), with the face-bound rule and the
//! lowering of estimates that a beam contradicted (ray carving).

use super::stats::FuseStats;
use crate::map::ElevationMap;
use crate::params::{ColorMode, MapParams};
use crate::rect;
use crate::tiles::TileKey;
use strider_core::{Cell, CellRect};

/// The fusion parameters of the update.
struct KalmanRule {
    /// The Mahalanobis gate.
    gate: f64,
    /// Variance added to a cell whose measurement the gate rejects.
    noise: f32,
    /// Keep the first colour seen instead of the running mean.
    first_seen: bool,
}

/// One cell's measurement of this scan.
struct Measurement {
    z: f32,
    /// σ_z².
    var: f32,
    rgb: [f32; 3],
    /// The height the estimate must exceed for the measurement to count as a face bound.
    bound_floor: f32,
}

/// What the update did to a cell.
enum Update {
    /// First measurement: the cell became observed.
    Initialised,
    /// Kalman-fused.
    Fused,
    /// A face bound raised the estimate.
    BoundRaised,
    /// A face bound at or below the estimate: no news.
    BoundIgnored,
    /// Rejected by the gate (variance inflated).
    Gated,
}

/// The layers of one tile that the update writes.
struct TileCells<'a> {
    el: &'a mut [f32],
    va: &'a mut [f32],
    co: &'a mut [[f32; 3]],
    hits: &'a mut [u32],
    ob: &'a mut [bool],
}

impl TileCells<'_> {
    /// Lowers the estimate of cell `t` to the carving bound `cz` when a beam crossed its
    /// column more than the gate below it: the top is at most there. Makes it uncertain so
    /// the next returns decide; returns whether it did.
    #[inline]
    fn carve(&mut self, t: usize, cz: f32, gate: f64) -> bool {
        let (el, va) = (&mut self.el[t], &mut self.va[t]);
        if !(cz < *el && self.ob[t] && (*el - cz) as f64 > gate * (*va as f64).sqrt()) {
            return false;
        }
        let excess = (*el - cz) as f64 / gate;
        *el = cz;
        *va = va.max((excess * excess) as f32);
        true
    }

    /// Fuses measurement `m` into cell `t`.
    #[inline]
    fn fuse(&mut self, t: usize, m: &Measurement, rule: &KalmanRule) -> Update {
        let (z, r) = (m.z, m.var);
        if !self.ob[t] {
            self.ob[t] = true;
            self.el[t] = z;
            self.va[t] = r;
            self.co[t] = m.rgb;
            self.hits[t] = 1;
            return Update::Initialised;
        }
        let (h, p) = (self.el[t] as f64, self.va[t] as f64);
        let (zf, rf) = (z as f64, r as f64);
        let sum = p + rf;
        // A face bound counts only where the map already holds a step up from the facing
        // neighbour: a stray face return spilled into a ground cell is then gated like any
        // outlier instead of lifting the ground.
        if h - m.bound_floor as f64 > rule.gate * p.sqrt() {
            // A lower bound of the top: news only when more than σ_z above it.
            if zf - h > rf.sqrt() {
                self.el[t] = z;
                self.va[t] = r;
                return Update::BoundRaised;
            }
            return Update::BoundIgnored;
        }
        if (zf - h).abs() > rule.gate * sum.sqrt() {
            self.va[t] += rule.noise;
            return Update::Gated;
        }
        self.el[t] = ((rf * h + p * zf) / sum) as f32;
        self.va[t] = (p * rf / sum) as f32;
        self.hits[t] = self.hits[t].saturating_add(1);
        if !rule.first_seen {
            let inv = 1.0 / self.hits[t] as f32;
            for ch in 0..3 {
                self.co[t][ch] += (m.rgb[ch] - self.co[t][ch]) * inv;
            }
        }
        Update::Fused
    }
}

impl KalmanRule {
    fn new(params: &MapParams) -> Self {
        Self {
            gate: params.mahalanobis_gate,
            noise: params.multi_height_noise as f32,
            first_seen: params.color_mode == ColorMode::FirstSeen,
        }
    }
}

impl ElevationMap {
    /// Kalman update of every cell with a measurement in the scratch rasters over `rect`, tile
    /// by tile (one lookup per tile and layer); marks the changed cells for the passability
    /// update.
    pub(super) fn apply_measurements(&mut self, rect: CellRect, stats: &mut FuseStats) {
        let ElevationMap {
            params,
            elevation,
            variance,
            color,
            hits,
            observed,
            passability,
            admissible,
            known_bounds,
            observed_count,
            dirty,
            changes,
            scratch: s,
            ..
        } = self;
        let rule = KalmanRule::new(params);
        let ts = elevation.tile_size() as i32;
        let w = rect.width as usize;
        let rk = |c: Cell| (c.j - rect.min.j) as usize * w + (c.i - rect.min.i) as usize;
        // The cells whose elevation changed, and those that became observed.
        let (mut changed, mut newly_known) = (None, None);
        changes.begin();
        let (ri1, rj1) = rect::max_corner(rect);
        for tj in rect.min.j.div_euclid(ts)..=rj1.div_euclid(ts) {
            for ti in rect.min.i.div_euclid(ts)..=ri1.div_euclid(ts) {
                let key = TileKey { ti, tj };
                let Some(ov) = rect::intersection(rect, elevation.tile_rect(key)) else {
                    continue;
                };
                // Row slices of the scratch: a tile that a few beams cross is mostly cells that
                // nothing reached, and those are skipped with two comparisons each.
                let (ow, rows) = (ov.width as usize, ov.height as usize);
                let row_start = |y: usize| rk(Cell::new(ov.min.i, ov.min.j + y as i32));
                let untouched = |k: usize| {
                    s.kept.z[k] == f32::NEG_INFINITY && s.columns.carve_z[k] == f32::INFINITY
                };
                if (0..rows).all(|y| (row_start(y)..row_start(y) + ow).all(untouched)) {
                    continue;
                }
                let mut tile = TileCells {
                    el: elevation.tile_or_insert(key),
                    va: variance.tile_or_insert(key),
                    co: color.tile_or_insert(key),
                    hits: hits.tile_or_insert(key),
                    ob: observed.tile_or_insert(key),
                };
                passability.tile_or_insert(key);
                admissible.tile_or_insert(key);
                for (y, x) in (0..rows).flat_map(|y| (0..ow).map(move |x| (y, x))) {
                    let k = row_start(y) + x;
                    if untouched(k) {
                        continue;
                    }
                    let c = Cell::new(ov.min.i + x as i32, ov.min.j + y as i32);
                    let t = ((c.j - tj * ts) * ts + (c.i - ti * ts)) as usize;
                    if tile.carve(t, s.columns.carve_z[k], rule.gate) {
                        stats.cells_carved += 1;
                        changed = Some(rect::include(changed, c));
                        changes.mark(c);
                    }
                    let z = s.kept.z[k];
                    if z == f32::NEG_INFINITY {
                        continue;
                    }
                    stats.cells_updated += 1;
                    let m = Measurement {
                        z,
                        var: s.kept.var[k],
                        rgb: s.kept.rgb[k].map(f32::from),
                        bound_floor: s.bound_floor[k],
                    };
                    match tile.fuse(t, &m, &rule) {
                        Update::Initialised => {
                            *observed_count += 1;
                            newly_known = Some(rect::include(newly_known, c));
                        }
                        Update::Fused => {}
                        Update::BoundRaised => stats.face_bounds_raised += 1,
                        Update::BoundIgnored => {
                            stats.face_bounds_ignored += 1;
                            continue;
                        }
                        Update::Gated => {
                            stats.cells_gated += 1;
                            continue;
                        }
                    }
                    changed = Some(rect::include(changed, c));
                    changes.mark(c);
                }
            }
        }
        if let Some(r) = changed {
            *dirty = Some(dirty.map_or(r, |d| rect::union(d, r)));
        }
        if let Some(r) = newly_known {
            *known_bounds = Some(known_bounds.map_or(r, |b| rect::union(b, r)));
        }
    }
}

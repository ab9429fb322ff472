//! The colored 2.5D elevation map M_2.5D (Prágr22 §4.2): per-cell layers on one tiled lattice.
//!
//! Layers (decision 1, each a separate [`TiledLayer`]): elevation mean and variance (Kalman
//! state, decision 2), colour (running mean or first seen, decision 3), observed flag, number of
//! fused measurements, passability π (Eq. 7–9) and configuration-space admissibility (decision 4).
//! This file holds the storage and its accessors only: scans are fused into it by the `fusion`
//! module, and the `passability` module keeps π and admissibility up to date.

use crate::changes::ChangeLog;
use crate::fusion::scratch::FusionScratch;
use crate::params::{MapParams, ParamError};
use crate::passability::rule::Passability;
use crate::rect;
use crate::tiles::TiledLayer;
use strider_core::{Cell, CellRect, Point2, Rgb8};

/// The colored elevation map.
#[derive(Clone, Debug)]
pub struct ElevationMap {
    pub(crate) params: MapParams,
    /// Elevation mean h, metres (valid where `observed`).
    pub(crate) elevation: TiledLayer<f32>,
    /// Elevation variance σ_h², m².
    pub(crate) variance: TiledLayer<f32>,
    /// Colour as mean sRGB channel values in [0, 255].
    pub(crate) color: TiledLayer<[f32; 3]>,
    /// Number of measurements fused into the cell.
    pub(crate) hits: TiledLayer<u32>,
    /// True once the cell has an elevation.
    pub(crate) observed: TiledLayer<bool>,
    /// π(ν) (Eq. 9).
    pub(crate) passability: TiledLayer<Passability>,
    /// Configuration-space admissibility (decision 4).
    pub(crate) admissible: TiledLayer<bool>,
    /// Bounding rectangle of the observed cells.
    pub(crate) known_bounds: Option<CellRect>,
    /// Number of observed cells.
    pub(crate) observed_count: usize,
    /// Cells whose elevation changed since the last passability update (bounding rectangle).
    pub(crate) dirty: Option<CellRect>,
    /// Revision stamps of the blocks whose cells changed, for incremental consumers.
    pub(crate) changes: ChangeLog,
    /// The revision of `changes` that passability and admissibility are up to date with.
    pub(crate) passability_revision: u64,
    /// Where the admissibility layer was rewritten, one revision per passability update: its
    /// consumers follow it instead of re-reading the whole layer.
    pub(crate) admissible_changes: ChangeLog,
    /// Number of scans fused.
    pub(crate) scans: u64,
    pub(crate) scratch: FusionScratch,
}

impl ElevationMap {
    /// An empty map, after checking `params` ([`MapParams::validate`]): the constructor for
    /// parameters from outside (files, command lines).
    pub fn try_new(params: MapParams) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self::new(params))
    }

    /// An empty map. `params` are trusted: they come from a scenario or configuration that
    /// validated them where they entered, or from code; see [`ElevationMap::try_new`].
    pub fn new(params: MapParams) -> Self {
        let ts = params.tile_size;
        Self {
            params,
            elevation: TiledLayer::new(ts),
            variance: TiledLayer::new(ts),
            color: TiledLayer::new(ts),
            hits: TiledLayer::new(ts),
            observed: TiledLayer::new(ts),
            passability: TiledLayer::new(ts),
            admissible: TiledLayer::new(ts),
            known_bounds: None,
            observed_count: 0,
            dirty: None,
            changes: ChangeLog::default(),
            passability_revision: 0,
            admissible_changes: ChangeLog::default(),
            scans: 0,
            scratch: FusionScratch::default(),
        }
    }

    /// The map's parameters.
    pub fn params(&self) -> &MapParams {
        &self.params
    }

    /// Sets the stride of the lattice on which Eq. 11 is evaluated (a performance knob; the
    /// geometry parameters are fixed at construction).
    pub fn set_info_gain_stride(&mut self, stride: u32) {
        self.params.info_gain_stride = stride.max(1);
    }

    /// Cell size d_ν, metres.
    pub fn cell_size(&self) -> f64 {
        self.params.cell_size
    }

    /// The cell containing world point `(x, y)`.
    pub fn cell_at(&self, x: f64, y: f64) -> Option<Cell> {
        Cell::containing(x, y, self.params.cell_size)
    }

    /// The centre of `c` in world coordinates.
    pub fn center(&self, c: Cell) -> Point2 {
        c.center(self.params.cell_size)
    }

    /// True when the cell has been observed (has an elevation).
    #[inline]
    pub fn is_observed(&self, c: Cell) -> bool {
        self.observed.value(c)
    }

    /// Elevation mean of the cell, `None` when unobserved.
    #[inline]
    pub fn elevation(&self, c: Cell) -> Option<f32> {
        self.is_observed(c).then(|| self.elevation.value(c))
    }

    /// Elevation at world point `(x, y)`, `None` when unobserved.
    pub fn elevation_at(&self, x: f64, y: f64) -> Option<f32> {
        self.cell_at(x, y).and_then(|c| self.elevation(c))
    }

    /// Elevation variance of the cell, `None` when unobserved.
    pub fn variance(&self, c: Cell) -> Option<f32> {
        self.is_observed(c).then(|| self.variance.value(c))
    }

    /// Colour of the cell, `None` when unobserved.
    pub fn color(&self, c: Cell) -> Option<Rgb8> {
        self.is_observed(c).then(|| {
            Rgb8(
                self.color
                    .value(c)
                    .map(|v| v.round().clamp(0.0, 255.0) as u8),
            )
        })
    }

    /// Colour at world point `(x, y)`.
    pub fn color_at(&self, x: f64, y: f64) -> Option<Rgb8> {
        self.cell_at(x, y).and_then(|c| self.color(c))
    }

    /// Number of measurements fused into the cell.
    pub fn hits(&self, c: Cell) -> u32 {
        self.hits.value(c)
    }

    /// Passability π of the cell (as of the last [`ElevationMap::update_passability`]).
    #[inline]
    pub fn passability(&self, c: Cell) -> Passability {
        self.passability.value(c)
    }

    /// Passability at world point `(x, y)`.
    pub fn passability_at(&self, x: f64, y: f64) -> Passability {
        self.cell_at(x, y)
            .map_or(Passability::Unknown, |c| self.passability(c))
    }

    /// True when the robot's centre may occupy the cell (passable, no impassable cell within
    /// r_robot; decision 4).
    #[inline]
    pub fn is_admissible(&self, c: Cell) -> bool {
        self.admissible.value(c)
    }

    /// Admissibility at world point `(x, y)`.
    pub fn is_admissible_at(&self, x: f64, y: f64) -> bool {
        self.cell_at(x, y).is_some_and(|c| self.is_admissible(c))
    }

    /// Bounding rectangle of the observed cells, `None` for an empty map.
    pub fn known_bounds(&self) -> Option<CellRect> {
        self.known_bounds
    }

    /// Number of observed cells.
    pub fn observed_count(&self) -> usize {
        self.observed_count
    }

    /// Number of scans fused so far.
    pub fn scan_count(&self) -> u64 {
        self.scans
    }

    /// True when fused elevations are waiting for [`ElevationMap::update_passability`].
    pub fn has_dirty_cells(&self) -> bool {
        self.dirty.is_some()
    }

    /// Where cells changed (elevation, colour or observed flag), by revision: lets derived
    /// layers be refreshed in the changed region only.
    pub fn changes(&self) -> &ChangeLog {
        &self.changes
    }

    /// Where the admissibility layer ([`ElevationMap::admissible_layer`]) was rewritten, by
    /// revision (a superset of the cells whose value changed).
    pub fn admissible_changes(&self) -> &ChangeLog {
        &self.admissible_changes
    }

    /// The elevation-mean layer (valid where [`ElevationMap::observed_layer`] is true).
    pub fn elevation_layer(&self) -> &TiledLayer<f32> {
        &self.elevation
    }
    /// The elevation-variance layer.
    pub fn variance_layer(&self) -> &TiledLayer<f32> {
        &self.variance
    }
    /// The observed-flag layer.
    pub fn observed_layer(&self) -> &TiledLayer<bool> {
        &self.observed
    }
    /// The passability layer.
    pub fn passability_layer(&self) -> &TiledLayer<Passability> {
        &self.passability
    }
    /// The admissibility layer.
    pub fn admissible_layer(&self) -> &TiledLayer<bool> {
        &self.admissible
    }

    /// Writes a cell directly (ground truth, tests, replay): elevation, variance and colour, as
    /// if it had been measured once. Marks the cell for the next passability update.
    pub fn set_cell(&mut self, c: Cell, elevation: f32, variance: f32, color: Rgb8) {
        self.elevation.set(c, elevation);
        self.variance.set(c, variance);
        self.color.set(c, color.0.map(f32::from));
        let h = self.hits.get_or_insert(c);
        *h = (*h).max(1);
        self.passability.get_or_insert(c);
        self.admissible.get_or_insert(c);
        let o = self.observed.get_or_insert(c);
        if !*o {
            *o = true;
            self.observed_count += 1;
        }
        self.known_bounds = Some(rect::include(self.known_bounds, c));
        self.dirty = Some(rect::include(self.dirty, c));
        self.changes.begin();
        self.changes.mark(c);
    }

    /// Elevation over `rect` as a dense row-major raster, NaN where unobserved.
    pub fn elevation_raster(&self, rect: CellRect) -> Vec<f32> {
        self.observed_values(&self.elevation, rect)
    }

    /// Elevation variance over `rect`, NaN where unobserved.
    pub fn variance_raster(&self, rect: CellRect) -> Vec<f32> {
        self.observed_values(&self.variance, rect)
    }

    /// `layer` over `rect`, NaN where unobserved.
    fn observed_values(&self, layer: &TiledLayer<f32>, rect: CellRect) -> Vec<f32> {
        let mut e = Vec::new();
        let mut o = Vec::new();
        layer.read_rect(rect, &mut e);
        self.observed.read_rect(rect, &mut o);
        e.iter()
            .zip(&o)
            .map(|(&z, &k)| if k { z } else { f32::NAN })
            .collect()
    }

    /// Observed flags over `rect`.
    pub fn observed_raster(&self, rect: CellRect) -> Vec<bool> {
        let mut o = Vec::new();
        self.observed.read_rect(rect, &mut o);
        o
    }

    /// Colours over `rect`, `None` where unobserved.
    pub fn color_raster(&self, rect: CellRect) -> Vec<Option<Rgb8>> {
        let mut c = Vec::new();
        let mut o = Vec::new();
        self.color.read_rect(rect, &mut c);
        self.observed.read_rect(rect, &mut o);
        c.iter()
            .zip(&o)
            .map(|(v, &k)| k.then(|| Rgb8(v.map(|x| x.round().clamp(0.0, 255.0) as u8))))
            .collect()
    }

    /// Passability over `rect`.
    pub fn passability_raster(&self, rect: CellRect) -> Vec<Passability> {
        let mut p = Vec::new();
        self.passability.read_rect(rect, &mut p);
        p
    }

    /// Admissibility over `rect`.
    pub fn admissible_raster(&self, rect: CellRect) -> Vec<bool> {
        let mut a = Vec::new();
        self.admissible.read_rect(rect, &mut a);
        a
    }
}

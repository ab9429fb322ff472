//! What one fusion call did.

/// What one call to [`ElevationMap::fuse`](crate::ElevationMap::fuse) did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FuseStats {
    /// Finite returns within `max_point_range` that entered their cell's per-scan maximum.
    pub fused_points: usize,
    /// Returns with a non-finite coordinate (or a scan with a non-finite origin).
    pub skipped_non_finite: usize,
    /// Returns farther than `max_point_range` from the sensor origin.
    pub skipped_out_of_range: usize,
    /// Returns attributed to a neighbour's vertical face by the mixed-cell rule.
    pub face_points: usize,
    /// Cells that received a measurement this scan (initialised, fused or gated).
    pub cells_updated: usize,
    /// Cells whose measurement was rejected by the Mahalanobis gate.
    pub cells_gated: usize,
    /// Returns dropped because a beam of the same scan crossed their cell's column below them.
    pub carved_points: usize,
    /// Cells whose estimate a beam contradicted and lowered (ray carving).
    pub cells_carved: usize,
    /// Cells whose measurement was a face bound that raised the estimate.
    pub face_bounds_raised: usize,
    /// Cells whose measurement was a face bound at or below the estimate (not fused).
    pub face_bounds_ignored: usize,
}

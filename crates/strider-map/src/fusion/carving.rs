//! Ray carving (see "Ray carving" in the module docs of `fusion`): each beam bounds the tops of
//! the cells it crossed over the last stretch before its trusted end.

use super::frame::{ScanFrame, ScanGrid};
use super::scratch::Located;
use strider_core::ColoredPoint;

/// Carving samples each beam at half-cell steps from its trusted end back over this many
/// steps (one cell). The trusted end of a beam that hit a face lies at most about 1σ in front
/// of it, so one cell back reaches the cell in front of the face, where spilled face returns
/// sit; looking no further keeps carving at three samples per return. A sample's height is
/// one the beam really had inside that cell, so the bound is sound (only slightly weaker than
/// the beam's minimum over the cell).
const CARVE_SAMPLES: usize = 2;

/// Carving uses every `CARVE_EVERY`-th beam of a scan (in scan order, so deterministic). A cell in
/// front of a face is crossed by many face beams; a subset finds it as surely (measured on
/// courtyard-large: the same elevation error with every beam and with every fourth) at a quarter
/// of the cost.
pub(super) const CARVE_EVERY: usize = 4;

/// The last `CARVE_SIGMAS`·σ of each beam are not trusted to have been travelled.
const CARVE_SIGMAS: f32 = 4.0;

/// Lowers `carve_z` (over the scan grid) to the heights of the beam to return `p` (squared
/// range `r2`, located at `l`) in the cells it crossed just before its trusted end; never in
/// the return's own cell.
pub(super) fn carve_beam(
    carve_z: &mut [f32],
    p: &ColoredPoint,
    r2: f32,
    l: &Located,
    frame: &ScanFrame,
    grid: &ScanGrid,
) {
    let (o, inv_d) = (frame.origin, frame.inv_d);
    let (ci, cj) = (l.ci as usize, l.cj as usize);
    // Beam geometry in cell units relative to the rect. Trust the beam up to CARVE_SIGMAS·σ
    // short of the return: the true hit may lie anywhere within the range noise before it.
    let back = CARVE_SIGMAS * l.var.sqrt();
    let (vx, vy, vz) = (p.x - o[0], p.y - o[1], p.z - o[2]);
    let lh = (vx * vx + vy * vy).sqrt() * inv_d; // horizontal beam length, cells
    let r = r2.sqrt();
    if lh < 1e-3 || back >= r {
        return;
    }
    // Unit horizontal direction (cells) and height change per cell travelled.
    let inv_lh = 1.0 / lh;
    let (hx, hy, dzc) = (vx * inv_d * inv_lh, vy * inv_d * inv_lh, vz * inv_lh);
    let back_c = lh * back / r; // trusted-end offset, horizontal cells
    let (ex, ey) = (ci as f32 + l.u - hx * back_c, cj as f32 + l.v - hy * back_c);
    let ez = p.z - dzc * back_c;
    let reach = lh - back_c; // horizontal cells from the origin to the trusted end
    let (wf, hf) = (grid.w as f32, grid.h as f32);
    for step in 0..=CARVE_SAMPLES {
        let b = 0.5 * step as f32;
        if b > reach {
            break;
        }
        let (x, y) = (ex - hx * b, ey - hy * b);
        if !(x >= 0.0 && y >= 0.0 && x < wf && y < hf) {
            continue;
        }
        let (xi, yi) = (x as usize, y as usize);
        if (xi, yi) == (ci, cj) {
            continue; // a return never carves its own cell
        }
        let cz = &mut carve_z[yi * grid.w + xi];
        *cz = cz.min(ez - dzc * b);
    }
}

//! The path handed to the robot: waypoints every carrot distance along the cheapest cell path,
//! which is what the paper's follow-the-carrot controller with that look-ahead tracks.

use strider_core::{Cell, Point2};

/// Waypoints every `carrot` metres along the cell path (centres, first cell skipped when the
/// robot stands in it), always ending at the last cell's centre.
pub fn carrot_waypoints(cells: &[Cell], cell_size: f64, carrot: f64, robot: Point2) -> Vec<Point2> {
    let pts: Vec<Point2> = cells.iter().map(|c| c.center(cell_size)).collect();
    let mut out = Vec::new();
    let mut last = robot;
    for (k, &p) in pts.iter().enumerate() {
        let is_last = k + 1 == pts.len();
        if is_last || (p.x - last.x).hypot(p.y - last.y) >= carrot {
            out.push(p);
            last = p;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carrot_spacing_and_end() {
        let cells: Vec<Cell> = (0..10).map(|i| Cell::new(i, 0)).collect();
        let w = carrot_waypoints(&cells, 0.1, 0.2, Point2::new(0.05, 0.05));
        assert_eq!(w.last().copied(), Some(Cell::new(9, 0).center(0.1)));
        for pair in w.windows(2) {
            let d = (pair[1].x - pair[0].x).hypot(pair[1].y - pair[0].y);
            assert!(d <= 0.2 + 1e-9, "{d}");
        }
        assert!(w.len() <= 6);
        assert!(carrot_waypoints(&[], 0.1, 0.2, Point2::new(0.0, 0.0)).is_empty());
    }
}

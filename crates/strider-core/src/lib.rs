//! # strider-core
//!
//! The vocabulary every other Strider crate speaks, and nothing else:
//!
//! * [`geom`]: points and poses in the world frame (x east, y north, z up, metres, radians).
//! * [`grid`]: the global cell lattice (`cell = floor(x / d_ν)`, Prágr22 §3) and the shape
//!   iterators every algorithm shares (footprint disc, cell ray), in the spirit of grid_map.
//! * [`color`]: sRGB → CIELAB, ΔE76 and the nine colour prototypes of decision 6 (Prágr22 §4.2,
//!   Fig. 5E).
//! * [`msg`] and [`interface`]: the messages a robot produces (point clouds, poses,
//!   proprioception) and the sensor/actuator interface. The simulator implements it; a real robot
//!   or a recorded log implements it too, so the autonomy stack never knows which one it runs on.
//!
//! * [`text`]: error text that is safe to print on one line.
//!
//! This crate depends on nothing of Strider's and has no algorithm beyond geometry.

pub mod color;
pub mod geom;
pub mod grid;
pub mod interface;
pub mod msg;
pub mod snapshot;
pub mod text;

pub use color::{Lab, Rgb8};
pub use geom::{Point2, Point3, Pose2};
pub use grid::{Cell, CellRect};
pub use msg::{ColoredPoint, GaitId, PointCloud, PoseStamped, Proprioception};
pub use snapshot::{GaitSpec, Snapshot};

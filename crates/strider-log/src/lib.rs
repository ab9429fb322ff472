//! # strider-log
//!
//! ROS 2 / MCAP log I/O: Strider's missions written to MCAP for Foxglove, and recorded robot
//! logs read back into the very same mapping and learning code.
//!
//! * [`sink`]: where recorded messages go — encoded once by [`sink::Writer`], written to any
//!   [`sink::MessageSink`]: [`writer`], an MCAP file over the [`mcap`] crate (zstd chunks,
//!   `ros2` profile), and [`live`], the live view over the Foxglove WebSocket protocol.
//! * [`recorder`]: a mission to MCAP and the live view — the robot's sensor stream as ROS 2 messages
//!   (`nav_msgs/msg/Odometry`, `sensor_msgs/msg/PointCloud2`, `tf2_msgs/msg/TFMessage`,
//!   `std_msgs/msg/String` gait, `std_msgs/msg/UInt8` motion state) and the mission's state
//!   with Foxglove's well-known schemas (`foxglove.Grid` map layers, `foxglove.PointCloud`
//!   experienced costs, `foxglove.SceneUpdate` goals, `foxglove.PosesInFrame` tour and path,
//!   `foxglove.FrameTransform` robot pose). The Foxglove messages are the protobuf types of
//!   Foxglove's SDK crate [`foxglove`], written with the `protobuf` message encoding and the
//!   schema (a `FileDescriptorSet`) it ships, so their schema names are Foxglove's exactly.
//! * [`cdr`] and [`ros2`]: the ROS 2 wire format (CDR via the [`cdr`](::cdr) crate with our own
//!   serde structs, hardened against hostile lengths) and the message definitions.
//! * [`replay`]: a recorded log behind [`strider_core::interface::Robot`], for
//!   `strider_explore::Mission::ingest`; [`config`] its TOML configuration.
//! * [`error`]: [`LogError`], which says what was wrong and where (file, topic, message index,
//!   byte offset); [`limits`]: the bounds a log must keep.
//!
//! Nothing here is used by the algorithms: `strider-explore` does not depend on this crate.

#![warn(missing_docs)]

pub mod cdr;
pub mod config;
pub mod error;
pub mod limits;
pub mod live;
pub mod recorder;
pub mod replay;
pub mod ros2;
pub mod sink;
pub mod writer;

pub use config::ReplayConfig;
pub use error::LogError;
pub use live::LiveServer;
pub use recorder::{Recorder, RecorderOptions, Recording, Topics};
pub use replay::{LogReplay, ReplayStats};
pub use writer::McapWriter;

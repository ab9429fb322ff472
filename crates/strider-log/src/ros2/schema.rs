//! The `ros2msg` schema texts of the messages: the concatenated definitions rosbag2 stores in
//! MCAP, which `mcap-ros2-support` and Foxglove parse to decode the messages.

/// The separator rosbag2 puts between a message definition and each dependency.
const SEP: &str =
    "================================================================================\n";

fn definition(main: &str, deps: &[(&str, &str)]) -> String {
    let mut s = main.to_string();
    for (name, text) in deps {
        s.push('\n');
        s.push_str(SEP);
        s.push_str("MSG: ");
        s.push_str(name);
        s.push('\n');
        s.push_str(text);
    }
    s
}

const TIME: (&str, &str) = ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n");
const HEADER: (&str, &str) = (
    "std_msgs/Header",
    "builtin_interfaces/Time stamp\nstring frame_id\n",
);
const POINT: (&str, &str) = ("geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n");
const VECTOR3: (&str, &str) = ("geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n");
const QUATERNION: (&str, &str) = (
    "geometry_msgs/Quaternion",
    "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
);
const POSE: (&str, &str) = (
    "geometry_msgs/Pose",
    "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
);
const TRANSFORM: (&str, &str) = (
    "geometry_msgs/Transform",
    "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
);

/// A ROS 2 message type: its schema name and `ros2msg` definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MsgType {
    /// `nav_msgs/msg/Odometry`.
    Odometry,
    /// `tf2_msgs/msg/TFMessage`.
    TfMessage,
    /// `sensor_msgs/msg/PointCloud2`.
    PointCloud2,
    /// `sensor_msgs/msg/LaserScan`.
    LaserScan,
    /// `std_msgs/msg/String`.
    String,
    /// `std_msgs/msg/UInt8`.
    UInt8,
}

impl MsgType {
    /// The schema name (the MCAP schema record's `name`, as rosbag2 writes it).
    pub fn name(self) -> &'static str {
        match self {
            MsgType::Odometry => "nav_msgs/msg/Odometry",
            MsgType::TfMessage => "tf2_msgs/msg/TFMessage",
            MsgType::PointCloud2 => "sensor_msgs/msg/PointCloud2",
            MsgType::LaserScan => "sensor_msgs/msg/LaserScan",
            MsgType::String => "std_msgs/msg/String",
            MsgType::UInt8 => "std_msgs/msg/UInt8",
        }
    }

    /// The full `ros2msg` definition with its dependencies.
    pub fn definition(self) -> String {
        match self {
            MsgType::Odometry => definition(
                "std_msgs/Header header\nstring child_frame_id\n\
                 geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
                &[
                    HEADER,
                    TIME,
                    (
                        "geometry_msgs/PoseWithCovariance",
                        "geometry_msgs/Pose pose\nfloat64[36] covariance\n",
                    ),
                    POSE,
                    POINT,
                    QUATERNION,
                    (
                        "geometry_msgs/TwistWithCovariance",
                        "geometry_msgs/Twist twist\nfloat64[36] covariance\n",
                    ),
                    (
                        "geometry_msgs/Twist",
                        "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
                    ),
                    VECTOR3,
                ],
            ),
            MsgType::TfMessage => definition(
                "geometry_msgs/TransformStamped[] transforms\n",
                &[
                    (
                        "geometry_msgs/TransformStamped",
                        "std_msgs/Header header\nstring child_frame_id\n\
                         geometry_msgs/Transform transform\n",
                    ),
                    HEADER,
                    TIME,
                    TRANSFORM,
                    VECTOR3,
                    QUATERNION,
                ],
            ),
            MsgType::PointCloud2 => definition(
                "std_msgs/Header header\nuint32 height\nuint32 width\n\
                 sensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\n\
                 uint32 row_step\nuint8[] data\nbool is_dense\n",
                &[
                    HEADER,
                    TIME,
                    (
                        "sensor_msgs/PointField",
                        "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\n\
                         uint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\n\
                         string name\nuint32 offset\nuint8 datatype\nuint32 count\n",
                    ),
                ],
            ),
            MsgType::LaserScan => definition(
                "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\n\
                 float32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\n\
                 float32 range_min\nfloat32 range_max\nfloat32[] ranges\n\
                 float32[] intensities\n",
                &[HEADER, TIME],
            ),
            MsgType::String => "string data\n".into(),
            MsgType::UInt8 => "uint8 data\n".into(),
        }
    }
}

#!/usr/bin/env python3
"""A CARMEN log (.clf, ODOM and FLASER records) as an MCAP file of CDR-encoded ROS 2 messages
with the laser as sensor_msgs/msg/LaserScan, for checking `strider replay` on a planar laser:

  /odom       nav_msgs/msg/Odometry     frame odom, child base_link (ODOM records)
  /tf         tf2_msgs/msg/TFMessage    odom -> base_link at each scan's odometry
  /tf_static  tf2_msgs/msg/TFMessage    base_link -> laser (from the first scan's poses)
  /scan       sensor_msgs/msg/LaserScan frame laser, beams from -90 deg over 180 deg

Every range is written as logged; returns at or below --min-range and at or beyond --max-range
are left to the reader through range_min and range_max (the float32 just inside the limits).

Usage: clf2laserscan.py IN.clf OUT.mcap [--height 0.35] [--min-range 0.02] [--max-range 40]
                        [--compression zstd|lz4|none]
Needs the `mcap` and `mcap-ros2-support` packages.
"""
import argparse
import math
import struct

from mcap.writer import CompressionType
from mcap_ros2.writer import Writer


def definition(main, deps):
    """A ros2msg schema: the main definition and its dependencies, as rosbag2 stores them."""
    rule = "=" * 80
    return main + "".join(f"{rule}\nMSG: {name}\n{text}" for name, text in deps)


STAMP = ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n")
HEAD = ("std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n")
XYZ = "float64 x\nfloat64 y\nfloat64 z\n"
QUAT = ("geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n")
SCHEMAS = {
    "nav_msgs/msg/Odometry": definition(
        "std_msgs/Header header\nstring child_frame_id\n"
        "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
        [
            HEAD,
            STAMP,
            ("geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"),
            ("geometry_msgs/Pose", "Point position\nQuaternion orientation\n"),
            ("geometry_msgs/Point", XYZ),
            QUAT,
            ("geometry_msgs/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n"),
            ("geometry_msgs/Twist", "Vector3 linear\nVector3 angular\n"),
            ("geometry_msgs/Vector3", XYZ),
        ],
    ),
    "tf2_msgs/msg/TFMessage": definition(
        "geometry_msgs/TransformStamped[] transforms\n",
        [
            (
                "geometry_msgs/TransformStamped",
                "std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
            ),
            HEAD,
            STAMP,
            ("geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"),
            ("geometry_msgs/Vector3", XYZ),
            QUAT,
        ],
    ),
    "sensor_msgs/msg/LaserScan": definition(
        "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
        "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
        "float32[] ranges\nfloat32[] intensities\n",
        [HEAD, STAMP],
    ),
}


def f32_toward(x, down):
    """The float32 next to float32(x), toward zero when `down` (else away): just inside a limit."""
    bits = struct.unpack("<I", struct.pack("<f", x))[0]
    return struct.unpack("<f", struct.pack("<I", bits - 1 if down else bits + 1))[0]


def records(path):
    """('odom', t, x, y, th) and ('scan', t, ranges, (laser x, y, th), (odom x, y, th))."""
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "ODOM":
                yield ("odom", float(w[7]), *map(float, w[1:4]))
            elif w[0] == "FLASER":
                n = int(w[1])
                tail = list(map(float, w[2 + n : 8 + n]))
                yield ("scan", float(w[8 + n]), [float(r) for r in w[2 : 2 + n]], tail[:3], tail[3:])


def when(t):
    ns = int(round(t * 1e9))
    return {"sec": ns // 10**9, "nanosec": ns % 10**9}, ns


def rotation(yaw):
    return {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}


def transform(stamp, parent, child, x, y, z, yaw):
    return {
        "transforms": [
            {
                "header": {"stamp": stamp, "frame_id": parent},
                "child_frame_id": child,
                "transform": {
                    "translation": {"x": x, "y": y, "z": z},
                    "rotation": rotation(yaw),
                },
            }
        ]
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("clf")
    ap.add_argument("out")
    ap.add_argument("--height", type=float, default=0.35, help="laser height, m")
    ap.add_argument("--min-range", type=float, default=0.02, help="returns at or below: none")
    ap.add_argument("--max-range", type=float, default=40.0, help="returns at or beyond: none")
    ap.add_argument("--compression", default="zstd", choices=["zstd", "lz4", "none"])
    a = ap.parse_args()
    kind = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
    out = open(a.out, "wb")
    w = Writer(out, compression=kind[a.compression])
    schema = {name: w.register_msgdef(name, text) for name, text in SCHEMAS.items()}
    zeros = [0.0] * 36
    origin = {"x": 0.0, "y": 0.0, "z": 0.0}
    counts = {"odom": 0, "scan": 0}
    static_written = False
    for rec in records(a.clf):
        stamp, ns = when(rec[1])
        counts[rec[0]] += 1
        if rec[0] == "odom":
            _, _, x, y, th = rec
            pose = {"position": {"x": x, "y": y, "z": 0.0}, "orientation": rotation(th)}
            msg = {
                "header": {"stamp": stamp, "frame_id": "odom"},
                "child_frame_id": "base_link",
                "pose": {"pose": pose, "covariance": zeros},
                "twist": {"twist": {"linear": origin, "angular": origin}, "covariance": zeros},
            }
            w.write_message("/odom", schema["nav_msgs/msg/Odometry"], msg, ns, ns)
            continue
        _, _, ranges, laser, base = rec
        tf = schema["tf2_msgs/msg/TFMessage"]
        if not static_written:
            # The laser in the body frame: its logged pose relative to the odometry pose.
            c, s = math.cos(base[2]), math.sin(base[2])
            dx, dy = laser[0] - base[0], laser[1] - base[1]
            lx, ly, lth = c * dx + s * dy, -s * dx + c * dy, laser[2] - base[2]
            msg = transform(stamp, "base_link", "laser", lx, ly, a.height, lth)
            w.write_message("/tf_static", tf, msg, ns, ns)
            static_written = True
        w.write_message("/tf", tf, transform(stamp, "odom", "base_link", *base[:2], 0.0, base[2]), ns, ns)
        n = len(ranges)
        # CARMEN's front laser: 180 beams over 180 deg (181 over 180 when odd), from -90 deg.
        step = math.pi / n if n % 2 == 0 else math.pi / max(n - 1, 1)
        scan = {
            "header": {"stamp": stamp, "frame_id": "laser"},
            "angle_min": -math.pi / 2,
            "angle_max": -math.pi / 2 + step * (n - 1),
            "angle_increment": step,
            "time_increment": 0.0,
            "scan_time": 0.0,
            "range_min": f32_toward(a.min_range, False),
            "range_max": f32_toward(a.max_range, True),
            "ranges": ranges,
            "intensities": [],
        }
        w.write_message("/scan", schema["sensor_msgs/msg/LaserScan"], scan, ns, ns)
    w.finish()
    out.close()
    print(f"{a.out}: {counts['odom']} odometry, {counts['scan']} scans")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Independent check of Strider's MCAP output with the PyPI readers.

Opens an MCAP file written by `strider run --mcap FILE` with the `mcap` package and decodes
every message: ROS 2 (`cdr`) messages with `mcap-ros2-support` (from the `ros2msg` schema texts
in the file), Foxglove (`protobuf`) messages with `mcap-protobuf-support` (from the
FileDescriptorSet in the file). Prints per topic the schema name, the encodings, the message
count and how many decoded, spot-checks a few fields, and exits non-zero unless 100 % of the
messages decode and every Foxglove schema name is one of Foxglove's.

Not part of the Rust build or tests. Setup:

    python3 -m venv /tmp/venv-mcap
    /tmp/venv-mcap/bin/pip install mcap mcap-ros2-support mcap-protobuf-support
    /tmp/venv-mcap/bin/python bench/mcap_check.py out/run.mcap
"""

import math
import sys
from collections import Counter, defaultdict

from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory as ProtobufDecoderFactory
from mcap_ros2.decoder import DecoderFactory as Ros2DecoderFactory

# Foxglove's well-known schemas (https://docs.foxglove.dev/docs/visualization/message-schemas).
FOXGLOVE_SCHEMAS = {
    "foxglove.ArrowPrimitive", "foxglove.CameraCalibration", "foxglove.CircleAnnotation",
    "foxglove.Color", "foxglove.CompressedImage", "foxglove.CompressedVideo",
    "foxglove.CubePrimitive", "foxglove.CylinderPrimitive", "foxglove.FrameTransform",
    "foxglove.FrameTransforms", "foxglove.GeoJSON", "foxglove.Grid", "foxglove.ImageAnnotations",
    "foxglove.KeyValuePair", "foxglove.LaserScan", "foxglove.LinePrimitive",
    "foxglove.LocationFix", "foxglove.Log", "foxglove.ModelPrimitive",
    "foxglove.PackedElementField", "foxglove.Point2", "foxglove.Point3", "foxglove.PointCloud",
    "foxglove.PointsAnnotation", "foxglove.Pose", "foxglove.PoseInFrame", "foxglove.PosesInFrame",
    "foxglove.Quaternion", "foxglove.RawImage", "foxglove.SceneEntity",
    "foxglove.SceneEntityDeletion", "foxglove.SceneUpdate", "foxglove.SpherePrimitive",
    "foxglove.TextAnnotation", "foxglove.TextPrimitive", "foxglove.TriangleListPrimitive",
    "foxglove.Vector2", "foxglove.Vector3", "foxglove.VoxelGrid",
}


def main(path):
    ros2 = Ros2DecoderFactory()
    proto = ProtobufDecoderFactory()
    total = Counter()
    ok = Counter()
    info = {}
    errors = defaultdict(list)
    last = {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            topic = channel.topic
            total[topic] += 1
            info[topic] = (schema.name if schema else "", schema.encoding if schema else "",
                           channel.message_encoding)
            factory = ros2 if channel.message_encoding == "cdr" else proto
            try:
                decoder = factory.decoder_for(channel.message_encoding, schema)
                if decoder is None:
                    raise ValueError(f"no decoder for {channel.message_encoding}")
                last[topic] = decoder(message.data)
                ok[topic] += 1
            except Exception as e:  # noqa: BLE001 - report every failure
                if len(errors[topic]) < 3:
                    errors[topic].append(repr(e))
    n, d = sum(total.values()), sum(ok.values())
    print(f"{path}: {n} messages, {len(total)} topics")
    if summary and summary.statistics:
        s = summary.statistics
        print(f"  time span {(s.message_end_time - s.message_start_time) / 1e9:.1f} s, "
              f"{s.chunk_count} chunks")
    print(f"  {'topic':32} {'schema':30} {'enc':9} {'messages':>9} {'decoded':>8}")
    for topic in sorted(total):
        name, _, enc = info[topic]
        print(f"  {topic:32} {name:30} {enc:9} {total[topic]:9d} {ok[topic]:8d}")
        for e in errors[topic]:
            print(f"      error: {e}")
    bad_names = sorted({info[t][0] for t in info
                        if info[t][2] == "protobuf" and info[t][0] not in FOXGLOVE_SCHEMAS})
    # Spot checks of decoded content.
    checks = []
    g = last.get("/strider/map")
    if g is not None:
        names = [fl.name for fl in g.fields]
        checks.append(f"map grid {g.column_count} columns, {len(g.data) // g.cell_stride} cells, "
                      f"fields {', '.join(names)}")
    c = last.get("/robot/sensor_0/points")
    if c is not None:
        checks.append(f"last PointCloud2: {c.width}x{c.height} points, fields "
                      f"{', '.join(fl.name for fl in c.fields)}, frame {c.header.frame_id}")
    o = last.get("/robot/odom")
    if o is not None:
        p = o.pose.pose.position
        ok_pose = all(math.isfinite(v) for v in (p.x, p.y, p.z))
        checks.append(f"last Odometry at ({p.x:.3f}, {p.y:.3f}), finite: {ok_pose}")
    for line in checks:
        print("  " + line)
    pct = 100.0 * d / max(n, 1)
    print(f"decoded {d}/{n} messages ({pct:.2f} %); "
          f"protobuf schema names not Foxglove's: {bad_names or 'none'}")
    return 0 if d == n and n > 0 and not bad_names else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: mcap_check.py FILE.mcap")
    sys.exit(main(sys.argv[1]))

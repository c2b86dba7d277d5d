"""Writes a rosbag2 recording from a JSON description, with the ROS ecosystem's own writers:
rosbags (rosbag2 folders, sqlite3 or MCAP storage) or mcap-ros2-support (one .mcap file).

Usage: write_bag.py SPEC.json OUT FORMAT   (FORMAT: sqlite3 | mcap | mcap_ros2)

SPEC: {"messages": [{"t": ns, "topic": str, "kind": str, ...}, ...]} where kind is
occupancy_grid | costmap | grid_update | path | pose_stamped | pose_cov | tf.
"""
import json
import sys

import numpy as np
from rosbags.typesys import Stores, get_typestore, get_types_from_msg

NAV2_MSGS = {
    "nav2_msgs/msg/CostmapMetaData": """
builtin_interfaces/Time map_load_time
builtin_interfaces/Time update_time
string layer
float32 resolution
uint32 size_x
uint32 size_y
geometry_msgs/Pose origin
""",
    "nav2_msgs/msg/Costmap": """
std_msgs/Header header
nav2_msgs/CostmapMetaData metadata
uint8[] data
""",
    "map_msgs/msg/OccupancyGridUpdate": """
std_msgs/Header header
int32 x
int32 y
uint32 width
uint32 height
int8[] data
""",
}

TYPES = {
    "occupancy_grid": "nav_msgs/msg/OccupancyGrid",
    "costmap": "nav2_msgs/msg/Costmap",
    "grid_update": "map_msgs/msg/OccupancyGridUpdate",
    "path": "nav_msgs/msg/Path",
    "pose_stamped": "geometry_msgs/msg/PoseStamped",
    "pose_cov": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "tf": "tf2_msgs/msg/TFMessage",
}


def typestore():
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = {}
    for name, text in NAV2_MSGS.items():
        types.update(get_types_from_msg(text, name))
    store.register(types)
    return store


class Build:
    def __init__(self, store):
        self.s = store
        self.t = store.types

    def time(self, ns):
        return self.t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9)

    def header(self, ns, frame="map"):
        return self.t["std_msgs/msg/Header"](stamp=self.time(ns), frame_id=frame)

    def pose(self, p):
        t = self.t
        return t["geometry_msgs/msg/Pose"](
            position=t["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2]),
            orientation=t["geometry_msgs/msg/Quaternion"](x=p[3], y=p[4], z=p[5], w=p[6]),
        )

    def message(self, m):
        t, ns, kind = self.t, m["t"], m["kind"]
        if kind == "occupancy_grid":
            info = t["nav_msgs/msg/MapMetaData"](
                map_load_time=self.time(ns), resolution=m["resolution"], width=m["width"],
                height=m["height"], origin=self.pose(m["origin"]))
            return t["nav_msgs/msg/OccupancyGrid"](
                header=self.header(ns), info=info, data=np.array(m["data"], dtype=np.int8))
        if kind == "costmap":
            md = t["nav2_msgs/msg/CostmapMetaData"](
                map_load_time=self.time(ns), update_time=self.time(ns), layer="master",
                resolution=m["resolution"], size_x=m["width"], size_y=m["height"],
                origin=self.pose(m["origin"]))
            return t["nav2_msgs/msg/Costmap"](
                header=self.header(ns), metadata=md, data=np.array(m["data"], dtype=np.uint8))
        if kind == "grid_update":
            return t["map_msgs/msg/OccupancyGridUpdate"](
                header=self.header(ns), x=m["x"], y=m["y"], width=m["width"], height=m["height"],
                data=np.array(m["data"], dtype=np.int8))
        if kind == "path":
            poses = [t["geometry_msgs/msg/PoseStamped"](header=self.header(ns), pose=self.pose(p))
                     for p in m["poses"]]
            return t["nav_msgs/msg/Path"](header=self.header(ns, m.get("frame", "map")), poses=poses)
        if kind == "pose_stamped":
            return t["geometry_msgs/msg/PoseStamped"](header=self.header(ns), pose=self.pose(m["pose"]))
        if kind == "pose_cov":
            pwc = t["geometry_msgs/msg/PoseWithCovariance"](
                pose=self.pose(m["pose"]), covariance=np.zeros(36, dtype=np.float64))
            return t["geometry_msgs/msg/PoseWithCovarianceStamped"](header=self.header(ns), pose=pwc)
        if kind == "tf":
            v3, tr = t["geometry_msgs/msg/Vector3"], t["geometry_msgs/msg/Transform"]
            out = []
            for parent, child, p in m["transforms"]:
                q = t["geometry_msgs/msg/Quaternion"](x=p[3], y=p[4], z=p[5], w=p[6])
                out.append(t["geometry_msgs/msg/TransformStamped"](
                    header=self.header(ns, parent), child_frame_id=child,
                    transform=tr(translation=v3(x=p[0], y=p[1], z=p[2]), rotation=q)))
            return t["tf2_msgs/msg/TFMessage"](transforms=out)
        raise ValueError(f"unknown kind {kind}")


def write_rosbags(spec, out, storage):
    from rosbags.rosbag2 import StoragePlugin, Writer
    store = typestore()
    build = Build(store)
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    conns = {}
    with Writer(out, version=9, storage_plugin=plugin) as writer:
        for m in spec["messages"]:
            typename = TYPES[m["kind"]]
            key = (m["topic"], typename)
            if key not in conns:
                conns[key] = writer.add_connection(m["topic"], typename, typestore=store)
            data = store.serialize_cdr(build.message(m), typename)
            writer.write(conns[key], m["t"], data)


def write_mcap_ros2(spec, out):
    from mcap_ros2.writer import Writer
    store = typestore()
    build = Build(store)
    schemas = {}
    with open(out, "wb") as f:
        writer = Writer(f)
        for m in spec["messages"]:
            typename = TYPES[m["kind"]]
            if typename not in schemas:
                text, _ = store.generate_msgdef(typename, ros_version=2)
                schemas[typename] = writer.register_msgdef(typename, text)
            # mcap-ros2-support encodes from plain data: serialize with rosbags, decode to dicts
            raw = store.serialize_cdr(build.message(m), typename)
            writer.write_message(m["topic"], schemas[typename], to_plain(store.deserialize_cdr(raw, typename)),
                                 log_time=m["t"], publish_time=m["t"])
        writer.finish()


def to_plain(msg):
    if isinstance(msg, np.ndarray):
        return msg.tolist()
    if isinstance(msg, list):
        return [to_plain(x) for x in msg]
    if hasattr(msg, "__dataclass_fields__"):
        return {k: to_plain(getattr(msg, k)) for k in msg.__dataclass_fields__ if k != "__msgtype__"}
    return msg


def main():
    spec_path, out, fmt = sys.argv[1:4]
    with open(spec_path) as f:
        spec = json.load(f)
    if fmt == "mcap_ros2":
        write_mcap_ros2(spec, out)
    else:
        write_rosbags(spec, out, fmt)


if __name__ == "__main__":
    main()

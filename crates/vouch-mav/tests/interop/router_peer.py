#!/usr/bin/env python3
"""A pymavlink ground station or companion for the router tests: sends its HEARTBEAT every 0.5 s,
records every message it receives (type counts per source system, heartbeat times), and once it
has heard the systems of --wait-for, optionally sends DO_PARACHUTE RELEASE (--parachute-to) and
PARAM_REQUEST_LIST (--params-from) to them. Runs --duration seconds (or until --stop-file
exists) and writes a JSON summary.
"""
import argparse
import json
import os
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

p = argparse.ArgumentParser()
p.add_argument("--url", required=True)
p.add_argument("--sysid", type=int, default=254)
p.add_argument("--compid", type=int, default=190)
p.add_argument("--onboard", action="store_true", help="announce as an onboard computer, not a GCS")
p.add_argument("--wait-for", default="", help="comma-separated system ids to hear before acting")
p.add_argument("--parachute-to", type=int, default=None)
p.add_argument("--params-from", type=int, default=None)
p.add_argument("--duration", type=float, default=20.0)
p.add_argument("--stop-file", default=None)
p.add_argument("--summary", required=True)
a = p.parse_args()

m = mavutil.mavlink_connection(a.url, source_system=a.sysid, source_component=a.compid, dialect="common")
C = mavutil.mavlink
kind = C.MAV_TYPE_ONBOARD_CONTROLLER if a.onboard else C.MAV_TYPE_GCS
wait_for = {int(s) for s in a.wait_for.split(",") if s}
out = {"types": {}, "heartbeats": {}, "command_ack": None, "param_values": {}, "acted_at": None}
start = time.time()
last_hb = 0.0
while time.time() - start < a.duration:
    if a.stop_file and os.path.exists(a.stop_file):
        break
    now = time.time()
    if now - last_hb > 0.5:
        m.mav.heartbeat_send(kind, C.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        last_hb = now
    heard = {int(s) for s in out["heartbeats"]}
    if out["acted_at"] is None and wait_for and wait_for <= heard:
        out["acted_at"] = round(now - start, 3)
        if a.parachute_to is not None:
            m.mav.command_long_send(a.parachute_to, 1, C.MAV_CMD_DO_PARACHUTE, 0, 2, 0, 0, 0, 0, 0, 0)
        if a.params_from is not None:
            m.mav.param_request_list_send(a.params_from, 1)
    msg = m.recv_match(blocking=True, timeout=0.05)
    if msg is None or msg.get_type() == "BAD_DATA":
        continue
    t, src = msg.get_type(), str(msg.get_srcSystem())
    per = out["types"].setdefault(src, {})
    per[t] = per.get(t, 0) + 1
    if t == "HEARTBEAT":
        out["heartbeats"].setdefault(src, []).append(round(time.time() - start, 3))
    elif t == "COMMAND_ACK" and msg.command == C.MAV_CMD_DO_PARACHUTE:
        out["command_ack"] = msg.result
    elif t == "PARAM_VALUE":
        out["param_values"][src] = out["param_values"].get(src, 0) + 1
with open(a.summary, "w") as f:
    json.dump(out, f)

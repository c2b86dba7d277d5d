#!/usr/bin/env python3
"""A minimal pymavlink ground station (255/190) for the guard's interop tests.

--parachute: waits for the vehicle's heartbeat, sends COMMAND_LONG DO_PARACHUTE RELEASE
(param1 = 2) and reports the COMMAND_ACK result (or none) and any STATUSTEXT, within --duration s.
"""
import argparse
import json
import os
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

p = argparse.ArgumentParser()
p.add_argument("--url", required=True)
p.add_argument("--duration", type=float, default=10.0)
p.add_argument("--summary", required=True)
a = p.parse_args()

m = mavutil.mavlink_connection(a.url, source_system=255, source_component=190, dialect="common")
C = mavutil.mavlink
out = {"heartbeat": False, "command_ack": None, "statustext": []}
deadline = time.time() + a.duration
sent_at = None
while time.time() < deadline:
    if sent_at is None:
        m.mav.heartbeat_send(C.MAV_TYPE_GCS, C.MAV_AUTOPILOT_INVALID, 0, 0, 0)
    msg = m.recv_match(blocking=True, timeout=0.1)
    if msg is None:
        continue
    t = msg.get_type()
    if t == "HEARTBEAT" and msg.get_srcSystem() == 1 and sent_at is None:
        out["heartbeat"] = True
        m.mav.command_long_send(1, 1, C.MAV_CMD_DO_PARACHUTE, 0, 2, 0, 0, 0, 0, 0, 0)
        sent_at = time.time()
    elif t == "COMMAND_ACK" and msg.command == C.MAV_CMD_DO_PARACHUTE:
        out["command_ack"] = msg.result
    elif t == "STATUSTEXT":
        out["statustext"].append(msg.text)
    if out["command_ack"] is not None and time.time() - sent_at > 0.5:
        break
with open(a.summary, "w") as f:
    json.dump(out, f)

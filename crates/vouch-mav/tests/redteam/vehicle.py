#!/usr/bin/env python3
"""A scripted ArduPilot-like vehicle (system 1, component 1) for the guard's red-team tests.

It streams its state (HEARTBEAT with the armed flag and custom mode, GLOBAL_POSITION_INT,
VFR_HUD) every 100 ms, reports its parameters, answers PARAM_SET / PARAM_REQUEST_READ with
PARAM_VALUE (names matched without regard to case, as ArduPilot's AP_Param::find does),
COMMAND_LONG / COMMAND_INT with COMMAND_ACK, stand-alone mission item reads with the home item,
and logs every datagram it receives, byte for byte, with what pymavlink decodes from it. The
summary (JSON) is what the tests assert on: what the vehicle actually received.
"""
import argparse
import json
import math
import os
import socket
import time

os.environ["MAVLINK20"] = "1"
from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

p = argparse.ArgumentParser()
p.add_argument("--port", type=int, required=True, help="UDP port on 127.0.0.1 the guard sends to")
p.add_argument("--summary", required=True)
p.add_argument("--stop-file", required=True, help="stop as soon as this file exists")
p.add_argument("--duration", type=float, default=60.0)
p.add_argument("--armed", type=int, default=1)
p.add_argument("--mode", type=int, default=5, help="custom_mode (ArduCopter 5 = LOITER)")
p.add_argument("--alt", type=float, default=50.0, help="metres above home")
p.add_argument("--climb", type=float, default=2.0, help="m/s, positive up")
p.add_argument("--param", action="append", default=[], help="NAME=VALUE (repeatable)")
p.add_argument("--quiet-state", action="store_true", help="send heartbeats only")
p.add_argument("--stale-answers", action="store_true",
               help="once connected, answer requests that were never sent (a guard joining mid-stream)")
a = p.parse_args()

params = {}
for kv in a.param:
    k, v = kv.split("=", 1)
    params[k] = float(v)

sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
sock.bind(("127.0.0.1", a.port))
sock.settimeout(0.02)
mav = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
mav.robust_parsing = True
peer = None
C = mavlink


def send(msg):
    if peer is not None:
        sock.sendto(msg.pack(mav), peer)
        mav.seq = (mav.seq + 1) % 256


def finite(x):
    return x if not isinstance(x, float) or math.isfinite(x) else repr(x)


def plain(v):
    if isinstance(v, (bytes, bytearray)):
        return v.hex()
    if isinstance(v, float):
        return finite(v)
    if isinstance(v, list):
        return [plain(x) for x in v]
    return v


def find_param(name):
    for k in params:
        if k.lower() == name.lower():
            return k
    return None


def send_param(name):
    names = list(params)
    send(mav.param_value_encode(name.encode(), params[name], C.MAV_PARAM_TYPE_REAL32, len(names),
                                names.index(name)))


summary = {"datagrams": [], "messages": [], "bad_data": 0, "parachute_param1": [],
           "param_sets": [], "commands": []}
deadline = time.time() + a.duration
last_state = 0.0
announced = False
while time.time() < deadline and not os.path.exists(a.stop_file):
    now = time.time()
    if now - last_state > 0.1:
        base_mode = C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | (C.MAV_MODE_FLAG_SAFETY_ARMED if a.armed else 0)
        send(mav.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, base_mode, a.mode,
                                  C.MAV_STATE_ACTIVE))
        if not a.quiet_state:
            send(mav.global_position_int_encode(int(now * 1000) & 0xFFFFFFFF, 0, 0, int(a.alt * 1000),
                                                int(a.alt * 1000), 0, 0, int(-a.climb * 100), 0))
            send(mav.vfr_hud_encode(0.0, 0.0, 0, 50, a.alt, a.climb))
        if peer is not None and not announced:
            for name in params:
                send_param(name)
            if a.stale_answers:
                send(mav.command_ack_encode(C.MAV_CMD_COMPONENT_ARM_DISARM, C.MAV_RESULT_ACCEPTED, 0, 0, 255, 190))
                send(mav.mission_item_int_encode(255, 190, 3, 0, 16, 0, 1, 0, 0, 0, 0, 1, 2, 30.0, 0))
            announced = True
        last_state = now
    try:
        data, frm = sock.recvfrom(65535)
    except socket.timeout:
        continue
    peer = frm
    summary["datagrams"].append(data.hex())
    for msg in mav.parse_buffer(data) or []:
        t = msg.get_type()
        if t == "BAD_DATA":
            summary["bad_data"] += 1
            continue
        fields = {k: plain(v) for k, v in msg.to_dict().items() if k != "mavpackettype"}
        summary["messages"].append({"type": t, "src": [msg.get_srcSystem(), msg.get_srcComponent()],
                                    "fields": fields})
        if t == "PARAM_SET":
            name = find_param(msg.param_id)
            summary["param_sets"].append([msg.param_id, finite(msg.param_value)])
            if name is not None:
                params[name] = msg.param_value
                send_param(name)
        elif t == "PARAM_REQUEST_READ":
            name = find_param(msg.param_id)
            if name is not None:
                send_param(name)
        elif t == "PARAM_REQUEST_LIST":
            for name in params:
                send_param(name)
        elif t in ("COMMAND_LONG", "COMMAND_INT") and msg.target_system in (0, 1):
            summary["commands"].append([t, msg.command, finite(msg.param1)])
            if msg.command == C.MAV_CMD_DO_PARACHUTE:
                summary["parachute_param1"].append(finite(msg.param1))
            send(mav.command_ack_encode(msg.command, C.MAV_RESULT_ACCEPTED, 0, 0, msg.get_srcSystem(),
                                        msg.get_srcComponent()))
        elif t in ("MISSION_REQUEST_INT", "MISSION_REQUEST") and msg.seq == 0:
            send(mav.mission_item_int_encode(msg.get_srcSystem(), msg.get_srcComponent(), 0, 0, 16, 0, 1,
                                             0, 0, 0, 0, -353632610, 1491652300, 584.0, msg.mission_type))

with open(a.summary, "w") as f:
    json.dump(summary, f)

#!/usr/bin/env python3
"""A scripted ArduPilot-like vehicle (system 1, component 1) for the guard's red-team tests.

It streams its state (HEARTBEAT with the armed flag and custom mode, GLOBAL_POSITION_INT,
VFR_HUD) every 100 ms, reports its parameters, answers PARAM_SET / PARAM_REQUEST_READ with
PARAM_VALUE (names matched without regard to case, as ArduPilot's AP_Param::find does),
COMMAND_LONG / COMMAND_INT with COMMAND_ACK, stand-alone mission item reads with the home item,
and logs every datagram it receives, byte for byte, with what pymavlink decodes from it. The
summary (JSON) is what the tests assert on: what the vehicle actually received.
"""
import json
import time

from peer import C, Link, arguments, finite, parameters

p = arguments("a scripted ArduPilot-like vehicle for the guard's red-team tests")
p.add_argument("--quiet-state", action="store_true", help="send heartbeats only")
p.add_argument("--stale-answers", action="store_true",
               help="once connected, answer requests that were never sent (a guard joining mid-stream)")
a = p.parse_args()
params = parameters(a)
link = Link(a)
mav = link.mav
send = link.send


def plain(v):
    if isinstance(v, (bytes, bytearray)):
        return v.hex()
    if isinstance(v, float):
        return finite(v)
    if isinstance(v, list):
        return [plain(x) for x in v]
    return v


def fields(msg):
    return {k: plain(v) for k, v in msg.to_dict().items() if k != "mavpackettype"}


def find_param(name):
    for k in params:
        if k.lower() == name.lower():
            return k
    return None


def send_param(name):
    link.param_value(params, name)


summary = link.summary
summary.update({"parachute_param1": [], "param_sets": [], "commands": []})
announced = False
while link.running():
    now = time.time()
    if link.state_due(now):
        link.heartbeat(a.mode)
        if not a.quiet_state:
            link.position(now)
        if link.peer is not None and not announced:
            for name in params:
                send_param(name)
            if a.stale_answers:
                send(mav.command_ack_encode(C.MAV_CMD_COMPONENT_ARM_DISARM, C.MAV_RESULT_ACCEPTED, 0, 0, 255, 190))
                send(mav.mission_item_int_encode(255, 190, 3, 0, 16, 0, 1, 0, 0, 0, 0, 1, 2, 30.0, 0))
            announced = True
    for msg in link.receive(fields):
        t = msg.get_type()
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

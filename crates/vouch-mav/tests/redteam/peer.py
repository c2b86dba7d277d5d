"""What the scripted vehicles of the red-team tests share (vehicle.py, chute_vehicle.py): their
command line, the UDP link to the guard (or to a ground station directly), the state they stream
(HEARTBEAT with the armed flag and custom mode, GLOBAL_POSITION_INT, VFR_HUD), the parameters
they report on connection, and the log of every datagram received, which the tests assert on.
"""
import argparse
import math
import os
import socket
import time

os.environ["MAVLINK20"] = "1"
from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

C = mavlink


def arguments(description):
    """The common command line; the caller adds its own options before parsing."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--port", type=int, required=True, help="UDP port on 127.0.0.1 the peer sends to")
    p.add_argument("--summary", required=True)
    p.add_argument("--stop-file", required=True, help="stop as soon as this file exists")
    p.add_argument("--duration", type=float, default=60.0)
    p.add_argument("--armed", type=int, default=1)
    p.add_argument("--mode", type=int, default=5, help="custom_mode (ArduCopter 5 = LOITER, 3 = AUTO)")
    p.add_argument("--alt", type=float, default=50.0, help="metres above home")
    p.add_argument("--climb", type=float, default=2.0, help="m/s, positive up")
    p.add_argument("--param", action="append", default=[], help="NAME=VALUE (repeatable), reported on connect")
    return p


def parameters(a):
    """The `--param NAME=VALUE` pairs as a dict (insertion order is the report order)."""
    params = {}
    for kv in a.param:
        k, v = kv.split("=", 1)
        params[k] = float(v)
    return params


def finite(x):
    """A float as JSON can hold it (NaN and infinities as text)."""
    return x if not isinstance(x, float) or math.isfinite(x) else repr(x)


class Link:
    """System 1, component 1 on a UDP port: answers go to whoever sent last."""

    def __init__(self, a):
        self.a = a
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", a.port))
        self.sock.settimeout(0.02)
        self.mav = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
        self.mav.robust_parsing = True
        self.peer = None
        self.deadline = time.time() + a.duration
        self.last_state = 0.0
        self.summary = {"datagrams": [], "messages": [], "bad_data": 0}

    def send(self, msg):
        if self.peer is not None:
            self.sock.sendto(msg.pack(self.mav), self.peer)
            self.mav.seq = (self.mav.seq + 1) % 256

    def running(self):
        return time.time() < self.deadline and not os.path.exists(self.a.stop_file)

    def state_due(self, now):
        """Whether the 10 Hz state is due (and mark it sent)."""
        if now - self.last_state > 0.1:
            self.last_state = now
            return True
        return False

    def heartbeat(self, mode):
        base_mode = C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | (C.MAV_MODE_FLAG_SAFETY_ARMED if self.a.armed else 0)
        self.send(self.mav.heartbeat_encode(C.MAV_TYPE_QUADROTOR, C.MAV_AUTOPILOT_ARDUPILOTMEGA, base_mode, mode,
                                            C.MAV_STATE_ACTIVE))

    def position(self, now):
        a = self.a
        self.send(self.mav.global_position_int_encode(int(now * 1000) & 0xFFFFFFFF, 0, 0, int(a.alt * 1000),
                                                      int(a.alt * 1000), 0, 0, int(-a.climb * 100), 0))
        self.send(self.mav.vfr_hud_encode(0.0, 0.0, 0, 50, a.alt, a.climb))

    def param_value(self, params, name):
        names = list(params)
        self.send(self.mav.param_value_encode(name.encode(), params[name], C.MAV_PARAM_TYPE_REAL32, len(names),
                                              names.index(name)))

    def receive(self, fields=None):
        """The messages of the next datagram (logged with its bytes), or [] after 20 ms; `fields`
        turns a message into the fields logged with it."""
        try:
            data, frm = self.sock.recvfrom(65535)
        except socket.timeout:
            return []
        self.peer = frm
        self.summary["datagrams"].append(data.hex())
        out = []
        for msg in self.mav.parse_buffer(data) or []:
            t = msg.get_type()
            if t == "BAD_DATA":
                self.summary["bad_data"] += 1
                continue
            entry = {"type": t, "src": [msg.get_srcSystem(), msg.get_srcComponent()]}
            if fields is not None:
                entry["fields"] = fields(msg)
            self.summary["messages"].append(entry)
            out.append(msg)
        return out

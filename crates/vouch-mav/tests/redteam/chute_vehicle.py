#!/usr/bin/env python3
"""A scripted ArduCopter-like vehicle (system 1, component 1) with a parachute, for the red-team
tests of the routes to the parachute release.

It models what ArduPilot does with each message that can release the parachute, as read in the
ArduPilot sources (docs/mav-monitor.md, "Effects and their routes", cites them):

* MAV_CMD_DO_PARACHUTE: the action is `(uint16_t)param1`; RELEASE is a manual release
  (Copter::parachute_manual_release: parachute enabled, not landed, not below CHUTE_ALT_MIN);
* MAV_CMD_DO_AUX_FUNCTION: param2 above 2 is denied, function 22 (parachute release) or 23
  (3-position switch) in position 2 (high) is a manual release;
* DO_SET_SERVO / DO_REPEAT_SERVO are refused on an output that has a function other than none,
  manual, RC pass-through (AP_ServoRelayEvents), so the parachute servo (function 27) cannot be
  driven;
* DO_SET_RELAY / DO_REPEAT_RELAY: with `--version 4.4` any relay with a pin (0..5) is driven,
  and the relay numbered CHUTE_TYPE fires the parachute; with `--version 4.5` only relays whose
  RELAYn_FUNCTION is 1 (relay) are driven, so the parachute relay (function 3) cannot be;
* RC_CHANNELS_OVERRIDE from system 255 (SYSID_MYGCS): a channel whose RCn_OPTION is 22 or 23
  that moves to the high position (1800 < pwm < 2200) is a manual release;
* missions: MISSION_COUNT / MISSION_WRITE_PARTIAL_LIST then MISSION_REQUEST_INT / MISSION_ITEM(_INT)
  for the mission, fence and rally plans (fence and rally items must be fence or rally points,
  else MAV_MISSION_UNSUPPORTED); a mission runs in AUTO (custom mode 3) entered by SET_MODE,
  MAV_CMD_DO_SET_MODE or MAV_CMD_MISSION_START, from item 1, NAV items taking 0.3 s, DO items at
  once, DO_JUMP jumping; MISSION_SET_CURRENT and MAV_CMD_DO_SET_MISSION_CURRENT move to an item.

A released parachute is what the tests look at: `released` in the summary lists each release
with the route that caused it. Every datagram received is logged too.
"""
import json
import math
import time

from peer import C, Link, arguments, finite, parameters

p = arguments("a scripted ArduCopter with a parachute for the red-team tests of its routes")
p.add_argument("--version", choices=["4.4", "4.5"], default="4.5", help="relay semantics")
a = p.parse_args()
params = parameters(a)

AUTO = 3
NAV_TIME = 0.3
FENCE_CMDS = (5000, 5001, 5002, 5003, 5004)
RALLY_CMDS = (5100,)

link = Link(a)
mav = link.mav
send = link.send
mode = a.mode
missions = {0: [], 1: [], 2: []}
upload = None  # {"type", "next", "end"}
current = 0
nav_started = None
jumps = {}
rc_high = {}
summary = link.summary
summary.update({"released": [], "not_released": [], "servo_set": [], "relay_set": [], "mission": {},
                "modes": [], "current": []})


def param(name, default=0.0):
    return params.get(name, default)


def u16(x):
    return int(x) & 0xFFFF if math.isfinite(x) else -1


def release(route):
    """Copter::parachute_manual_release: enabled, not landed, not below CHUTE_ALT_MIN."""
    if param("CHUTE_ENABLED") == 0:
        summary["not_released"].append([route, "disabled"])
    elif not a.armed or a.alt <= 0:
        summary["not_released"].append([route, "landed"])
    elif param("CHUTE_ALT_MIN") != 0 and a.alt < param("CHUTE_ALT_MIN"):
        summary["not_released"].append([route, "too low"])
    else:
        summary["released"].append(route)


def aux(func, pos, route):
    if pos == 2 and func in (22, 23):
        release(route)


def set_servo(ch, pwm, route):
    func = param("SERVO%d_FUNCTION" % ch)
    if func in (0, 1) or 51 <= func <= 66:
        summary["servo_set"].append([ch, pwm, route])
        return True
    return False  # "ServoRelayEvent: Channel %d is already in use"


def set_relay(num, route):
    if a.version == "4.4":
        if not 0 <= num <= 5:
            return False
        summary["relay_set"].append([num, route])
        if param("CHUTE_TYPE", -1) == num:
            summary["released"].append(route)  # the relay pin fires the parachute, no checks
        return True
    if param("RELAY%d_FUNCTION" % (num + 1)) != 1:
        return False
    summary["relay_set"].append([num, route])
    return True


def do_command(cmd, p1, p2, route):
    """A command, from COMMAND_LONG/INT or a mission item; True when accepted."""
    if cmd == C.MAV_CMD_DO_PARACHUTE:
        action = u16(p1)
        if action == C.PARACHUTE_RELEASE:
            release(route)
        return action in (0, 1, 2)
    if cmd == C.MAV_CMD_DO_AUX_FUNCTION:
        if not p2 <= 2:
            return False
        aux(int(p1) if math.isfinite(p1) else -1, int(p2) if math.isfinite(p2) else -1, route)
        return True
    if cmd in (C.MAV_CMD_DO_SET_SERVO, C.MAV_CMD_DO_REPEAT_SERVO):
        return set_servo(int(p1) & 0xFF, p2, route)
    if cmd in (C.MAV_CMD_DO_SET_RELAY, C.MAV_CMD_DO_REPEAT_RELAY):
        return set_relay(int(p1) & 0xFF, route)
    return True


def set_mode(m, why):
    global mode, current, nav_started
    mode = m
    summary["modes"].append([m, why])
    if m == AUTO and current == 0:
        current = 1
        nav_started = None


def set_current(seq, why):
    global current, nav_started
    if 0 <= seq < len(missions[0]):
        current = seq
        nav_started = None
        summary["current"].append([seq, why])
        return True
    return False


def run_mission(now):
    """One step of AUTO: DO items at once, NAV items after NAV_TIME, DO_JUMP jumps."""
    global current, nav_started
    items = missions[0]
    if mode != AUTO or not a.armed or current >= len(items) or current == 0:
        return
    it = items[current]
    cmd = it["command"]
    route = "mission item %d" % current
    if cmd == C.MAV_CMD_DO_JUMP:
        target, repeat = int(it["param1"]), int(it["param2"])
        done = jumps.get(current, 0)
        if repeat < 0 or done < repeat:
            jumps[current] = done + 1
            current = target
        else:
            current += 1
        nav_started = None
    elif cmd <= 95:  # NAV commands (MAV_CMD_NAV_LAST = 95)
        if nav_started is None:
            nav_started = now
        elif now - nav_started >= NAV_TIME and cmd != C.MAV_CMD_NAV_LOITER_UNLIM:
            send(mav.mission_item_reached_encode(current))
            current += 1
            nav_started = None
    else:
        do_command(cmd, it["param1"], it["param2"], route)
        current += 1
    send(mav.mission_current_encode(current))


def request(seq, mtype):
    send(mav.mission_request_int_encode(peer_ids[0], peer_ids[1], seq, mtype))


def ack(mtype, result):
    send(mav.mission_ack_encode(peer_ids[0], peer_ids[1], result, mtype))


def on_item(msg):
    global upload
    mtype = getattr(msg, "mission_type", 0)
    if upload is None or upload["type"] != mtype or msg.seq != upload["next"]:
        return
    cmd = msg.command
    if (mtype == 1 and cmd not in FENCE_CMDS) or (mtype == 2 and cmd not in RALLY_CMDS):
        ack(mtype, C.MAV_MISSION_UNSUPPORTED)
        upload = None
        return
    item = {"command": cmd, "param1": msg.param1, "param2": msg.param2, "seq": msg.seq}
    items = missions[mtype]
    while len(items) <= msg.seq:
        items.append({"command": C.MAV_CMD_NAV_WAYPOINT, "param1": 0.0, "param2": 0.0, "seq": len(items)})
    items[msg.seq] = item
    if msg.seq >= upload["end"]:
        ack(mtype, C.MAV_MISSION_ACCEPTED)
        upload = None
    else:
        upload["next"] += 1
        request(upload["next"], mtype)


def handle(msg):
    global upload, peer_ids
    t = msg.get_type()
    src = (msg.get_srcSystem(), msg.get_srcComponent())
    if t in ("COMMAND_LONG", "COMMAND_INT") and msg.target_system in (0, 1):
        peer_ids = src
        cmd, p1, p2 = msg.command, msg.param1, msg.param2
        route = "%s %d" % (t, cmd)
        if cmd == C.MAV_CMD_MISSION_START:
            set_mode(AUTO, route)
            ok = True
        elif cmd == C.MAV_CMD_DO_SET_MISSION_CURRENT:
            ok = set_current(int(p1), route)
        elif cmd == C.MAV_CMD_DO_SET_MODE:
            set_mode(int(p2), route)
            ok = True
        else:
            ok = do_command(cmd, p1, p2, route)
        send(mav.command_ack_encode(cmd, C.MAV_RESULT_ACCEPTED if ok else C.MAV_RESULT_FAILED, 0, 0, src[0], src[1]))
    elif t == "SET_MODE":
        set_mode(msg.custom_mode, "SET_MODE")
    elif t == "MISSION_SET_CURRENT":
        set_current(msg.seq, "MISSION_SET_CURRENT")
    elif t == "MISSION_COUNT":
        peer_ids = src
        mtype = msg.mission_type
        missions[mtype] = missions[mtype][:msg.count]
        if msg.count == 0:
            ack(mtype, C.MAV_MISSION_ACCEPTED)
            return
        upload = {"type": mtype, "next": 0, "end": msg.count - 1}
        request(0, mtype)
    elif t == "MISSION_WRITE_PARTIAL_LIST":
        peer_ids = src
        mtype = msg.mission_type
        if not 0 <= msg.start_index <= msg.end_index < max(len(missions[mtype]), 1):
            ack(mtype, C.MAV_MISSION_ERROR)
            return
        upload = {"type": mtype, "next": msg.start_index, "end": msg.end_index}
        request(msg.start_index, mtype)
    elif t in ("MISSION_ITEM_INT", "MISSION_ITEM"):
        on_item(msg)
    elif t == "MISSION_ACK" and upload is not None:
        upload = None  # the GCS (or a guard in its name) cancelled the upload
    elif t == "RC_CHANNELS_OVERRIDE" and src[0] == 255:
        for ch in range(1, 17):
            v = getattr(msg, "chan%d_raw" % ch)
            if v in (0, 65535) or (ch > 8 and v == 65534):
                continue
            high = 1800 < v < 2200
            if high and not rc_high.get(ch, False) and param("RC%d_OPTION" % ch) in (22, 23):
                release("RC_CHANNELS_OVERRIDE chan%d" % ch)
            rc_high[ch] = high


peer_ids = (255, 190)
if mode == AUTO:
    current = 1  # already flying a mission: new items are reached from item 1 on
announced = False
while link.running():
    now = time.time()
    if link.state_due(now):
        link.heartbeat(mode)
        link.position(now)
        if link.peer is not None and not announced:
            for name in params:
                link.param_value(params, name)
            announced = True
    run_mission(now)
    for msg in link.receive():
        handle(msg)

summary["mission"] = {str(k): [[i["seq"], i["command"], finite(i["param1"])] for i in v] for k, v in missions.items()}
with open(a.summary, "w") as f:
    json.dump(summary, f)

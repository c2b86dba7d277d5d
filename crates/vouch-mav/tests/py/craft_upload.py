"""Writes a tlog of a mission upload crafted with pymavlink (both directions, MAVLink 2).

Usage: python craft_upload.py OUT.tlog N ACK_AFTER
The vehicle (1/1) requests items 0..ACK_AFTER-1 with MISSION_REQUEST_INT and then sends
MISSION_ACK ACCEPTED; with ACK_AFTER == N this is a correct upload.
"""
import struct
import sys

from pymavlink.dialects.v20 import ardupilotmega as mav2

out, n, ack_after = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
gcs = mav2.MAVLink(None, srcSystem=255, srcComponent=190)
uav = mav2.MAVLink(None, srcSystem=1, srcComponent=1)
t = [1_700_000_000_000_000]
records = []


def emit(link, msg):
    t[0] += 20_000
    records.append(struct.pack(">Q", t[0]) + bytes(msg.pack(link)))
    link.seq = (link.seq + 1) % 256


emit(gcs, mav2.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3))
emit(uav, mav2.MAVLink_heartbeat_message(2, 3, 1, 0, 3, 3))
emit(gcs, mav2.MAVLink_mission_count_message(1, 1, n, 0))
for s in range(ack_after):
    emit(uav, mav2.MAVLink_mission_request_int_message(255, 190, s, 0))
    emit(gcs, mav2.MAVLink_mission_item_int_message(1, 1, s, 3, 16, 0, 1, 0, 0, 0, 0, 473977420 + s, 85455940, 50.0, 0))
emit(uav, mav2.MAVLink_mission_ack_message(255, 190, 0, 0))
with open(out, "wb") as f:
    f.write(b"".join(records))

#!/usr/bin/env python3
"""A vehicle built from MAVSDK 4.1 server plugins (PyPI `mavsdk`, no mavsdk_server binary):
MissionRawServer accepts uploads; the summary records how many items each upload delivered.
Runs at most --duration seconds."""
import argparse
import json
import threading
import time

from mavsdk import ComponentType, Configuration, Mavsdk
from mavsdk.plugins.mission_raw_server.mission_raw_server import MissionRawServer

p = argparse.ArgumentParser()
p.add_argument("--url", required=True, help="MAVSDK connection url, e.g. udpin://127.0.0.1:14560")
p.add_argument("--duration", type=float, default=30.0)
p.add_argument("--summary", required=True)
p.add_argument("--exit-after-upload", action="store_true")
a = p.parse_args()

cfg = Configuration.create_with_component_type(ComponentType.AUTOPILOT)
sdk = Mavsdk(cfg)
res = sdk.add_any_connection(a.url)
server = MissionRawServer(sdk.server_component())
uploads = []
got = threading.Event()


def on_mission(result, plan, _ud):
    uploads.append({"result": str(result.name), "items": len(plan.mission_items)})
    got.set()


server.subscribe_incoming_mission(on_mission)
print("mavsdk vehicle ready:", res, flush=True)
deadline = time.time() + a.duration
while time.time() < deadline:
    if got.wait(0.1) and a.exit_after_upload:
        time.sleep(1.0)
        break
with open(a.summary, "w") as f:
    json.dump({"uploads": uploads}, f)

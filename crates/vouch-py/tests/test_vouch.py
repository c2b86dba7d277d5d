"""The Python package `vouch` as a nav2 user's script calls it: maps, plans, checks, inflation,
body checks, bags, suites and campaign shards. Results are compared with the `vouch` command line (the binary
built by `cargo test`/`cargo build --release`, or VOUCH_BIN) on the same inputs, and with the
nav2 maps of ../shared when present (required when VOUCH_REQUIRE_SHARED=1)."""
import hashlib
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import vouch

REPO = pathlib.Path(__file__).resolve().parents[3]
EXAMPLES = REPO / "examples" / "navfn"
SHARED = REPO.parent / "shared" / "navfn"


def vouch_bin():
    path = pathlib.Path(os.environ.get("VOUCH_BIN", REPO / "target" / "release" / "vouch"))
    if not path.exists():
        if os.environ.get("VOUCH_REQUIRE_PEERS") == "1":
            pytest.fail(f"{path} is required here but missing")
        pytest.skip(f"{path} not built")
    return path


def cli(*args):
    out = subprocess.run([str(vouch_bin()), *map(str, args)], capture_output=True, text=True, cwd=REPO)
    return out.returncode, out.stdout


def shared():
    if not (SHARED / "SEMANTICS.md").exists():
        if os.environ.get("VOUCH_REQUIRE_SHARED") == "1":
            pytest.fail(f"{SHARED} is required here but missing")
        pytest.skip(f"{SHARED} not found")
    return SHARED


def test_load_map_reads_the_example_as_map_server_does():
    m = vouch.load_map(EXAMPLES / "warehouse.yaml")
    assert m["costmap"].dtype == np.uint8 and m["costmap"].shape == (80, 100)
    assert m["occupancy"].dtype == np.int8
    assert m["resolution"] == 0.1 and m["origin"] == (0.0, 0.0, 0.0)
    assert set(np.unique(m["costmap"])) <= {0, 254, 255}
    # nav2's static layer: occupied 100 -> 254, free 0 -> 0, unknown -1 -> 255
    assert np.all((m["occupancy"] == 100) == (m["costmap"] == 254))


def test_load_map_errors_are_located():
    with pytest.raises(OSError):
        vouch.load_map(EXAMPLES / "no_such_map.yaml")


def test_bad_yaml_is_a_value_error_with_the_line(tmp_path):
    bad = tmp_path / "m.yaml"
    bad.write_text("image: m.pgm\nresolution: fast\n")
    with pytest.raises(ValueError, match=r"m.yaml:2: resolution must be a number"):
        vouch.load_map(bad)


def test_plan_equals_the_cli():
    m = vouch.load_map(EXAMPLES / "warehouse.yaml")
    r = vouch.plan(m["costmap"], (1.0, 1.0), (8.5, 6.5), resolution=m["resolution"],
                   origin=m["origin"][:2], goal_yaw=1.5)
    assert r["status"] == "OK" and r["violations"] == []
    code, out = cli("navfn", "plan", EXAMPLES / "warehouse.yaml", "--start", "1,1", "--goal",
                    "8.5,6.5", "--goal-yaw", "1.5", "--json")
    assert code == 0
    doc = json.loads(out)
    expected = np.array([[p["x"], p["y"], p["z"]] + p["orientation"] for p in doc["poses"]])
    assert r["poses"].shape == expected.shape
    assert np.array_equal(r["poses"], expected), "bit-identical poses"
    assert r["potential"].shape == (80, 100) and r["potential"].dtype == np.float32


def test_plan_in_cells_with_nav2_parameters():
    costmap = np.zeros((20, 30), dtype=np.uint8)
    costmap[5:15, 12] = 254
    r = vouch.plan(costmap, (2, 10), (25, 10), cells=True, use_astar=True,
                   use_final_approach_orientation=True, max_cycles_factor=6)
    assert r["status"] == "OK"
    first, last = r["poses"][0], r["poses"][-1]
    assert tuple(first[:2]) == (2.0, 10.0) and tuple(last[:2]) == (25.0, 10.0)
    # final approach orientation: the last pose faces along the last step (a unit quaternion)
    assert abs(last[5] ** 2 + last[6] ** 2 - 1.0) < 1e-12
    assert all(costmap[int(round(y)), int(round(x))] != 254 for x, y in r["poses"][:, :2])
    with pytest.raises(ValueError, match="tolerance"):
        vouch.plan(costmap, (2, 10), (25, 10), cells=True, tolerance=-1.0)


def test_check_finds_a_tampered_potential():
    costmap = np.zeros((20, 30), dtype=np.uint8)
    r = vouch.plan(costmap, (2, 10), (25, 10), cells=True)
    args = (r["navfn_costs"], r["potential"], r["navfn_path"], r["navfn_start"], r["navfn_goal"])
    assert vouch.check(*args) == []
    pot = r["potential"].copy()
    x, y = r["navfn_start"]
    pot[y, x + 1] = 1e10  # unreach a neighbour of the path's start
    pot[10, 15] = 0.0     # a second zero-potential cell: Progress fails around it
    violations = vouch.check(r["navfn_costs"], pot, r["navfn_path"], r["navfn_start"], r["navfn_goal"])
    assert any("Progress" in v for v in violations), violations


def test_check_bag_on_the_example_bag():
    report = vouch.check_bag(EXAMPLES / "warehouse_bag")
    s = report["summary"]
    assert (s["plans"], s["passed"], s["failed"], s["replay_equal"]) == (3, 2, 1, 2)
    failing = report["plans"][2]
    assert any(v["kind"] == "pose_in_obstacle" for v in failing["violations"])
    with pytest.raises(OSError):
        vouch.check_bag(EXAMPLES / "no_such_bag")


def test_run_suite_equals_the_cli():
    test_file = EXAMPLES / "suite" / "field" / "blocks_30x20" / "test.txt"
    lines = vouch.run_suite(test_file, mode="navfn", algo="astar")
    code, out = cli("navfn", "suite", "run", test_file, "--mode", "navfn", "--algo", "astar")
    assert code == 0
    strip = lambda t: [l for l in t.splitlines() if not l.startswith("MAP")]
    assert strip(lines) == strip(out)


def test_campaign_shards_add_up():
    suite = EXAMPLES / "suite"
    whole = vouch.run_campaign_shard(suite, metamorphic=False, optimality=False)
    a = vouch.run_campaign_shard(suite, index=0, count=2, metamorphic=False, optimality=False)
    b = vouch.run_campaign_shard(suite, index=1, count=2, metamorphic=False, optimality=False)
    assert a["cases"] + b["cases"] == whole["cases"] > 0
    with pytest.raises(ValueError):
        vouch.run_campaign_shard(suite, index=2, count=2)


RECTANGLE = "[[0.3,0.25],[0.3,-0.25],[-0.3,-0.25],[-0.3,0.25]]"


def cli_costmap(yaml, tmp_path, *args):
    """The bytes `vouch navfn costmap` writes (raw, row 0 = bottom) and its JSON summary."""
    out = tmp_path / "costmap.bin"
    code, text = cli("navfn", "costmap", yaml, *args, "-o", out, "--json")
    assert code == 0, text
    return out.read_bytes(), json.loads(text)


def test_inflate_costmap_equals_the_cli_byte_for_byte(tmp_path):
    cases = [
        (EXAMPLES / "warehouse.yaml", dict(robot_radius=0.22, cost_scaling_factor=3.0),
         ["--robot-radius", "0.22", "--cost-scaling-factor", "3"]),
        (EXAMPLES / "warehouse.yaml",
         dict(footprint=RECTANGLE, inflation_radius=1.0, cost_scaling_factor=2.5,
              inflate_unknown=True, inflate_around_unknown=True, footprint_padding=0.05),
         ["--footprint", RECTANGLE, "--inflation-radius", "1.0", "--cost-scaling-factor", "2.5",
          "--inflate-unknown", "--inflate-around-unknown", "--footprint-padding", "0.05"]),
        # no robot: a point robot, as the command line
        (EXAMPLES / "warehouse.yaml", dict(inflation_radius=0.3), ["--inflation-radius", "0.3"]),
    ]
    if (SHARED / "SEMANTICS.md").exists() or os.environ.get("VOUCH_REQUIRE_SHARED") == "1":
        # a 0.5 m square without padding on a 0.05 m map: cells 5 cells from an obstacle are
        # inscribed at 0.05 m but not at the map message's float 0.05000000074505806
        square = "[[0.25,0.25],[0.25,-0.25],[-0.25,-0.25],[-0.25,0.25]]"
        cases.append((shared() / "nav2_maps" / "map_circular.yaml",
                      dict(footprint=square, footprint_padding=0.0, cost_scaling_factor=3.0),
                      ["--footprint", square, "--footprint-padding", "0", "--cost-scaling-factor", "3"]))
    for yaml, kwargs, args in cases:
        m = vouch.load_map(yaml)
        got = vouch.inflate_costmap(m["costmap"], resolution=m["resolution"], **kwargs)
        assert got.dtype == np.uint8 and got.shape == m["costmap"].shape
        expected, summary = cli_costmap(yaml, tmp_path, *args)
        assert got.tobytes() == expected, (yaml.name, args)
        assert hashlib.sha256(got.tobytes()).hexdigest() == summary["sha256"]
        assert np.count_nonzero(got != m["costmap"]) > 50, "something was inflated"


def test_inflate_costmap_rejects_bad_robots_with_codes():
    costmap = np.zeros((10, 10), dtype=np.uint8)
    with pytest.raises(ValueError, match=r"navfn::E121: robot_radius = -0.3 is out of range"):
        vouch.inflate_costmap(costmap, robot_radius=-0.3)
    with pytest.raises(ValueError, match=r"navfn::E120: footprint `\[\[1,1\],\[1,-1\]\]`"):
        vouch.inflate_costmap(costmap, footprint="[[1,1],[1,-1]]")
    with pytest.raises(ValueError, match="not both"):
        vouch.inflate_costmap(costmap, robot_radius=0.3, footprint=RECTANGLE)
    with pytest.raises(ValueError, match=r"navfn::E121: cost_scaling_factor = -1"):
        vouch.inflate_costmap(costmap, robot_radius=0.3, cost_scaling_factor=-1.0)
    with pytest.raises(ValueError, match=r"navfn::E121: resolution = 0"):
        vouch.inflate_costmap(costmap, robot_radius=0.3, resolution=0.0)
    with pytest.raises(ValueError, match=r"navfn::E121: footprint_padding = -0.1"):
        vouch.inflate_costmap(costmap, robot_radius=0.3, footprint_padding=-0.1)


def body_of(r):
    """The keys of check_body's dict that `vouch navfn plan --json` prints under `body`."""
    return {k: r[k] for k in ("motions", "min", "window", "violations")}


def test_check_body_equals_the_cli_plan():
    compared = 0
    maps = [(EXAMPLES / "warehouse.yaml", [((1.0, 1.0), (8.5, 6.5))])]
    if (SHARED / "SEMANTICS.md").exists() or os.environ.get("VOUCH_REQUIRE_SHARED") == "1":
        lines = (shared() / "suite_ros" / "map_circular" / "test_world.txt").read_text().splitlines()
        ends = [tuple(float(t) for t in l.split()) for l in lines[3:] if len(l.split()) == 4][-8:]
        maps.append((SHARED / "nav2_maps" / "map_circular.yaml",
                     [((e[0], e[1]), (e[2], e[3])) for e in ends]))
    contacts = 0
    for yaml, plans in maps:
        m = vouch.load_map(yaml)
        for robot, args in [(dict(robot_radius=0.3), ["--robot-radius", "0.3"]),
                            (dict(footprint=RECTANGLE), ["--footprint", RECTANGLE])]:
            # an inflation radius below the robot's: plans graze the walls
            for (x0, y0), (x1, y1) in plans:
                code, out = cli("navfn", "plan", yaml, "--start", f"{x0!r},{y0!r}", "--goal",
                                f"{x1!r},{y1!r}", *args, "--inflation-radius", "0.1",
                                "--cost-scaling-factor", "3", "--json")
                if code not in (0, 3):
                    continue  # an end the command line refuses, or no plan
                doc = json.loads(out)
                # the command line's poses, as (x, y, yaw) and as poses with quaternions
                xyyaw = np.array([[p["x"], p["y"], p["yaw"]] for p in doc["poses"]])
                quat = np.array([[p["x"], p["y"], p["z"]] + p["orientation"] for p in doc["poses"]])
                kw = dict(resolution=m["resolution"], origin=m["origin"][:2], **robot)
                for poses in (xyyaw, quat):
                    r = vouch.check_body(m["costmap"], poses, **kw)
                    assert body_of(r) == doc["body"], (yaml.name, args, x0, y0)
                    assert r["ok"] == (doc["body"]["violations"] == [])
                    assert r["contacts"] == len(doc["body"]["violations"])
                # the whole pipeline from Python: inflate, plan, check
                inflated = vouch.inflate_costmap(m["costmap"], resolution=m["resolution"],
                                                 inflation_radius=0.1, cost_scaling_factor=3.0,
                                                 **robot)
                p = vouch.plan(inflated, (x0, y0), (x1, y1), resolution=m["resolution"],
                               origin=m["origin"][:2])
                assert np.array_equal(p["poses"], quat)
                assert body_of(vouch.check_body(m["costmap"], p["poses"], **kw)) == doc["body"]
                contacts += r["contacts"]
                compared += 1
    assert compared >= 2
    assert contacts > 0, "no plan grazed a wall: the comparison would prove little"


def test_check_body_finds_a_wall_and_clears_the_open_side():
    # 40×30 cells of 0.1 m from (−1, −0.5); a wall in column 20 (x ∈ [1.0, 1.1]) over rows 0–19
    costmap = np.zeros((30, 40), dtype=np.uint8)
    costmap[0:20, 20] = 254
    kw = dict(resolution=0.1, origin=(-1.0, -0.5), robot_radius=0.2)
    # across the wall at y = 0.5 in steps of 0.25 m: the segments from x = 0.75, 1.0 and 1.25
    # reach into [1.0, 1.1] (the one from 0.5 stops 0.05 m short, the one from 1.5 is 0.2 m past)
    across = np.array([[0.25 * i, 0.5, 0.0] for i in range(9)])
    r = vouch.check_body(costmap, across, **kw)
    assert (r["ok"], r["contacts"], r["motions"], r["min_clearance"]) == (False, 3, 9, 0.0)
    assert [v["pose"] for v in r["violations"]] == [3, 4, 5]
    assert all(v["cell"][0] == 20 and v["cell"][1] < 20 for v in r["violations"])
    # beside it at x = 0: 1.0 m to the wall's face, 0.8 m beyond the disc
    beside = np.array([[0.0, 0.25 * i, np.pi / 2] for i in range(5)])
    r = vouch.check_body(costmap, beside, **kw)
    assert r["ok"] and r["contacts"] == 0 and r["violations"] == []
    assert abs(r["min_clearance"] - 0.8) < 1e-12 and r["min"]["cell"][0] == 20
    # the rectangle facing +y: its side, 0.25 m from its centre, 0.75 m from the wall
    r = vouch.check_body(costmap, beside, resolution=0.1, origin=(-1.0, -0.5), footprint=RECTANGLE)
    assert r["ok"] and abs(r["min_clearance"] - 0.75) < 1e-12
    # nothing within a 0.5 m window
    r = vouch.check_body(costmap, beside, window=0.5, **kw)
    assert r["ok"] and r["min"] is None and r["min_clearance"] is None
    with pytest.raises(ValueError, match="no robot_radius or footprint"):
        vouch.check_body(costmap, beside, resolution=0.1)
    with pytest.raises(ValueError, match=r"navfn::E121: robot_radius = -1"):
        vouch.check_body(costmap, beside, robot_radius=-1.0)
    with pytest.raises(ValueError, match=r"navfn::E120"):
        vouch.check_body(costmap, beside, footprint="[[0,0],[1,x]]")
    with pytest.raises(ValueError, match=r"n×3 \(x, y, yaw\) or n×7, not n×2"):
        vouch.check_body(costmap, beside[:, :2], **kw)
    with pytest.raises(ValueError, match=r"pose 1 \(NaN, 0.25"):
        bad = beside.copy()
        bad[1, 0] = np.nan
        vouch.check_body(costmap, bad, **kw)
    with pytest.raises(ValueError, match=r"window -1"):
        vouch.check_body(costmap, beside, window=-1.0, **kw)


def test_nav2_maps_load_and_plan_like_the_cli():
    root = shared()
    compared = 0
    for name, folder in [("empty_room.yaml", "empty_room"), ("keepout_mask.yaml", "keepout_mask"),
                         ("map_circular.yaml", "map_circular"), ("speed_mask.yaml", "speed_mask")]:
        m = vouch.load_map(root / "nav2_maps" / name)
        lines = (root / "suite_ros" / folder / "test_world.txt").read_text().splitlines()[-3:]
        for line in lines:
            x0, y0, x1, y1 = (float(t) for t in line.split())
            code, out = cli("navfn", "plan", root / "nav2_maps" / name, "--start", f"{x0!r},{y0!r}",
                            "--goal", f"{x1!r},{y1!r}", "--json")
            if code != 0:
                continue  # an end in an obstacle of the static layer: the CLI refuses it
            r = vouch.plan(m["costmap"], (x0, y0), (x1, y1), resolution=m["resolution"],
                           origin=m["origin"][:2])
            doc = json.loads(out)
            expected = np.array([[p["x"], p["y"], p["z"]] + p["orientation"] for p in doc["poses"]])
            assert np.array_equal(r["poses"], expected), name
            compared += 1
    assert compared >= 4


def test_the_readme_python_example_runs():
    out = subprocess.run([sys.executable, str(EXAMPLES / "plan_warehouse.py")], capture_output=True,
                         text=True, cwd=REPO, check=True).stdout
    assert out.startswith("OK: 181 poses, last (8.500, 6.500)") and "0 violations" in out

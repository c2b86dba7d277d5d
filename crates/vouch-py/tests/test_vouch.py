"""The Python package `vouch` as a nav2 user's script calls it: maps, plans, checks, bags,
suites and campaign shards. Results are compared with the `vouch` command line (the binary
built by `cargo test`/`cargo build --release`, or VOUCH_BIN) on the same inputs, and with the
nav2 maps of ../shared when present (required when VOUCH_REQUIRE_SHARED=1)."""
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

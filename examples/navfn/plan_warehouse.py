"""Plans across the bundled warehouse map with the Python package and checks the plan.
   pip install ./crates/vouch-py && python3 examples/navfn/plan_warehouse.py"""
import sys

import vouch

m = vouch.load_map(sys.argv[1] if len(sys.argv) > 1 else "examples/navfn/warehouse.yaml")
r = vouch.plan(m["costmap"], (1.0, 1.0), (8.5, 6.5), resolution=m["resolution"],
               origin=m["origin"][:2], use_final_approach_orientation=True)
x, y, _, _, _, qz, qw = r["poses"][-1]
print(f"{r['status']}: {len(r['poses'])} poses, last ({x:.3f}, {y:.3f}) facing qz={qz:.4f} qw={qw:.4f}, "
      f"{len(r['violations'])} violations; potential {r['potential'].shape}")

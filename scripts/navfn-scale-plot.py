#!/usr/bin/env python3
"""Plot the scale rows of `vouch navfn bench --scale … --oracle CMD --json` (docs/navfn-core.md).

usage: navfn-scale-plot.py BENCH.json OUT.png

Needs matplotlib (not used by any test). Left: planning time per plan against map size (median
of the passes), right: peak resident-set growth over the process start against map size, and
a third panel: time against explored cells on one map. vouch solid, the oracle
dashed.
"""
import json
import re
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = json.load(open(sys.argv[1]))
size_re = re.compile(r"^scale (\S+) (\d+)x\d+$")
dist_re = re.compile(r"^scale (\S+) (\d+)x\d+ d=(\d+)$")

by_size, by_cells = {}, {}
for r in rows:
    m = size_re.match(r["workload"])
    if m:
        by_size.setdefault(m.group(1), []).append((int(m.group(2)), r))
    m = dist_re.match(r["workload"])
    if m:
        by_cells.setdefault(m.group(1), []).append((r["count"], r))

fig, (ax_t, ax_m, ax_e) = plt.subplots(1, 3, figsize=(15, 4.6))
colors = {"navfn-dijkstra": "tab:blue", "navfn-astar": "tab:orange", "paper": "tab:green"}


def med(r, side):
    return statistics.median(r[side]) if r[side] else None


def growth_mb(r, side):
    peak, start = r.get(f"{side}_peak_rss_kb"), r.get(f"{side}_start_rss_kb")
    if peak is None or start is None:
        return None
    return (peak - start) / 1024.0


for mode, pts in sorted(by_size.items()):
    pts.sort(key=lambda p: p[0])
    cells = [n * n for n, _ in pts]
    c = colors.get(mode, None)
    for side, style in (("vouch", "-o"), ("oracle", "--s")):
        t = [med(r, side) for _, r in pts]
        if all(v is not None for v in t):
            ax_t.loglog(cells, t, style, color=c, label=f"{side} {mode}")
        m = [growth_mb(r, side) for _, r in pts]
        if all(v is not None for v in m):
            ax_m.loglog(cells, m, style, color=c, label=f"{side} {mode}")

for mode, pts in sorted(by_cells.items()):
    pts.sort(key=lambda p: p[0])
    c = colors.get(mode, None)
    for side, style in (("vouch", "-o"), ("oracle", "--s")):
        t = [med(r, side) for _, r in pts]
        if all(v is not None for v in t):
            ax_e.semilogx([max(n, 1) for n, _ in pts], t, style, color=c, label=f"{side} {mode}")

ax_t.set(xlabel="map cells (random costs, corner to corner)", ylabel="ms per plan (median)",
         title="planning time against map size")
ax_m.set(xlabel="map cells", ylabel="MB above process start (peak RSS)",
         title="peak memory against map size")
ax_e.set(xlabel="explored cells (cases of growing length, one map)", ylabel="ms per plan (median)",
         title="planning time against explored cells")
for ax in (ax_t, ax_m, ax_e):
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)

#!/usr/bin/env python3
"""A NavFn verification campaign on a Dask distributed cluster, through the `vouch` CLI.

Every shard `I/N` is one Dask task that runs `vouch navfn campaign SUITE --shard I/N --json`
on a worker and returns the shard's JSON report; the driver gathers the reports, writes them to
`OUT/shard-I.json` and joins them with `vouch navfn report merge` (strict: a missing, duplicated
or inconsistent shard fails the run). With `--compare-single` it also runs the whole suite in
one process (as one more task) and checks that the merged report says exactly what the single
run says (every field but `shards` and `runs`, which name the shards and their timings).

The workers run the `vouch` given by `--vouch` on the suite path given: on a real cluster both
must exist at the same paths on every worker (a shared file system or the same image).

    dask_campaign.py SUITE --shards 8 --local-workers 2 --out reports/ --compare-single
    dask_campaign.py SUITE --shards 64 --scheduler tcp://head:8786 --vouch /opt/vouch/bin/vouch \\
        -- --mode navfn --algo dijkstra

With `--inflation`, the positional argument is a map and every task runs
`vouch navfn inflation MAP --shard I/N --json` (the inflation-radius search, sharded over its
goals); the reports are joined with `vouch navfn inflation --merge`, and `--compare-single`
checks that the merged smallest safe radius and failing radius equal one unsharded run's:

    dask_campaign.py map.yaml --inflation --shards 8 --compare-single -- --robot-radius 0.3

Everything after `--` is passed to every `vouch navfn campaign` unchanged. Exit status: 0 when
the merged report has no failures (and equals the single run when asked), 3 when the campaign
found failures, 1 when the merged and single reports differ, 2 on a usage or run error.
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable, NamedTuple

# What a report says about its shards and timings: the only fields a merged report and a
# single run may differ in.
RUN_FIELDS = ("shards", "runs")

# `vouch` exit statuses that still carry a report: 0 ok, 3 findings.
REPORT_STATUSES = (0, 3)


def run_shard(vouch, suite, index, count, extra, threads, command):
    """One Dask task: run one shard (`count` 1 = the whole suite) and return its report text."""
    cmd = [vouch, "-q", "navfn", command, suite, "--json"]
    if count > 1:
        cmd += ["--shard", f"{index}/{count}"]
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    done = subprocess.run(cmd + list(extra), capture_output=True, text=True, env=env, check=False)
    if done.returncode not in REPORT_STATUSES:
        raise RuntimeError(f"{' '.join(cmd)} exited {done.returncode}: {done.stderr.strip()}")
    return done.stdout


def results_of(report):
    """A report without the fields that name shards and timings."""
    return {k: v for k, v in report.items() if k not in RUN_FIELDS}


def first_difference(a, b, path="report"):
    """The first path at which two JSON values differ, or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k}: present on one side only"
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} vs {len(b)} elements"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path}: {a!r} vs {b!r}"


def connect(args):
    """A Dask client: to the scheduler given, or to a new local cluster of worker processes."""
    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        return Client(args.scheduler), None
    cluster = LocalCluster(
        n_workers=args.local_workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
    )
    return Client(cluster), cluster


class Job(NamedTuple):
    """What differs between the sharded commands."""

    task: str         # the shard tasks' names on the cluster: TASK-I-of-N
    single_task: str  # the single run's task name
    stem: str         # the shard files: OUT/STEM-I.json
    merge_name: str   # the merge, as its errors name it
    merge_args: Callable[[Path, list], list]  # `vouch navfn` arguments merging files into out


JOBS = {
    "campaign": Job(
        "navfn-shard", "navfn-single", "shard", "report merge",
        lambda out, files: ["report", "merge", "--json", "-o", str(out), *map(str, files)]),
    "inflation": Job(
        "navfn-inflation", "navfn-inflation-single", "inflation", "inflation --merge",
        lambda out, files: ["inflation", "--json", "-o", str(out), "--merge", *map(str, files)]),
}


def merge(vouch, job, files, out):
    """The job's merge of the shard files into `out`; the merged report."""
    cmd = [vouch, "-q", "navfn", *job.merge_args(out, files)]
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if done.returncode not in REPORT_STATUSES:
        raise RuntimeError(f"{job.merge_name} exited {done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def run_sharded(args, extra, command):
    """Fan the shards of `vouch navfn COMMAND` out as Dask tasks (with --compare-single, one
    unsharded run as one more task), gather them into OUT/STEM-I.json and merge those into
    OUT/merged.json; the single run's report goes to OUT/single.json. Returns the merged report
    and the single run's report text (None when not asked)."""
    job = JOBS[command]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    client, cluster = connect(args)
    try:
        futures = [
            client.submit(run_shard, args.vouch, args.suite, i, args.shards, extra, args.threads,
                          command, key=f"{job.task}-{i}-of-{args.shards}", pure=False,
                          retries=args.retries)
            for i in range(args.shards)
        ]
        single = None
        if args.compare_single:
            single = client.submit(run_shard, args.vouch, args.suite, 0, 1, extra, args.threads,
                                   command, key=job.single_task, pure=False, retries=args.retries)
        texts = client.gather(futures)
        single_text = single.result() if single is not None else None
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    files = []
    for i, text in enumerate(texts):
        f = out / f"{job.stem}-{i}.json"
        f.write_text(text)
        files.append(f)
    merged = merge(args.vouch, job, files, out / "merged.json")
    if single_text is not None:
        (out / "single.json").write_text(single_text)
    return merged, single_text


def campaign(args, extra):
    """Fan the shards out, gather, merge, and (when asked) compare with one unsharded run."""
    began = time.monotonic()
    merged, single_text = run_sharded(args, extra, "campaign")
    summary = {
        "shards": args.shards,
        "cases": merged["cases"],
        "maps": len(merged["suite"]["maps"]),
        "content": merged["suite"]["content"],
        "seconds": round(time.monotonic() - began, 2),
    }
    status = 3 if failures(merged) else 0
    if single_text is not None:
        diff = first_difference(results_of(merged), results_of(json.loads(single_text)))
        summary["equal_to_single"] = diff is None
        if diff:
            summary["first_difference"] = diff
            status = 1
    print(json.dumps(summary))
    return status


def inflation(args, extra):
    """The inflation-radius search: one task per shard of goals, gather, merge, compare."""
    began = time.monotonic()
    merged, single_text = run_sharded(args, extra, "inflation")

    def answer(report):
        cx = report.get("counterexample") or {}
        return [report.get("smallest_safe_radius"), cx.get("inflation_radius")]

    summary = {
        "shards": args.shards,
        "smallest_safe_radius": merged["smallest_safe_radius"],
        "largest_failing_radius": answer(merged)[1],
        "seconds": round(time.monotonic() - began, 2),
    }
    status = 0 if merged["smallest_safe_radius"] is not None else 3
    if single_text is not None:
        same = answer(merged) == answer(json.loads(single_text))
        summary["equal_to_single"] = same
        if not same:
            status = 1
    print(json.dumps(summary))
    return status


def failures(report):
    """Failed checks, exact relations and oracle disagreements of a report."""
    n = 0
    for c in report["categories"].values():
        n += sum(p["fail"] for p in c["checks"].values())
        n += c["oracle"]["fail"]
    return n


def main(argv):
    extra = []
    if "--" in argv:
        cut = argv.index("--")
        argv, extra = argv[:cut], argv[cut + 1:]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("suite", help="suite folder, as the workers see it")
    p.add_argument("--shards", type=int, default=8, help="number of shards N (default 8)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler")
    p.add_argument("--local-workers", type=int, default=2,
                   help="without --scheduler: worker processes of a local cluster (default 2)")
    p.add_argument("--vouch", default="vouch", help="the vouch executable on the workers")
    p.add_argument("--out", default="navfn-campaign", help="folder for the reports")
    p.add_argument("--threads", type=int, default=1,
                   help="threads per shard (RAYON_NUM_THREADS; 0 = vouch's default)")
    p.add_argument("--retries", type=int, default=1, help="Dask retries of a failed shard")
    p.add_argument("--compare-single", action="store_true",
                   help="also run the whole suite in one task and compare")
    p.add_argument("--inflation", action="store_true",
                   help="the positional argument is a map: run the inflation-radius search")
    args = p.parse_args(argv)
    if args.shards < 1:
        p.error("--shards must be at least 1")
    try:
        return inflation(args, extra) if args.inflation else campaign(args, extra)
    except (RuntimeError, OSError, json.JSONDecodeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

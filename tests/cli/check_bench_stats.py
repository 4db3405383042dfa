#!/usr/bin/env python3
"""ctest bench_suite_stats_json: `cmkit bench --suite DIR --stats --json` of a
library that counts the queries' work (CMKIT_QUERY_STATS; the Clang preset of
./dev.sh test builds one) prints valid JSON whose "work per query" object has
every query kind it counts (all but point contents) with its counters, and the
counters say what the queries did (docs/performance.md quotes them).

    check_bench_stats.py CLI SOURCE_DIR WORK_DIR

The suite is the committed sample of lt4's reference queries
(data/reference/lt4/lt4.queries.txt, 60 of each kind) against the bundled
data/maps/lt4/lt4.map, so the test needs only the repository.
"""
import json
import os
import shutil
import subprocess
import sys

# (Point contents are not counted: pointContents() leaves its QueryWork alone.)
KINDS = ("translation", "rotation", "contents", "contacts")
COUNTERS = ("queries", "nodes", "polygons met", "polygons tested", "brushes met", "vertex tests", "edge pairs")


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def main():
    cli, source, work = sys.argv[1:4]
    # DIR/ref/lt4.queries.txt beside DIR/maps -> the bundled maps (bench --suite
    # finds DIR/../maps/*/lt4.map).
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "ref"))
    shutil.copy(os.path.join(source, "data", "reference", "lt4", "lt4.queries.txt"), os.path.join(work, "ref"))
    os.symlink(os.path.join(source, "data", "maps"), os.path.join(work, "maps"))
    run = subprocess.run([cli, "bench", "--suite", os.path.join(work, "ref"), "--repeat", "1", "--stats", "--json"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"exit status {run.returncode}: {run.stderr.strip()}")
    try:
        report = json.loads(run.stdout)
    except json.JSONDecodeError as e:
        fail(f"not JSON ({e}): {run.stdout[:300]}")
    work_per_query = report.get("work per query")
    if not isinstance(work_per_query, dict):
        fail('no "work per query" object')
    for kind in KINDS:
        w = work_per_query.get(kind)
        if w is None:
            fail(f"no work counted for {kind}")
        missing = [c for c in COUNTERS if c not in w]
        if missing:
            fail(f"{kind}: no {', '.join(missing)}")
        # 60 of each kind in the sample; a contents query of a point trace
        # model is a point-contents lookup, not counted (two in the sample).
        expected = 60 - (2 if kind == "contents" else 0)
        if w["queries"] != expected:
            fail(f"{kind}: {w['queries']} queries counted, expected {expected}")
        if any(w[c] < 0 for c in COUNTERS):
            fail(f"{kind}: a negative counter {w}")
    # What the queries must have done: every kind walks nodes and meets
    # polygons; translations, rotations and contacts test polygons (the
    # sample hits the map) and pair edges; position tests meet brushes.
    for kind in KINDS:
        w = work_per_query[kind]
        if not (w["nodes"] > 0 and w["polygons met"] >= w["polygons tested"]):
            fail(f"{kind}: implausible counts {w}")
    for kind in ("translation", "rotation", "contacts"):
        w = work_per_query[kind]
        if not (w["polygons tested"] > 0 and w["vertex tests"] > 0 and w["edge pairs"] > 0):
            fail(f"{kind}: implausible feature tests {w}")
    if not work_per_query["contents"]["brushes met"] > 0:
        fail("contents: no brush met")
    if "pointcontents" in work_per_query:
        fail("point contents counted: update this test and the note on them above")
    print("OK: bench --suite --stats --json counts the work of every kind:",
          ", ".join(f"{k} {work_per_query[k]['polygons tested']:.2f} polygons tested" for k in KINDS))


if __name__ == "__main__":
    main()

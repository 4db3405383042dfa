#!/usr/bin/env python3
"""A/B speed of two cmkit CLIs, one query kind at a time.

    bench/ab.py OLD_CLI NEW_CLI [--suite DIR] [--kinds translation,contacts]
                [--runs 5] [--repeat 10] [--files]

Splits every NAME.queries.txt of the suite (default ../shared/reference) into
one-kind copies in a temporary directory (beside a link to the suite's
../maps, where `cmkit bench --suite` finds the models), then runs
`cmkit bench --suite COPY --repeat N --json` with OLD_CLI and NEW_CLI in
turn, RUNS times, and prints per kind the geometric mean over the files of
old ns / new ns (above 1: NEW_CLI is faster), from the best run of each side,
with the slowest and fastest file (--files: every file).

Both CLIs must have `bench --suite --json` (commits from 2026-11 on); for an
older commit use bench/compare.sh, which reads the text tables. This is the
per-step measure of docs/performance.md: two builds of one machine in one
run. Alternate runs and several of them: on a 2-core VM one file's ratio
moves by a few per cent between runs, the geometric mean by up to about 2.5%
(docs/performance.md): a step of 1% needs repeated runs to show.

--instructions counts instead of timing: each CLI runs each file's queries
of a kind once under valgrind's callgrind (--repeat passes), counting the
instructions inside cmkit::runParsedQueryUnformatted (the query and the
harness's call of it, not the parsing or the model's build), and the ratio
is old / new instructions a query. Deterministic, so one run settles what
timing on a shared VM cannot; but it is not time (cache misses and
mispredicted branches are free there). Slow: a few seconds a file and kind
(--repeat 3 is plenty). Needs valgrind (apt-get install valgrind).

--mispredictions counts the same way the conditional and indirect branches
callgrind's branch model (--branch-sim=yes) mispredicts, a query: old / new
mispredictions. The model is a simple one (two-bit counters, no history),
so it overcounts what a processor's predictor misses, but a branch it finds
unpredictable from the data usually is: on lt4's translations the first
steps that removed such branches showed in time where instruction counts
said nothing (docs/performance.md).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile


def split_suite(suite, kinds, out):
    """One-kind copies of the suite's query files: out/KIND/ref/NAME.queries.txt."""
    names = sorted(f for f in os.listdir(suite) if f.endswith(".queries.txt"))
    if not names:
        sys.exit(f"ab.py: no NAME.queries.txt files in {suite}")
    maps = os.path.abspath(os.path.join(suite, "..", "maps"))
    dirs = {}
    for kind in kinds:
        ref = os.path.join(out, kind, "ref")
        os.makedirs(ref)
        os.symlink(maps, os.path.join(out, kind, "maps"))
        dirs[kind] = ref
    for name in names:
        with open(os.path.join(suite, name), encoding="utf-8") as f:
            lines = f.readlines()
        for kind in kinds:
            mine = [l for l in lines if l.split(" ", 1)[0] == kind]
            if mine:
                with open(os.path.join(dirs[kind], name), "w", encoding="utf-8") as f:
                    f.writelines(mine)
    return dirs


def bench(cli, suite, repeat):
    """{(kind, file): ns} of one `cmkit bench --suite --json` run."""
    out = subprocess.run([cli, "bench", "--suite", suite, "--repeat", str(repeat), "--json"],
                         capture_output=True, text=True, check=True).stdout
    times = {}
    for f in json.loads(out)["files"]:
        for kind, v in f["kinds"].items():
            times[(kind, f["name"])] = v["ns"]
    return times


def callgrind_count(cli, suite, repeat, name, queries, mispredictions=False):
    """Instructions (or mispredicted branches) a query of one file's queries
    (a suite of that file alone)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        sim = ["--branch-sim=yes"] if mispredictions else []
        subprocess.run(["valgrind", "--tool=callgrind", *sim, f"--callgrind-out-file={out}",
                        "--toggle-collect=cmkit::runParsedQueryUnformatted(*",
                        cli, "bench", "--suite", suite, "--repeat", str(repeat)],
                       capture_output=True, text=True, check=True)
        events = []
        with open(out, encoding="utf-8") as f:
            for line in f:
                if line.startswith("events:"):
                    events = line.split()[1:]
                if line.startswith("summary:"):
                    counts = dict(zip(events, (int(v) for v in line.split()[1:])))
                    n = counts.get("Bcm", 0) + counts.get("Bim", 0) if mispredictions else counts["Ir"]
                    return n / (queries * repeat)
    sys.exit(f"ab.py: no count from {cli} on {name}")


def callgrind_counts(a, kinds, dirs, tmp):
    """{cli: {(kind, file): instructions (or mispredictions) a query}}, each file a
    suite of its own."""
    counts = {a.old: {}, a.new: {}}
    for kind in kinds:
        for name in sorted(os.listdir(dirs[kind])):
            one = os.path.join(tmp, "one", kind, name)
            os.makedirs(os.path.join(one, "ref"))
            os.symlink(os.path.join(dirs[kind], "..", "maps"), os.path.join(one, "maps"))
            with open(os.path.join(dirs[kind], name), encoding="utf-8") as f:
                lines = f.readlines()
            with open(os.path.join(one, "ref", name), "w", encoding="utf-8") as f:
                f.writelines(lines)
            file = name[: -len(".queries.txt")]
            for cli in (a.old, a.new):
                counts[cli][(kind, file)] = callgrind_count(cli, os.path.join(one, "ref"), a.repeat, file,
                                                            len(lines), a.mispredictions)
    return counts


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("old")
    p.add_argument("new")
    p.add_argument("--suite", default="../shared/reference")
    p.add_argument("--kinds", default="translation,rotation,contents,pointcontents,contacts")
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--repeat", type=int, default=10)
    p.add_argument("--files", action="store_true", help="print every file's ratio")
    p.add_argument("--instructions", action="store_true",
                   help="count instructions a query under callgrind instead of timing (--runs is ignored)")
    p.add_argument("--mispredictions", action="store_true",
                   help="count mispredicted branches a query in callgrind's branch model instead of timing")
    a = p.parse_args()
    counting = a.instructions or a.mispredictions
    kinds = [k for k in a.kinds.split(",") if k]
    best = {a.old: {}, a.new: {}}
    with tempfile.TemporaryDirectory() as tmp:
        dirs = split_suite(a.suite, kinds, tmp)
        if counting:
            best = callgrind_counts(a, kinds, dirs, tmp)
        else:
            for _ in range(a.runs):
                for kind in kinds:
                    for cli in (a.old, a.new):  # (alternating: drifts of the machine hit both)
                        for key, ns in bench(cli, dirs[kind], a.repeat).items():
                            best[cli][key] = min(best[cli].get(key, math.inf), ns)
    what = "mispredictions" if a.mispredictions else "instructions" if a.instructions else "ns"
    for kind in kinds:
        ratios = sorted((best[a.old][k] / best[a.new][k], k[1]) for k in best[a.old] if k[0] == kind)
        if not ratios:
            continue
        geo = math.exp(sum(math.log(r) for r, _ in ratios) / len(ratios))
        print(f"{kind}: old/new {what} geometric mean {geo:.3f} over {len(ratios)} files; "
              f"min {ratios[0][0]:.3f} ({ratios[0][1]}), max {ratios[-1][0]:.3f} ({ratios[-1][1]})")
        if a.files or counting:
            for r, name in sorted(ratios, key=lambda x: x[1]):
                extra = ""
                if counting:
                    fmt = ".1f" if a.mispredictions else ".0f"
                    extra = f"  ({best[a.old][(kind, name)]:{fmt}} -> {best[a.new][(kind, name)]:{fmt}} a query)"
                print(f"  {name:<36} {r:.3f}{extra}")


if __name__ == "__main__":
    main()

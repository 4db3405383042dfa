#!/usr/bin/env python3
"""Compares `cmkit bench --suite` tables of two builds (bench/compare.sh runs it).

Each table has a header line starting with "file" that names the query kinds,
then one row per reference file with "NS (QUERIES)" per kind, and an
"all files" row. The best (lowest) ns/query over the runs of each side is
kept; the speed-up is old / new.
"""
import argparse
import math
import re
import sys

# A cell: "NS (QUERIES)", or "-" for a kind the file has no queries of.
CELL = re.compile(r"(\d+(?:\.\d+)?) \((\d+)\)|(?<!\S)-(?!\S)")


def parse(path):
    """{file: {kind: ns}} of one table."""
    kinds, rows = None, {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("file "):
                kinds = line.split()[1:]
                continue
            if kinds is None or "(skipped" in line:
                continue
            cells = list(CELL.finditer(line))
            if len(cells) != len(kinds):
                continue
            name = line[: cells[0].start()].strip()
            rows[name] = {k: float(c.group(1)) for k, c in zip(kinds, cells) if c.group(1) is not None}
    if kinds is None:
        sys.exit(f"compare_tables: {path}: no table (no line starting with 'file')")
    return kinds, rows


def best(paths):
    kinds, merged = None, {}
    for p in paths:
        kinds, rows = parse(p)
        for name, cells in rows.items():
            into = merged.setdefault(name, {})
            for k, ns in cells.items():
                into[k] = min(ns, into.get(k, math.inf))
    return kinds, merged


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--old", nargs="+", required=True)
    ap.add_argument("--new", nargs="+", required=True)
    ap.add_argument("--old-name", default="old")
    ap.add_argument("--new-name", default="new")
    a = ap.parse_args()
    kinds, old = best(a.old)
    _, new = best(a.new)
    files = [f for f in old if f in new and f != "all files"]
    print(f"ns/query, best of {len(a.old)} run(s) each; speed-up = {a.old_name} / {a.new_name}")
    summary = []
    for k in kinds:
        print(f"\n{k}")
        print(f"  {'file':<36} {a.old_name:>14} {a.new_name:>14} {'speed-up':>9}")
        ratios = []
        for f in files:
            o, n = old[f].get(k), new[f].get(k)
            if not o or not n:
                continue
            ratios.append((o / n, f))
            print(f"  {f:<36} {o:>14.0f} {n:>14.0f} {o / n:>8.2f}x")
        o, n = old.get("all files", {}).get(k), new.get("all files", {}).get(k)
        if o and n:
            print(f"  {'all files':<36} {o:>14.0f} {n:>14.0f} {o / n:>8.2f}x")
        if ratios:
            gm = math.exp(sum(math.log(r) for r, _ in ratios) / len(ratios))
            worst = min(ratios)
            print(f"  geometric mean {gm:.2f}x over {len(ratios)} files; slowest {worst[1]} {worst[0]:.2f}x")
            summary.append((k, gm, worst))
    print("\nsummary")
    for k, gm, worst in summary:
        print(f"  {k:<14} geometric mean {gm:5.2f}x   slowest {worst[0]:5.2f}x ({worst[1]})")


if __name__ == "__main__":
    main()

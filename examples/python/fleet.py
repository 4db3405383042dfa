#!/usr/bin/env python3
"""The walkable-floor job (walkable.py) for every map of a folder, on a Dask cluster.

Each .map (and .cm) file of DIR is loaded here, its models travel pickled (as .cm text) to a
Dask worker, which runs walkable.py's job on the world model with one thread; the results
come back as they finish (a progress line each) and are gathered into one report:
OUT/fleet.json (every map's summary) and OUT/NAME-walkable.png per map, with a table printed.
By default the cluster is a LocalCluster on this machine (--workers processes, one thread
each); --scheduler ADDRESS uses a running one instead, e.g. started with Debian's
python3-distributed:

    dask scheduler                     # prints tcp://HOST:8786
    dask worker tcp://HOST:8786        # on every machine, with cmkit importable
    PYTHONPATH=build/python/python python3 examples/python/fleet.py MAPS --scheduler tcp://HOST:8786

    PYTHONPATH=build/python/python python3 examples/python/fleet.py data/maps/lt4 -o fleet-out

Needs Debian's python3-dask, python3-distributed, python3-numpy and python3-matplotlib.
"""
import argparse
import json
import pathlib
import pickle
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import walkable  # noqa: E402  (the job itself, beside this file)

import cmkit  # noqa: E402


def bake(name, models, spacing, min_normal_z):
    """One map's job (on a worker): the summary and the height grid of its world model."""
    t0 = time.perf_counter()
    height, xs, ys, drops, kept = walkable.walkable(models.world, spacing, min_normal_z, threads=1,
                                                    progress=False)
    cells = int(np.isfinite(height).sum())
    summary = {
        "map": name, "spacing": spacing, "grid": [len(xs), len(ys)], "drops": drops, "landings_kept": kept,
        "walkable_cells": cells, "walkable_area": cells * spacing ** 2,
        "floor_height_min": float(np.nanmin(height)) if cells else None,
        "floor_height_max": float(np.nanmax(height)) if cells else None,
        "seconds": round(time.perf_counter() - t0, 3),
    }
    return summary, height, xs, ys


def load_folder(folder):
    """(name, Models) for every .map and .cm file of the folder, sorted by name."""
    jobs = []
    for path in sorted(folder.glob("*.map")) + sorted(folder.glob("*.cm")):
        if path.suffix == ".cm" and path.with_suffix(".map").exists():
            continue  # the map's own .cm: the map is loaded (and uses it when current)
        try:
            models = cmkit.load_map(path) if path.suffix == ".map" else cmkit.load_cm(path)
        except cmkit.Error as e:
            print(f"fleet.py: skipped {path}: {e}", file=sys.stderr)
            continue
        jobs.append((path.stem, models))
    return jobs


def run_local(jobs, spacing, min_normal_z):
    """The same job without Dask, on models that went through pickling as on a worker."""
    return [bake(name, pickle.loads(pickle.dumps(models)), spacing, min_normal_z) for name, models in jobs]


def run_distributed(jobs, spacing, min_normal_z, scheduler=None, workers=2, quiet=False):
    """Every job on a Dask cluster; results in the order of `jobs`."""
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(scheduler or cluster)
    try:
        # The models go to the cluster once each (pickled as .cm text), then the jobs.
        shipped = [client.scatter(models) for _, models in jobs]
        futures = [client.submit(bake, name, sent, spacing, min_normal_z, pure=False, key=f"walkable-{name}")
                   for (name, _), sent in zip(jobs, shipped)]
        index = {f.key: i for i, f in enumerate(futures)}
        results = [None] * len(futures)
        for done, future in enumerate(as_completed(futures), 1):
            results[index[future.key]] = future.result()
            if not quiet:
                summary = results[index[future.key]][0]
                print(f"[{done}/{len(futures)}] {summary['map']}: {summary['walkable_cells']} walkable cells "
                      f"({summary['seconds']} s on a worker)", file=sys.stderr)
        return results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def write_report(results, out):
    """OUT/NAME-walkable.png per map and OUT/fleet.json; returns the report."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    report = []
    for summary, height, xs, ys in results:
        png = out / f"{summary['map']}-walkable.png"
        fig, ax = plt.subplots(figsize=(6, 6), dpi=100)
        if len(xs) and len(ys):
            image = ax.imshow(height.T, origin="lower", extent=(xs[0], xs[-1], ys[0], ys[-1]), cmap="viridis",
                              interpolation="nearest")
            fig.colorbar(image, ax=ax, label="floor height", shrink=0.8)
        ax.set_title(f"{summary['map']}: where a player can stand")
        fig.tight_layout()
        fig.savefig(png)
        plt.close(fig)
        report.append(dict(summary, picture=png.name))
    (out / "fleet.json").write_text(json.dumps(report, indent=2) + "\n")
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", type=pathlib.Path, help="a folder of .map (and .cm) files")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes (default 2)")
    ap.add_argument("-o", "--output", type=pathlib.Path, default=pathlib.Path("."), help="output folder")
    ap.add_argument("--spacing", type=float, default=16.0, help="grid spacing in map units (default 16)")
    ap.add_argument("--min-normal-z", type=float, default=0.7, help="walkable floor normal z (default 0.7)")
    args = ap.parse_args()
    if not args.folder.is_dir():
        ap.error(f"{args.folder} is not a folder")
    if not args.spacing > 0 or args.workers < 1:
        ap.error("--spacing must be positive and --workers at least 1")
    jobs = load_folder(args.folder)
    if not jobs:
        sys.exit(f"fleet.py: no .map or .cm file could be loaded in {args.folder}")
    t0 = time.perf_counter()
    results = run_distributed(jobs, args.spacing, args.min_normal_z, args.scheduler, args.workers)
    report = write_report(results, args.output)
    print(f"{'map':<40} {'cells':>8} {'area':>12} {'floor z':>17} {'s':>7}")
    for r in report:
        z = f"{r['floor_height_min']:g}..{r['floor_height_max']:g}" if r["walkable_cells"] else "-"
        print(f"{r['map']:<40} {r['walkable_cells']:>8} {r['walkable_area']:>12g} {z:>17} {r['seconds']:>7}")
    print(f"{len(report)} maps in {time.perf_counter() - t0:.1f} s -> {args.output / 'fleet.json'}")


if __name__ == "__main__":
    main()

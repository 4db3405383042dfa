#!/usr/bin/env python3
"""Where can a player stand? A top-down heat map of a map's walkable floors.

For every cell of a grid over the map (--spacing units apart), rays cast down find every
surface under it that faces up steeply enough; a player box is dropped onto each from 24 units
above (batch translations down). A landing counts when the box started free, came to rest on a
floor whose normal is walkable (normal z >= --min-normal-z, 0.7 as Doom 3's MIN_WALK_NORMAL),
fits there (a position test a little above the floor), and has a ceiling above it (a ray up
hits something: the void outside a sealed map has none). The highest landing per cell colours
the picture.

    PYTHONPATH=build/python/python python3 examples/python/walkable.py data/maps/lt4/lt4.map

writes NAME-walkable.png and NAME-walkable.json into the current folder (or -o DIR).
Needs Debian's python3-numpy and python3-matplotlib.
"""
import argparse
import json
import pathlib
import sys
import time

import numpy as np

import cmkit

PLAYER_SPEC = "box:-16,-16,0,16,16,72"  # Doom 3's player bounds (standing)
FIT_LIFT = 1.0  # the position test stands the box this far above where it landed
DROP_HEIGHT = 24.0  # the box is dropped from this far above a floor candidate (a stair step is 16)


class ProgressBar:
    """A progress bar on stderr over the job's steps, also usable as a batch progress hook."""

    def __init__(self, steps):
        self.steps, self.step, self.label, self.shown = steps, 0, "", None

    def start(self, label):
        self.label = label
        self.show(0.0)

    def hook(self, done, total):  # the batch methods call it with the queries answered so far
        self.show(done / max(total, 1))
        return True

    def finish_step(self):
        self.step += 1
        self.show(0.0)
        if self.step == self.steps:
            sys.stderr.write("\n")

    def show(self, fraction):
        width = 40
        filled = min(width, int(width * (self.step + fraction) / self.steps))
        if (filled, self.label) != self.shown:
            self.shown = (filled, self.label)
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.label:<28}")
            sys.stderr.flush()


def floor_candidates(world, points, max_hits, threads, bar):
    """Every upward-facing surface below each point (rays cast down again and again)."""
    found = []
    origins = points.copy()
    down = np.array([0, 0, world.bounds[0][2] - world.bounds[1][2] - 16], dtype=np.float32)
    for _ in range(max_hits):
        if len(origins) == 0:
            break
        bar.start(f"floors ({len(origins)} rays)")
        r = world.cast_rays(origins, origins + down, mask=cmkit.MASK_PLAYER_SOLID, threads=threads, progress=bar.hook)
        hit = r["hit"]
        found.append(np.concatenate([r["endpos"][hit], r["normal"][hit, 2:3]], axis=1))
        origins = r["endpos"][hit] - [0, 0, 0.5]  # go on below the surface: its brush is left through back faces
    return np.concatenate(found) if found else np.zeros((0, 4), np.float32)


class QuietBar(ProgressBar):
    """The same steps without output (fleet.py's workers)."""

    def show(self, fraction):
        pass

    def finish_step(self):
        self.step += 1


def walkable(world, spacing, min_normal_z, threads, progress=True):
    """The walkable floor height per grid cell (NaN: none), the grid's x and y, and counts."""
    player = cmkit.TraceModel.from_spec(PLAYER_SPEC)
    lo, hi = world.bounds
    xs = np.arange(lo[0] + spacing / 2, hi[0], spacing, dtype=np.float32)
    ys = np.arange(lo[1] + spacing / 2, hi[1], spacing, dtype=np.float32)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    tops = np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, hi[2] + 16, np.float32)], axis=1)
    bar = ProgressBar(5) if progress else QuietBar(5)

    # 1. Floor candidates: the walkable-looking surfaces under every cell.
    floors = floor_candidates(world, tops, 32, threads, bar)
    floors = floors[floors[:, 3] >= min_normal_z, :3]
    bar.finish_step()

    # 2. Drop the player box from a little above each candidate (where it starts free).
    starts = floors + [0, 0, DROP_HEIGHT]
    bar.start("start positions")
    free = world.contents(player, starts, mask=cmkit.MASK_PLAYER_SOLID, threads=threads,
                          progress=bar.hook)["contents"] == 0
    starts = starts[free]
    bar.finish_step()
    bar.start(f"drops ({len(starts)})")
    r = world.translate(player, starts, starts - [0, 0, 2 * DROP_HEIGHT], mask=cmkit.MASK_PLAYER_SOLID,
                        threads=threads, progress=bar.hook)
    landed = (r["fraction"] < 1) & (r["normal"][:, 2] >= min_normal_z)
    spots = r["endpos"][landed]
    bar.finish_step()

    # 3. It must fit where it landed, and have a ceiling above (the void outside a sealed map has none).
    bar.start("fit")
    fits = world.contents(player, spots + [0, 0, FIT_LIFT], mask=cmkit.MASK_PLAYER_SOLID, threads=threads,
                          progress=bar.hook)["contents"] == 0
    spots = spots[fits]
    bar.finish_step()
    bar.start("ceilings")
    eyes = spots + [0, 0, 64]
    spots = spots[world.cast_rays(eyes, eyes + [0, 0, 16384], threads=threads, progress=bar.hook)["hit"]]
    bar.finish_step()

    height = np.full((len(xs), len(ys)), np.nan, dtype=np.float32)
    if len(spots):  # (a map smaller than one grid cell has no cells and no spots)
        ix = np.rint((spots[:, 0] - xs[0]) / spacing).astype(int)
        iy = np.rint((spots[:, 1] - ys[0]) / spacing).astype(int)
        order = np.argsort(spots[:, 2])  # the highest landing of a cell is written last
        height[ix[order], iy[order]] = spots[order, 2]
    return height, xs, ys, len(starts), len(spots)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("map", type=pathlib.Path, help="a .map file (NAME.cm / NAME.proc beside it are used)")
    ap.add_argument("-o", "--output", type=pathlib.Path, default=pathlib.Path("."), help="output folder")
    ap.add_argument("--spacing", type=float, default=8.0, help="grid spacing in map units (default 8)")
    ap.add_argument("--min-normal-z", type=float, default=0.7, help="walkable floor normal z (default 0.7)")
    ap.add_argument("--threads", type=int, default=0, help="worker threads (default 0: all cores)")
    args = ap.parse_args()
    if not args.spacing > 0:
        ap.error("--spacing must be positive")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t0 = time.perf_counter()
    try:
        models = cmkit.load_map(args.map)
    except cmkit.Error as e:
        sys.exit(f"walkable.py: {e}")
    world = models[0]
    height, xs, ys, drops, kept = walkable(world, args.spacing, args.min_normal_z, args.threads)
    seconds = time.perf_counter() - t0

    name = args.map.stem
    args.output.mkdir(parents=True, exist_ok=True)
    png = args.output / f"{name}-walkable.png"
    fig, ax = plt.subplots(figsize=(8, 8 * len(ys) / max(len(xs), 1) + 0.5), dpi=120)
    image = ax.imshow(height.T, origin="lower", extent=(xs[0], xs[-1], ys[0], ys[-1]), cmap="viridis",
                      interpolation="nearest")
    fig.colorbar(image, ax=ax, label="floor height (map units)", shrink=0.8)
    ax.set_title(f"{name}: where a player can stand ({args.spacing:g}-unit grid)")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    fig.tight_layout()
    fig.savefig(png)

    cells = int(np.isfinite(height).sum())
    summary = {
        "map": str(args.map), "spacing": args.spacing, "grid": [len(xs), len(ys)], "drops": drops,
        "landings_kept": kept, "walkable_cells": cells, "walkable_area": cells * args.spacing ** 2,
        "floor_height_min": float(np.nanmin(height)) if cells else None,
        "floor_height_max": float(np.nanmax(height)) if cells else None,
        "seconds": round(seconds, 3), "picture": png.name,
    }
    (args.output / f"{name}-walkable.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"{name}: {cells} walkable cells of {len(xs) * len(ys)} ({drops} drops) in {seconds:.1f} s -> {png}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""A player walks a route through two doors of lt4, closed and then opened.

The map is loaded as a cmkit.World (every entity placed). A player steered along a route of
waypoints stops at the first closed door (a translation of the player box says which entity
stopped it); both doors are then opened by turning each 90 degrees about its hinge
(World.set_transform) and the same walk passes through. A top view of the corridor (heights
from rays cast down, through the world with its doors) shows both paths.

    PYTHONPATH=build/python/python python3 examples/python/door_walk.py [-o door_walk.png]

It is the Python twin of examples/door_walk.cpp (the same route and doors). Needs Debian's
python3-numpy and python3-matplotlib; the bundled lt4 map is found beside this file
(data/maps/lt4/lt4.map) unless --map says where it is.
"""
import argparse
import math
import pathlib
import sys

import numpy as np

import cmkit

HERE = pathlib.Path(__file__).resolve().parent
DEFAULT_MAP = HERE.parent.parent / "data" / "maps" / "lt4" / "lt4.map"

# Where the player's feet go, in order (x, y); the doorways are 40 units wide for a 32-unit
# player, so the route keeps to the middle of each. It starts 20 units above the floor.
ROUTE = [(1000.0, -1483.5), (900.0, -1483.5), (850.0, -1492.0), (700.0, -1492.0)]
START_Z = -530.0
# Each door turns about the vertical line through its -y end, away from a player coming from +x.
DOORS = {"lt4_door_wood_3": (935.0, -1504.0), "lt4_door_wood_4": (799.0, -1512.0)}
STEP = 1.0 / 60.0  # one player step (cmkit's move::kTimeStep)
REACHED = 4.0  # a waypoint counts as reached this close (map units)
PATIENCE = 30  # steps without moving a unit: blocked
MAX_STEPS = 1200  # 20 s


def where(p):
    """A position as examples/door_walk.cpp prints it."""
    return f"({p[0]:.2f} {p[1]:.2f} {p[2]:.2f})"


def walk_route(world):
    """Steers a player along ROUTE, one step at a time; returns (path (N, 3), arrived)."""
    pos = np.array([ROUTE[0][0], ROUTE[0][1], START_Z])
    velocity = np.zeros(3)
    path, still, waypoint = [], 0, 1
    for _ in range(MAX_STEPS):
        if waypoint == len(ROUTE):
            break
        toward = np.array(ROUTE[waypoint]) - pos[:2]
        if np.hypot(*toward) < REACHED:
            waypoint += 1
            continue
        r = world.walk(pos, toward / np.hypot(*toward), STEP, velocity=velocity)
        still = still + 1 if np.linalg.norm(r["end"] - pos) < 1.0 / 60.0 else 0
        pos, velocity = r["end"].astype(float), r["velocity"]
        path.append(pos)
        if still >= PATIENCE:
            break
    return np.array(path), waypoint == len(ROUTE)


def blocker(world, at):
    """The name of what stops the player box 32 units further along the route (-x) from `at`."""
    r = world.translate(cmkit.TraceModel.box((-16, -16, 0), (16, 16, 74)), at, at + (-32, 0, 0),
                        mask=cmkit.MASK_PLAYER_SOLID)
    entity = int(r["entity"][0])
    return world.entity_names[entity] if entity >= 0 else "nothing"


def turn_about(world, name, hinge, degrees):
    """Turns an entity about the vertical line through `hinge` (world = origin + local @ axis)."""
    origin, axis = world.transform(name)
    t = math.radians(degrees)
    turn = np.array([[math.cos(t), math.sin(t), 0], [-math.sin(t), math.cos(t), 0], [0, 0, 1]])
    h = np.array([hinge[0], hinge[1], 0.0])
    world.set_transform(name, origin=h + (origin - h) @ turn, axis=axis @ turn)


def footprint(world, name):
    """The corners (5, 2) of an entity's placed bounds seen from above, closed."""
    origin, axis = world.transform(name)
    lo, hi = world.model(name).bounds
    corners = np.array([[x, y, lo[2]] for x, y in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1]))])
    placed = (corners @ axis + origin)[:, :2]
    return np.vstack([placed, placed[:1]])


def top_view(world, closed, opened, doors, out):
    """Heights of the corridor's floors (rays cast down) with both paths and the doors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs, ys = np.arange(660, 1040, 2.0), np.arange(-1600, -1380, 2.0)
    gx, gy = np.meshgrid(xs, ys)
    starts = np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, -476.0)], axis=1)
    hits = world.cast_rays(starts, starts + (0, 0, -200))
    height = np.where(hits["hit"], starts[:, 2] - 200 * hits["fraction"], np.nan).reshape(gx.shape)
    fig, ax = plt.subplots(figsize=(9, 5.5), dpi=100)
    image = ax.imshow(height, origin="lower", extent=(xs[0], xs[-1], ys[0], ys[-1]), cmap="terrain")
    fig.colorbar(image, ax=ax, label="floor height (white: walls; the rays start inside them)")
    for name, was in doors.items():
        ax.plot(was[:, 0], was[:, 1], color="orange", lw=2)
        now = footprint(world, name)
        ax.plot(now[:, 0], now[:, 1], color="green", lw=2)
        ax.annotate(name, was[2], textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.plot(opened[:, 0], opened[:, 1], color="green", lw=2, label="doors opened: through")
    ax.plot(closed[:, 0], closed[:, 1], color="red", lw=2, label="doors closed: stopped")
    ax.plot(*ROUTE[0], "ko")
    ax.annotate("start", ROUTE[0], textcoords="offset points", xytext=(6, 6))
    ax.set(xlabel="x", ylabel="y", aspect="equal", title="lt4: a walk through two doors (cmkit World)")
    ax.legend(loc="lower left")
    fig.savefig(out, bbox_inches="tight")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--map", default=str(DEFAULT_MAP), help="lt4.map (default: the bundled one)")
    parser.add_argument("-o", "--output", default="door_walk.png", help="the picture (default: %(default)s)")
    args = parser.parse_args()

    world = cmkit.load_world(args.map)
    print(f"{len(world)} entities placed")
    closed, arrived = walk_route(world)
    print(f"doors closed: {'arrived' if arrived else 'stopped'} at {where(closed[-1])} after "
          f"{len(closed)} steps, stopped by {blocker(world, closed[-1])}")
    doors = {name: footprint(world, name) for name in DOORS}  # where they stand closed
    for name, hinge in DOORS.items():
        turn_about(world, name, hinge, 90)  # each door swings towards -x, away from the player
    opened, arrived_open = walk_route(world)
    print(f"doors open: {'arrived' if arrived_open else 'stopped'} at {where(opened[-1])} after "
          f"{len(opened)} steps")
    top_view(world, closed, opened, doors, args.output)
    print(f"picture: {args.output}")
    return 0 if arrived_open and not arrived else 1


if __name__ == "__main__":
    sys.exit(main())

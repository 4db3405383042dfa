#!/usr/bin/env python3
"""Writes stairs.map beside this script: a closed room with two staircases
side by side for the player-move tests (tests/unit/test_movement.cpp) and
`cmkit walk`. Run it again after changing it; the .map is committed.

  floor z = 0 (x -160..272, y -144..144), ceiling z = 256, walls around;
  a divider wall at y -8..8 from x = 0 on;
  lane y > 8 (centre y = 64): risers of 12 units, treads of 16, from
    x = 64: tops at z = 12, 24, 36, 48, then the landing at z = 60 from
    x = 128 to the far wall at x = 256;
  lane y < -8 (centre y = -64): risers of 24 units, treads of 16, from
    x = 64: tops at z = 24, 48, 72, 96, then a landing at z = 120 from x = 128.
"""
import os

MATERIAL = "textures/base_wall/lfwall27d"


def box(lo, hi):
    """brushDef3 text of an axis-aligned box (plane: n . p + d = 0, d = -dist)."""
    faces = []
    for axis in range(3):
        n = [0, 0, 0]
        n[axis] = 1
        faces.append((tuple(n), -hi[axis]))
        n = [0, 0, 0]
        n[axis] = -1
        faces.append((tuple(n), lo[axis]))
    lines = [" brushDef3", " {"]
    for n, d in faces:
        lines.append(f"  ( {n[0]} {n[1]} {n[2]} {d} ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"{MATERIAL}\" 0 0 0")
    lines.append(" }")
    return lines


def main():
    brushes = [
        ((-160, -144, -16), (272, 144, 0)),  # floor
        ((-160, -144, 256), (272, 144, 272)),  # ceiling
        ((-160, -144, 0), (-144, 144, 256)),  # wall at x = -144
        ((256, -144, 0), (272, 144, 256)),  # wall at x = 256
        ((-144, -144, 0), (256, -128, 256)),  # wall at y = -128
        ((-144, 128, 0), (256, 144, 256)),  # wall at y = 128
        ((0, -8, 0), (256, 8, 256)),  # divider
    ]
    for k in range(5):  # 12-unit risers; k = 4 is the landing
        brushes.append(((64 + 16 * k, 8, 0), (256, 128, 12 * (k + 1))))
    for k in range(5):  # 24-unit risers
        brushes.append(((64 + 16 * k, -128, 0), (256, -8, 24 * (k + 1))))
    out = [
        "Version 2",
        "// stairs.map: written by make_stairs.py (its docstring describes the room). Two staircases",
        "// side by side: 12-unit risers (y > 8) that a player climbs, 24-unit risers (y < -8) that",
        "// hold it (tests/unit/test_movement.cpp, cmkit walk).",
        "// entity 0",
        "{",
        "\"classname\" \"worldspawn\"",
    ]
    for i, (lo, hi) in enumerate(brushes):
        out.append(f"// primitive {i}")
        out.append("{")
        out.extend(box(lo, hi))
        out.append("}")
    out.append("}")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "stairs.map")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()

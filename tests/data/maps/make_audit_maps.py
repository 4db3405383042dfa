#!/usr/bin/env python3
"""Writes the audit test maps beside this script (tests/unit/test_audit.cpp,
`cmkit audit`): a sealed room, and the same room with one planted fault each.
Run it again after changing it; the .map files are committed.

  the room: floor z = 0 (a brush 16 thick), walls 16 thick around
    x, y in -256..256, ceiling z = 160; player start at (-160, 0, 1);
  audit_sealed.map  the room, a monster and an item on the floor: no findings;
  audit_hole.map    a 96 x 96 hole in the floor (x 64..160, y -48..48) over
                    nothing: a fall-out next to it;
  audit_wedge.map   a V trench in the floor (x -64..64, y -20..20, 110 deep)
                    whose sides slope at 60 degrees (too steep to walk or jump
                    from): a player who walks in is wedged: a stuck spot;
  audit_crack.map   the floor in two brushes 2 units apart (x 37..39) over
                    nothing: an open shell (a point falls through; the player
                    does not);
  audit_wall_crack.map  the wall at x = 256 in two brushes with a slit 2 units
                    wide (y 37..39) to the outside: an open shell in the wall;
  audit_gap.map     the floor split by a gap 64 wide (x -32..32) over a pit
                    128 deep with a floor: the far side is reached by a running
                    jump; no findings;
  audit_trigger.map the room with a trigger_multiple brush entity (a material
                    the default rules make solid) around the player start: the
                    audit ignores triggers, so no findings;
  audit_pillar.map  a pillar (x 96..160, y -32..32) with a second player
                    start inside it: an embedded player start.
"""
import math
import os

MATERIAL = "textures/base_wall/lfwall27d"
HALF = 256  # the room's inner half width
CEILING = 160


def planes_brush(planes):
    """brushDef3 text of a brush from planes (normal, d) with n . p + d = 0,
    normals pointing out of the brush."""
    lines = [" brushDef3", " {"]
    for n, d in planes:
        lines.append(
            f"  ( {n[0]:.9g} {n[1]:.9g} {n[2]:.9g} {d:.9g} ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"{MATERIAL}\" 0 0 0"
        )
    lines.append(" }")
    return lines


def box(lo, hi):
    planes = []
    for axis in range(3):
        n = [0, 0, 0]
        n[axis] = 1
        planes.append((tuple(n), -hi[axis]))
        n = [0, 0, 0]
        n[axis] = -1
        planes.append((tuple(n), lo[axis]))
    return planes_brush(planes)


def room(floor, east_wall=None):
    """The room's walls and ceiling, and `floor`: a list of (lo, hi) boxes;
    `east_wall` replaces the wall at x = 256 (a list of boxes)."""
    w = HALF + 16
    brushes = [box(lo, hi) for lo, hi in floor]
    east = east_wall or [((HALF, -w, 0), (w, w, CEILING))]
    brushes += [box(lo, hi) for lo, hi in east]
    brushes += [
        box((-w, -w, CEILING), (w, w, CEILING + 16)),
        box((-w, -w, 0), (-HALF, w, CEILING)),
        box((-HALF, -w, 0), (HALF, -HALF, CEILING)),
        box((-HALF, HALF, 0), (HALF, w, CEILING)),
    ]
    return brushes


def full_floor():
    w = HALF + 16
    return [((-w, -w, -16), (w, w, 0))]


def point_entity(classname, name, origin):
    return [
        "{",
        f'"classname" "{classname}"',
        f'"name" "{name}"',
        f'"origin" "{origin[0]} {origin[1]} {origin[2]}"',
        "}",
    ]


def brush_entity(classname, name, brushes):
    out = ["{", f'"classname" "{classname}"', f'"name" "{name}"', f'"model" "{name}"']
    for i, b in enumerate(brushes):
        out.append(f"// primitive {i}")
        out.append("{")
        out.extend(b)
        out.append("}")
    out.append("}")
    return out


def write(name, comment, brushes, entities):
    out = ["Version 2", f"// {name}: written by make_audit_maps.py. {comment}", "// entity 0", "{",
           '"classname" "worldspawn"']
    for i, b in enumerate(brushes):
        out.append(f"// primitive {i}")
        out.append("{")
        out.extend(b)
        out.append("}")
    out.append("}")
    start = point_entity("info_player_start", "info_player_start_1", (-160, 0, 1))
    for e in [start] + entities:
        out.extend(e)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def wedge_floor():
    """The floor around the trench, the trench's end walls, and its two sloped
    sides (solid below planes at 60 degrees meeting 110.85 below the floor)."""
    w = HALF + 16
    brushes = [
        box((-w, -w, -16), (-64, w, 0)),
        box((64, -w, -16), (w, w, 0)),
        box((-64, -w, -128), (64, -20, 0)),  # end wall y < -20
        box((-64, 20, -128), (64, w, 0)),  # end wall y > 20
    ]
    s, c = math.sin(math.radians(60)), math.cos(math.radians(60))
    d = s * 64  # the slope passes through (-64, y, 0) and (0, y, -64 tan 60)
    brushes.append(planes_brush([((s, 0, c), d), ((1, 0, 0), 0), ((-1, 0, 0), -64), ((0, 0, -1), -128),
                                 ((0, 1, 0), -20), ((0, -1, 0), -20)]))
    brushes.append(planes_brush([((-s, 0, c), d), ((-1, 0, 0), 0), ((1, 0, 0), -64), ((0, 0, -1), -128),
                                 ((0, 1, 0), -20), ((0, -1, 0), -20)]))
    return brushes


def main():
    w = HALF + 16
    write("audit_sealed.map", "A sealed room with a monster and an item: no findings.", room(full_floor()),
          [point_entity("monster_zombie_fat", "monster_1", (128, 128, 1)),
           point_entity("item_medkit", "item_1", (-128, -128, 8))])
    hole = [((-w, -w, -16), (64, w, 0)), ((160, -w, -16), (w, w, 0)), ((64, -w, -16), (160, -48, 0)),
            ((64, 48, -16), (160, w, 0))]
    write("audit_hole.map", "The sealed room with a 96 x 96 hole (x 64..160, y -48..48) over nothing.",
          room(hole), [])
    write("audit_wedge.map", "The sealed room with a V trench whose sides are too steep: a trap.",
          room([]) + wedge_floor(), [])
    crack = [((-w, -w, -16), (37, w, 0)), ((39, -w, -16), (w, w, 0))]
    write("audit_crack.map", "The sealed room whose floor has a crack 2 units wide (x 37..39) over nothing.",
          room(crack), [])
    slit = [((HALF, -w, 0), (w, 37, CEILING)), ((HALF, 39, 0), (w, w, CEILING))]
    write("audit_wall_crack.map", "The sealed room whose east wall has a slit 2 units wide (y 37..39) to the outside.",
          room(full_floor(), slit), [])
    gap = [((-w, -w, -144), (-32, w, 0)), ((32, -w, -144), (w, w, 0)), ((-32, -w, -144), (32, w, -128))]
    write("audit_gap.map", "The room's floor split by a gap 64 wide over a pit 128 deep: jump across.",
          room(gap) + [box((-32, -w, -128), (32, -HALF, 0)), box((-32, HALF, -128), (32, w, 0))], [])
    trigger = [line.replace(MATERIAL, "textures/common/trigmulti") for line in box((-200, -40, 0), (-120, 40, 96))]
    write("audit_trigger.map", "The sealed room with a trigger_multiple around the player start.",
          room(full_floor()), [brush_entity("trigger_multiple", "trigger_multiple_1", [trigger])])
    write("audit_pillar.map", "The sealed room with a pillar and a player start inside it.",
          room(full_floor()) + [box((96, -32, 0), (160, 32, CEILING))],
          [point_entity("info_player_start", "info_player_start_2", (128, 0, 1))])


if __name__ == "__main__":
    main()

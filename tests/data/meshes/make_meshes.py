#!/usr/bin/env python3
"""Writes the small test meshes of tests/data/meshes (run from anywhere; the
files are committed, this script says how they were made). Ours, MIT like
the rest of cmkit.

cube.obj        a closed 64-unit cube (0..64 on each axis), 8 vertices, 12
                triangles counter-clockwise seen from outside, one material.
cube.gltf       the same cube as glTF 2.0 (y up, embedded base64 buffer).
collision.obj   a 64-unit cube drawn with a visual material plus, on the
                material "textures/common/collision", a 32-unit box
                (16..48): only the collision box may collide.
two_sided.obj   one 32x32 quad (two triangles) at z=0 facing up.
malformed.obj   a face that uses vertex 9 of 3.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# Corners of a box: index bit 0 -> x, bit 1 -> y, bit 2 -> z.
def box(lo, hi):
    return [(hi if i & 1 else lo, hi if i & 2 else lo, hi if i & 4 else lo) for i in range(8)]

# Two triangles per face, counter-clockwise seen from outside (0-based corners).
BOX_TRIANGLES = [
    (0, 2, 3), (0, 3, 1),  # z = lo, facing -z
    (4, 5, 7), (4, 7, 6),  # z = hi, facing +z
    (0, 1, 5), (0, 5, 4),  # y = lo, facing -y
    (2, 6, 7), (2, 7, 3),  # y = hi, facing +y
    (0, 4, 6), (0, 6, 2),  # x = lo, facing -x
    (1, 3, 7), (1, 7, 5),  # x = hi, facing +x
]


def obj_box(lines, corners, material, first):
    for c in corners:
        lines.append("v %g %g %g" % c)
    lines.append("usemtl %s" % material)
    for t in BOX_TRIANGLES:
        lines.append("f %d %d %d" % tuple(first + i for i in t))


def write(name, text):
    with open(os.path.join(HERE, name), "w", newline="\n") as f:
        f.write(text)


def main():
    lines = ["# cmkit test mesh: a closed 64-unit cube (make_meshes.py)"]
    obj_box(lines, box(0, 64), "textures/test/cube", 1)
    write("cube.obj", "\n".join(lines) + "\n")

    lines = ["# cmkit test mesh: a visual cube and a collision box (make_meshes.py)"]
    obj_box(lines, box(0, 64), "textures/test/visual", 1)
    obj_box(lines, box(16, 48), "textures/common/collision", 9)
    write("collision.obj", "\n".join(lines) + "\n")

    write("two_sided.obj", "# cmkit test mesh: one quad facing +z (make_meshes.py)\n"
          "v 0 0 0\nv 32 0 0\nv 32 32 0\nv 0 32 0\nusemtl textures/test/twosided\nf 1 2 3\nf 1 3 4\n")

    write("malformed.obj", "# cmkit test mesh: a face using a vertex that does not exist\n"
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")

    # glTF is y up: Doom (x, y, z) is glTF (x, z, -y).
    corners = [(x, z, -y) for (x, y, z) in box(0, 64)]
    positions = b"".join(struct.pack("<3f", *c) for c in corners)
    indices = b"".join(struct.pack("<3H", *t) for t in BOX_TRIANGLES)
    buffer = positions + indices
    gltf = {
        "asset": {"version": "2.0", "generator": "cmkit tests/data/meshes/make_meshes.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "cube"}],
        "materials": [{"name": "textures/test/cube"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "buffers": [{"byteLength": len(buffer),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(buffer).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(positions)},
            {"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
             "min": [min(c[i] for c in corners) for i in range(3)],
             "max": [max(c[i] for c in corners) for i in range(3)]},
            {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"},
        ],
    }
    write("cube.gltf", json.dumps(gltf, indent=1) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""random_meshes.py OUTDIR [GRIDS] [CLUSTERS]: random .obj meshes that stress the mesh build's
welding, edge sharing and two-sided copies, for comparing the .cm files two builds of the CLI
write (compare_mesh_builds.sh). Writes OUTDIR/grid-NNN.obj (GRIDS, default 60: height-field
grids of 3x3 to 9x9 cells, each triangle one- or two-sided, some flipped or repeated, points
moved within the weld and snap distances), OUTDIR/cluster-NNN.obj (CLUSTERS, default 4: 5000
points gathered at 4-unit cell borders, 6000 triangles between any of them) and
OUTDIR/mtr/materials/test.mtr (textures/test/two is two-sided, textures/test/one is not).
The same seeds give the same files."""
import os
import random
import sys

MATERIALS = ["textures/test/two", "textures/test/one"]


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % v)
        current = None
        for material, tri in faces:
            if material != current:
                f.write("usemtl %s\n" % material)
                current = material
            f.write("f %d %d %d\n" % tri)


def grid(seed, path):
    rnd = random.Random(seed)
    n = rnd.randint(3, 9)
    verts, faces, at = [], [], {}
    for i in range(n + 1):
        for j in range(n + 1):
            x, y = i * 16.0, j * 16.0
            z = rnd.choice([0.0, 0.0, 8.0, rnd.uniform(-20, 20)])
            if rnd.random() < 0.2:
                x += rnd.uniform(-0.3, 0.3)  # near an integer: snapped, or not
            verts.append((x, y, z))
            at[(i, j)] = len(verts)
    for i in range(n):
        for j in range(n):
            a, b, c, d = at[(i, j)], at[(i + 1, j)], at[(i + 1, j + 1)], at[(i, j + 1)]
            for tri in ((a, b, c), (a, c, d)):
                if rnd.random() < 0.1:
                    tri = (tri[0], tri[2], tri[1])  # facing the other way
                faces.append((rnd.choice(MATERIALS) if rnd.random() < 0.5 else MATERIALS[0], tri))
                if rnd.random() < 0.05:
                    faces.append((rnd.choice(MATERIALS), tri))  # the same triangle again
    for _ in range(rnd.randint(0, 4)):  # a point within the weld distance of another
        v = verts[rnd.randrange(len(verts))]
        verts.append((v[0] + rnd.uniform(-0.05, 0.05), v[1], v[2]))
        e = len(verts)
        faces.append((rnd.choice(MATERIALS), (e, rnd.randint(1, e - 1), rnd.randint(1, e - 1))))
    rnd.shuffle(faces)
    write_obj(path, verts, faces)


def cluster(seed, path):
    rnd = random.Random(1000 + seed)
    centres = [[rnd.randint(-60, 60) * 4.0 + rnd.choice([0, 0.38, -0.38, 1.62, 2.38]) for _ in range(3)]
               for _ in range(1500)]
    verts = []
    for _ in range(5000):
        c = centres[rnd.randrange(len(centres))]
        verts.append(tuple(x + rnd.uniform(-0.12, 0.12) if rnd.random() < 0.7 else x for x in c))
    faces = [(rnd.choice(MATERIALS), (rnd.randrange(len(verts)) + 1, rnd.randrange(len(verts)) + 1,
                                      rnd.randrange(len(verts)) + 1)) for _ in range(6000)]
    write_obj(path, verts, faces)


def main():
    out = sys.argv[1]
    grids = int(sys.argv[2]) if len(sys.argv) > 2 else 60
    clusters = int(sys.argv[3]) if len(sys.argv) > 3 else 4
    os.makedirs(os.path.join(out, "mtr", "materials"), exist_ok=True)
    with open(os.path.join(out, "mtr", "materials", "test.mtr"), "w") as f:
        f.write("textures/test/two\n{\n\ttwosided\n}\ntextures/test/one\n{\n}\n")
    for s in range(grids):
        grid(s, os.path.join(out, "grid-%03d.obj" % s))
    for s in range(clusters):
        cluster(s, os.path.join(out, "cluster-%03d.obj" % s))


if __name__ == "__main__":
    main()

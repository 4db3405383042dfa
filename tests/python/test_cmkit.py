"""The cmkit Python package: loading, trace models, batch queries (the same
bits as single queries and as the C++ API, at any thread count), pickling,
progress and cancelling, and bad input raising."""
import pickle
import threading

import numpy as np
import pytest

import cmkit
from conftest import LT4

PLAYER = cmkit.TraceModel.box((-16, -16, 0), (16, 16, 72))
TRACE_FIELDS = ["fraction", "endpos", "endaxis", "start_solid", "point", "normal", "dist", "contents", "type",
                "material", "model_feature", "trm_feature"]


def random_points(bounds, n, seed, pad=0.0):
    rng = np.random.default_rng(seed)
    lo, hi = bounds[0] - pad, bounds[1] + pad
    return (lo + rng.random((n, 3)) * (hi - lo)).astype(np.float32)


def assert_same(a, b, where=""):
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k]), f"{where} field {k} differs"


def one(results, i):
    return {k: v[i:i + 1] for k, v in results.items()}


# ---- loading ---------------------------------------------------------------------------------


def test_load_map_gives_models_by_position_and_name(lt4):
    assert len(lt4) > 1
    world = lt4[0]
    assert world.name == "worldMap"
    assert lt4["worldMap"] is world
    assert lt4.world is world
    assert "worldMap" in lt4 and "no such model" not in lt4
    assert lt4.names[0] == "worldMap"
    assert world.bounds.shape == (2, 3) and np.all(world.bounds[0] < world.bounds[1])
    assert world.content_flags & cmkit.CONTENTS_SOLID
    assert world.num_polygons > 1000 and world.num_brushes > 100
    assert "solid" in cmkit.content_names(world.content_flags)
    with pytest.raises(KeyError, match="no model named 'nothing'"):
        lt4["nothing"]
    assert [m.name for m in lt4] == lt4.names


def test_missing_and_malformed_files_raise_with_file_and_line(tmp_path):
    with pytest.raises(cmkit.Error, match="nothing.map"):
        cmkit.load_map(tmp_path / "nothing.map")
    bad = tmp_path / "bad.map"
    bad.write_text('Version 2\n// entity 0\n{\n"classname" "worldspawn"\n{\n brushDef3\n{\n ( 0 0 1 nan ) ( ( 1 0 0 ) ( 0 1 0 ) ) "x" 0 0 0\n}\n}\n}\n')
    with pytest.raises(cmkit.Error) as e:
        cmkit.load_map(bad)
    assert e.value.file.endswith("bad.map") and e.value.line == 8
    assert str(e.value).startswith(f"{bad}:8:")
    badcm = tmp_path / "bad.cm"
    badcm.write_text('CM "1.00"\n\n0\n\ncollisionModel "worldMap" {\n vertices { 1\n /* 0 */ ( 0 0 x )\n }\n}\n')
    with pytest.raises(cmkit.Error) as e:
        cmkit.load_cm(badcm)
    assert e.value.line == 7 and str(e.value).startswith(f"{badcm}:7:")


def test_cm_round_trip_and_pickle(lt4, tmp_path):
    path = tmp_path / "lt4.cm"
    lt4.save_cm(path)
    again = cmkit.load_cm(path)
    assert again.names == lt4.names
    assert again.to_cm() == lt4.to_cm()
    world = pickle.loads(pickle.dumps(lt4[0]))
    assert world.name == "worldMap" and world.to_cm() == lt4[0].to_cm()
    # The unpickled model answers as the same model loaded from its .cm text.
    from_cm = cmkit.parse_cm(lt4[0].to_cm())[0]
    pts = random_points(lt4[0].bounds, 2000, 11)
    assert_same(world.translate(PLAYER, pts, pts[::-1].copy()), from_cm.translate(PLAYER, pts, pts[::-1].copy()))
    models = pickle.loads(pickle.dumps(lt4))
    assert models.names == lt4.names and models.crc == lt4.crc


# ---- trace models --------------------------------------------------------------------------------


def test_trace_models():
    assert PLAYER.shape == "box" and PLAYER.num_vertices == 8 and PLAYER.num_polygons == 6 and PLAYER.is_convex
    assert np.array_equal(PLAYER.bounds, [[-16, -16, 0], [16, 16, 72]])
    assert cmkit.TraceModel.from_spec("box:-16,-16,0,16,16,72") == PLAYER
    cyl = cmkit.TraceModel.cylinder((-12, -12, -20), (12, 12, 20), sides=8)
    assert cyl.num_vertices == 16 and cyl == cmkit.TraceModel.from_spec("cylinder:8:-12,-12,-20,12,12,20")
    assert cmkit.TraceModel.point().is_point
    assert cmkit.TraceModel.bone(40, 12).shape == "bone"
    hull = cmkit.TraceModel.convex_hull(np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 10], [1, 1, 1]]))
    assert hull.num_vertices == 4
    for trm in (PLAYER, cyl, hull, cmkit.TraceModel.point()):
        assert pickle.loads(pickle.dumps(trm)) == trm
    with pytest.raises(cmkit.Error, match="box"):
        cmkit.TraceModel.from_spec("box:1,2,3")
    with pytest.raises(cmkit.Error):
        cmkit.TraceModel.box((0, 0, 0), (-1, 1, 1))
    with pytest.raises(cmkit.Error):
        cmkit.TraceModel.cylinder((-1, -1, -1), (1, 1, 1), sides=40)
    with pytest.raises(ValueError, match="mins"):
        cmkit.TraceModel.box((0, 0), (1, 1, 1))


# ---- batch = loop of single queries, at any thread count ---------------------------------------------


def test_translate_batch_equals_single_queries(lt4):
    world = lt4[0]
    n = 400
    starts = random_points(world.bounds, n, 1)
    ends = random_points(world.bounds, n, 2, pad=64)
    batch = world.translate(PLAYER, starts, ends, start_solid=True, threads=1)
    assert batch["fraction"].shape == (n,) and batch["endpos"].shape == (n, 3) and batch["endaxis"].shape == (n, 3, 3)
    assert batch["fraction"].dtype == np.float32 and batch["contents"].dtype == np.uint32
    assert (batch["fraction"] < 1).sum() > n // 4, "the moves must hit something to compare anything"
    for i in range(n):
        assert_same(one(batch, i), world.translate(PLAYER, starts[i], ends[i], start_solid=True), f"query {i}")
    for threads in (2, 4, 0):
        assert_same(world.translate(PLAYER, starts, ends, start_solid=True, threads=threads), batch, f"{threads}")
    # A spec string and None (a point) work as trace models; one start, many ends.
    assert_same(world.translate("box:-16,-16,0,16,16,72", starts, ends, start_solid=True), batch)
    center = (world.bounds[0] + world.bounds[1]) / 2
    fan = world.translate(None, center, ends, threads=3)
    for i in range(0, n, 37):
        assert_same(one(fan, i), world.translate(None, center, ends[i]))


def test_other_batches_equal_single_queries(lt4):
    world = lt4[0]
    n = 300
    pts = random_points(world.bounds, n, 3)
    ends = random_points(world.bounds, n, 4)
    bone = cmkit.TraceModel.bone(60, 12)
    angles = np.linspace(-170, 170, n).astype(np.float32)
    calls = {
        "rotate": lambda s, t: world.rotate(bone, pts[s], pts[s] + [5, 3, 0], (0, 0, 1), angles[s], threads=t),
        "cast_rays": lambda s, t: world.cast_rays(pts[s], ends[s], threads=t),
        "point_contents": lambda s, t: world.point_contents(pts[s], threads=t),
        "contents": lambda s, t: world.contents(PLAYER, pts[s], threads=t),
        "contacts": lambda s, t: world.contacts(PLAYER, pts[s], (0, 0, -1), 32, max_contacts=8, threads=t),
        "contacts along rotations": lambda s, t: world.contacts(bone, pts[s], origins=pts[s] + [40, 0, 0],
                                                                axes=(0, 1, 0), angles=angles[s], max_contacts=8,
                                                                threads=t),
    }
    for name, call in calls.items():
        batch = call(slice(None), 1)
        for i in range(n):
            assert_same(one(batch, i), call(slice(i, i + 1), 1), f"{name} query {i}")
        for threads in (2, 3, 0):
            assert_same(call(slice(None), threads), batch, f"{name} threads {threads}")
    assert world.cast_rays(pts, ends)["hit"].sum() > n // 4
    assert (world.point_contents(pts)["contents"] != 0).sum() > 10
    assert (world.contacts(PLAYER, pts, (0, 0, -1), 32)["count"] > 0).sum() >= 5
    turned = world.contacts(bone, pts, origins=pts + [40, 0, 0], axes=(0, 1, 0), angles=angles)
    assert (turned["count"] > 0).sum() >= 20, "the rotations must touch something to compare anything"


def test_empty_batches(lt4):
    world = lt4[0]
    empty = np.zeros((0, 3), np.float32)
    assert world.translate(PLAYER, empty, empty)["fraction"].shape == (0,)
    assert world.point_contents(empty)["contents"].shape == (0,)
    assert world.cast_rays(empty, empty)["endpos"].shape == (0, 3)
    assert world.contacts(PLAYER, empty, (0, 0, 1), 8)["point"].shape == (0, 16, 3)


def test_concurrent_calls_from_python_threads_agree(lt4):
    world = lt4[0]
    pts = random_points(world.bounds, 20000, 5)
    expected = world.point_contents(pts, threads=1)["contents"]
    out = [None] * 4

    def run(k):
        out[k] = world.point_contents(pts, threads=2)["contents"]

    workers = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    for o in out:
        assert np.array_equal(o, expected)


def test_every_result_has_the_query_status(lt4):
    world = lt4[0]
    inside = random_points(world.bounds, 2, 10)
    far = np.array([[3e9, 0, 0]], np.float32)  # beyond 1e9 units: refused, not an exception
    pts = np.concatenate([inside, far])
    ok, out_of_range = cmkit.STATUS_OK, cmkit.STATUS_OUT_OF_RANGE
    p = world.point_contents(pts)
    assert p["status"].dtype == np.uint8 and list(p["status"]) == [ok, ok, out_of_range]
    assert p["contents"][2] == 0
    t = world.translate(PLAYER, pts, pts + [0, 0, -64])
    assert list(t["status"]) == [ok, ok, out_of_range] and t["fraction"][2] == 0
    r = world.rotate(PLAYER, pts, pts, (0, 0, 1), 30)
    assert r["status"][2] == out_of_range
    c = world.contents(PLAYER, pts)
    assert list(c["status"]) == [ok, ok, out_of_range] and c["contents"][2] == 0
    k = world.contacts(PLAYER, pts, (0, 0, -1), 16)
    assert k["status"][2] == out_of_range and k["count"][2] == 0
    placed = world.point_contents(inside, model_axis=np.eye(3) * 2)  # a scaled axis is no rotation
    assert list(placed["status"]) == [cmkit.STATUS_BAD_MODEL_AXIS] * 2
    assert cmkit.status_name(cmkit.STATUS_OK) == "ok"
    assert "not finite" in cmkit.status_name(cmkit.STATUS_NON_FINITE)
    with pytest.raises(ValueError):
        cmkit.status_name(99)


# ---- contacts along a rotation --------------------------------------------------------------------------


def box_brush(mins, maxs):
    """A brushDef3 box: each side ( a b c d ) is the plane a*x + b*y + c*z + d = 0, normal outward."""
    sides = [((0, 0, 1), maxs[2]), ((0, 1, 0), maxs[1]), ((1, 0, 0), maxs[0]),
             ((0, 0, -1), -mins[2]), ((0, -1, 0), -mins[1]), ((-1, 0, 0), -mins[0])]
    text = "".join(f"( {n[0]} {n[1]} {n[2]} {-d} ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/a\" 0 0 0\n"
                   for n, d in sides)
    return "{\nbrushDef3\n{\n" + text + "}\n}\n"


@pytest.fixture
def two_walls(tmp_path):
    """The C++ test's scene (test_query_contacts_rotation.cpp): walls y <= -10 for x >= 0 and y >= 14 for x <= 0."""
    path = tmp_path / "two_walls.map"
    path.write_text('Version 2\n{\n"classname" "worldspawn"\n' + box_brush((0, -40, -50), (100, -10, 100)) +
                    box_brush((-100, 14, -50), (0, 40, 100)) + "}\n")
    return cmkit.load_map(path)


def corner_angle(d):
    """Degrees a 60-long, 4-wide bar turns about its centre until a corner (30, 2) is 0.25 from a wall d away."""
    r = np.hypot(30.0, 2.0)
    return np.degrees(np.arcsin((d - 0.25) / r) - np.arctan(2.0 / 30))


def test_contacts_along_a_rotation_hand_computed(two_walls):
    world = two_walls[0]
    bar = cmkit.TraceModel.box((-30, -2, 0), (30, 2, 16))
    r = world.contacts(bar, (0, 0, 0), origins=(0, 0, 0), axes=(0, 0, 1), angles=30, max_contacts=8)
    assert list(r["status"]) == [cmkit.STATUS_OK] and r["count"][0] == 2
    assert r["angle"].shape == (1, 8) and r["angle"].dtype == np.float32
    # The +x end meets y = -10 (about 16.9 degrees), then the -x end y = 14 (about 23.5).
    assert r["angle"][0, 0] == pytest.approx(corner_angle(10), abs=1e-3)
    assert r["angle"][0, 1] == pytest.approx(corner_angle(14), abs=1e-3)
    assert list(r["type"][0, :2]) == [cmkit.CONTACT_TRM_VERTEX] * 2
    assert np.array_equal(r["normal"][0, :2], [[0, 1, 0], [0, -1, 0]])
    assert r["point"][0, 0, 1] == pytest.approx(-9.75, abs=1e-4)
    assert r["point"][0, 1, 1] == pytest.approx(13.75, abs=1e-4)
    assert np.all(r["angle"][0, 2:] == 0) and np.all(r["type"][0, 2:] == cmkit.CONTACT_NONE)
    # rotate() stops at the first contact.
    assert world.rotate(bar, (0, 0, 0), (0, 0, 0), (0, 0, 1), 30)["fraction"][0] * 30 == pytest.approx(
        r["angle"][0, 0], abs=1e-3)
    # Counter-clockwise meets nothing; a translation's contacts have angle 0.
    assert world.contacts(bar, (0, 0, 0), origins=(0, 0, 0), axes=(0, 0, 1), angles=-30)["count"][0] == 0
    moved = world.contacts(bar, (0, -7, 0), (0, -1, 0), 8)
    assert moved["count"][0] > 0 and np.all(moved["angle"] == 0)
    # The same answer as the query-file path, angle for angle (%.9g gives the float back).
    line = "contacts trm=box:-30,-2,0,30,2,16 start=0,0,0 rotorigin=0,0,0 rotaxis=0,0,1 angle=30 max=8"
    assert python_answer_matches(two_walls, line)
    fields = dict(kv.split("=", 1) for kv in cmkit._cmkit._answer_query_line(list(two_walls), line).split(" "))
    assert [np.float32(fields[f"angle.{k}"]) for k in range(2)] == list(r["angle"][0, :2])


def test_contacts_along_a_rotation_input(two_walls):
    world = two_walls[0]
    bar = cmkit.TraceModel.box((-30, -2, 0), (30, 2, 16))
    turn = dict(origins=(0, 0, 0), axes=(0, 0, 1), angles=30)
    # dirs may be given when zero, or with depth 0; with a depth beside the rotation the query is refused.
    base = world.contacts(bar, (0, 0, 0), **turn)
    assert_same(world.contacts(bar, (0, 0, 0), (0, 0, 0), 8, **turn), base)
    assert_same(world.contacts(bar, (0, 0, 0), (1, 0, 0), 0, **turn), base)
    mixed = world.contacts(bar, (0, 0, 0), (1, 0, 0), 8, **turn)
    assert list(mixed["status"]) == [cmkit.STATUS_MIXED_MOTION] and mixed["count"][0] == 0
    assert cmkit.status_name(cmkit.STATUS_MIXED_MOTION) == (
        "contacts query given both a translation (dir and depth) and a rotation")
    with pytest.raises(ValueError):
        cmkit.status_name(cmkit.STATUS_MIXED_MOTION + 1)
    with pytest.raises(ValueError, match="origins, axes and angles"):
        world.contacts(bar, (0, 0, 0), origins=(0, 0, 0), angles=30)
    with pytest.raises(ValueError, match="dirs"):
        world.contacts(bar, (0, 0, 0))
    with pytest.raises(ValueError, match="unit vector"):
        world.contacts(bar, (0, 0, 0), origins=(0, 0, 0), axes=(0, 0, 2), angles=30)
    with pytest.raises(cmkit.Error, match="starts, dirs and rotations"):
        world.contacts(bar, np.zeros((3, 3)), origins=np.zeros((2, 3)), axes=(0, 0, 1), angles=30)


# ---- progress, cancelling, bad input ----------------------------------------------------------------------


def test_progress_and_cancel(lt4):
    world = lt4[0]
    pts = random_points(world.bounds, 5000, 6)
    seen = []
    world.point_contents(pts, threads=1, progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (5000, 5000) and len(seen) > 10
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    with pytest.raises(cmkit.Error, match="batch cancelled after"):
        world.translate(PLAYER, pts, pts, threads=2, progress=lambda done, total: done < 1000)

    def broken(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        world.point_contents(pts, progress=broken)


def test_bad_input_raises(lt4):
    world = lt4[0]
    three = np.zeros((3, 3), np.float32)
    with pytest.raises(ValueError, match=r"starts must have shape \(N, 3\)"):
        world.translate(PLAYER, np.zeros((3, 2)), three)
    with pytest.raises(ValueError, match=r"ends\[1\] is not finite"):
        world.translate(PLAYER, three, [[0, 0, 0], [0, np.nan, 0], [0, 0, 0]])
    with pytest.raises(cmkit.Error, match="starts and ends .3 and 2"):
        world.translate(PLAYER, three, np.zeros((2, 3)))
    with pytest.raises(ValueError, match="threads"):
        world.point_contents(three, threads=-1)
    with pytest.raises(ValueError, match="unit vector"):
        world.rotate(PLAYER, three, three, (0, 0, 2), 10)
    with pytest.raises(ValueError, match="mask"):
        world.translate(PLAYER, three, three, mask=-1)
    with pytest.raises(ValueError, match="3x3"):
        world.translate(PLAYER, three, three, axis=np.eye(2))
    with pytest.raises(ValueError, match="depth"):
        world.contacts(PLAYER, three, three, -1)
    with pytest.raises(cmkit.Error):
        world.translate("box:nonsense", three, three)
    with pytest.raises(TypeError, match="trm must be a cmkit.TraceModel"):
        world.translate(42, three, three)


# ---- the same answers as the C++ API -----------------------------------------------------------------------

TYPES = {"none": cmkit.CONTACT_NONE, "edge": cmkit.CONTACT_EDGE, "modelvertex": cmkit.CONTACT_MODEL_VERTEX,
         "trmvertex": cmkit.CONTACT_TRM_VERTEX}


def f32(text):
    return np.array([float(x) for x in text.split(",")], dtype=np.float32)


def check_contact(fields, r, i, model, suffix=""):
    assert TYPES[fields["type" + suffix]] == r["type"][i]
    for key in ("point", "normal"):
        assert np.array_equal(f32(fields[key + suffix]), r[key][i]), key
    assert f32(fields["dist" + suffix])[0] == r["dist"][i]
    material = model.materials[r["material"][i]] if r["material"][i] >= 0 else "-"
    assert fields["material" + suffix] == material
    assert int(fields["modelfeature" + suffix]) == r["model_feature"][i]
    assert int(fields["trmfeature" + suffix]) == r["trm_feature"][i]


def python_answer_matches(models, line):
    """Runs a query line through the Python methods and checks every field of the C++ API's result line."""
    q = cmkit._cmkit._parse_query_line(list(models), line)
    if q is None:
        return False
    expected = cmkit._cmkit._answer_query_line(list(models), line)
    fields = dict(kv.split("=", 1) for kv in expected.split(" "))
    model = models[q["model"]]
    place = {"origin": q["origin"], "model_axis": q["model_axis"]}
    trm = q["trm"]
    common = dict(mask=q["mask"], axis=q["trm_axis"], **place)
    op = q["op"]
    if op == "pointcontents":
        assert int(fields["contents"]) == model.point_contents(q["start"], **place)["contents"][0], line
        return True
    if op == "contacts":
        turn = dict(origins=q["rot_origin"], axes=q["rot_axis"], angles=q["angle"]) if q["rotational"] else {}
        r = model.contacts(trm, q["start"], q["dir"], q["depth"], max_contacts=q["max_contacts"], **turn, **common)
        assert int(fields["count"]) == r["count"][0], line
        for k in range(r["count"][0]):
            assert fields[f"contents.{k}"] == str(r["contents"][0, k])
            check_contact(fields, {key: v[0] for key, v in r.items()}, k, model, f".{k}")
            # angle.k only along a rotation (other lines are as the reference results)
            assert fields.get(f"angle.{k}") == (f"{r['angle'][0, k]:.9g}" if q["rotational"] else None), line
        return True
    if op == "translation":
        r = model.translate(trm, q["start"], q["end"], **common)
    elif op == "rotation":
        r = model.rotate(trm, q["start"], q["rot_origin"], q["rot_axis"], q["angle"], **common)
    else:
        r = model.contents(trm, q["start"], **common)
        assert int(fields["result"]) == r["contents"][0], line
        r = dict(r, contents=r["contact_contents"])
    assert f32(fields["fraction"])[0] == r["fraction"][0], line
    assert np.array_equal(f32(fields["endpos"]), r["endpos"][0]), line
    assert np.array_equal(f32(fields["endaxis"]).reshape(3, 3), r["endaxis"][0]), line
    assert int(fields["contents"]) == r["contents"][0], line
    check_contact(fields, r, 0, model)
    return True


def test_same_answers_as_the_cpp_api_on_bundled_lt4(lt4):
    world = lt4[0]
    pts = random_points(world.bounds, 600, 8)
    ends = random_points(world.bounds, 600, 9, pad=32)
    specs = ["box:-16,-16,0,16,16,72", "cylinder:8:-12,-12,-20,12,12,20", "point", "bone:40,12"]

    def v(p):
        return ",".join(f"{x:.9g}" for x in p)

    lines = []
    for i in range(len(pts)):
        trm = specs[i % len(specs)]
        lines += [f"translation trm={trm} start={v(pts[i])} end={v(ends[i])}",
                  f"contents trm={trm} start={v(pts[i])}",
                  f"pointcontents pos={v(pts[i])}",
                  f"rotation trm={trm} start={v(pts[i])} rotorigin={v(pts[i] + 8)} rotaxis=0,0,1 angle={i % 300 - 150}",
                  f"contacts trm={trm} start={v(pts[i])} dir=0,0,-1 depth=24 max=6",
                  f"contacts trm={trm} start={v(pts[i])} rotorigin={v(pts[i] + 8)} rotaxis=0,0,1 "
                  f"angle={i % 300 - 150} max=6"]
    assert all(python_answer_matches(lt4, line) for line in lines)


@pytest.mark.parametrize("name", ["lt4", "box_room", "water_clip", "test"])
def test_same_answers_as_the_cpp_api_on_shared_reference_queries(shared_dir, name):
    maps = {p.stem: p for p in (shared_dir / "maps").rglob("*.map")}
    if name not in maps:
        pytest.skip(f"no {name}.map in {shared_dir / 'maps'}")
    models = cmkit.load_map(maps[name], use_proc=False)
    lines = [line for line in (shared_dir / "reference" / f"{name}.queries.txt").read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    ran = sum(python_answer_matches(models, line) for line in lines)
    assert ran > len(lines) * 0.9, f"only {ran} of {len(lines)} queries could run"


def test_import_without_installing_documents_itself():
    assert cmkit.__doc__ and cmkit.load_map.__doc__ and cmkit.Model.translate.__doc__
    assert "threads=" in cmkit.Model.cast_rays.__doc__
    assert str(LT4).endswith("lt4.map")


# ---- the example job ---------------------------------------------------------------------------------------


def test_walkable_example_writes_its_picture_and_summary(tmp_path):
    pytest.importorskip("matplotlib", reason="examples/python/walkable.py needs Debian's python3-matplotlib")
    import json
    import os
    import subprocess
    import sys

    from conftest import SOURCE_DIR

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "python" / "walkable.py"), str(LT4),
                          "--spacing", "32", "-o", str(tmp_path)], env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    summary = json.loads((tmp_path / "lt4-walkable.json").read_text())
    assert summary["walkable_cells"] > 1000 and summary["grid"] == [158, 127]
    assert -1100 < summary["floor_height_min"] < summary["floor_height_max"] < 400
    assert (tmp_path / "lt4-walkable.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "python" / "walkable.py"),
                          str(tmp_path / "missing.map")], env=env, capture_output=True, text=True, timeout=60)
    assert bad.returncode != 0 and "missing.map" in bad.stderr

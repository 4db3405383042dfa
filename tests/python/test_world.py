"""cmkit.World from Python: a map's entities placed by their keys, every query kind with the
entity hit (the same dicts as cmkit.Model's), set_transform, the same bits at any thread
count, the player walk, and bad arguments raising."""
import numpy as np
import pytest

import cmkit
from conftest import SOURCE_DIR

MAPS = SOURCE_DIR / "tests" / "data" / "maps"
TWO_HALLS = MAPS / "two_halls.map"
STAIRS = MAPS / "stairs.map"
PLAYER = cmkit.TraceModel.box((-16, -16, 0), (16, 16, 72))


@pytest.fixture()
def halls():
    # Function scope: tests move the door.
    return cmkit.load_world(TWO_HALLS)


@pytest.fixture(scope="module")
def stairs():
    return cmkit.load_world(STAIRS)


def assert_same(a, b, where=""):
    assert a.keys() == b.keys(), where
    for k in a:
        assert np.array_equal(a[k], b[k]), f"{where} field {k} differs"


def without_entity(results):
    return {k: v for k, v in results.items() if k != "entity"}


# ---- placement and entities ------------------------------------------------------------------


def test_two_halls_entities_and_placement(halls):
    # worldspawn, then door1 (the info_player_start owns no brushes).
    assert halls.entity_names == ["worldspawn", "door1"]
    assert len(halls) == 2
    assert halls.find("door1") == 1 and halls.find("worldspawn") == 0
    assert halls.info["entities_placed"] == 2 and halls.info["path"] == str(TWO_HALLS)
    # "origin" "0 0 48", "angle" "90": the door's long side turned across the doorway.
    origin, axis = halls.transform("door1")
    assert np.allclose(origin, [0, 0, 48])
    assert np.allclose(axis, [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-6)
    door = halls.model("door1")
    assert isinstance(door, cmkit.Model) and door.num_brushes == 1
    assert np.allclose(door.bounds, [[-32, -4, -48], [32, 4, 48]])


def test_the_door_stops_a_box_and_lets_it_pass_when_moved(halls):
    door = halls.find("door1")
    r = halls.translate(PLAYER, (-100, 0, 1), (100, 0, 1))
    assert r["fraction"][0] < 1
    assert r["endpos"][0, 0] == pytest.approx(-20.25)  # the door's face at x = -4, less 16 and 0.25
    assert r["entity"].dtype == np.int32 and r["entity"][0] == door
    assert np.allclose(r["normal"][0], [-1, 0, 0], atol=1e-6)

    halls.set_transform("door1", origin=(0, 0, 48 + 128))  # up into the ceiling
    assert np.allclose(halls.transform(door)[0], [0, 0, 176])
    r = halls.translate(PLAYER, (-100, 0, 1), (100, 0, 1))
    assert r["fraction"][0] == 1 and r["entity"][0] == -1
    assert np.allclose(r["endpos"][0], [100, 0, 1])

    halls.set_transform(door, (0, 0, 48), axis=[[0, 1, 0], [-1, 0, 0], [0, 0, 1]])  # back, by id
    r = halls.translate(PLAYER, (-100, 0, 1), (100, 0, 1))
    assert r["endpos"][0, 0] == pytest.approx(-20.25) and r["entity"][0] == door


def test_every_kind_reports_the_door(halls):
    door = halls.find("door1")
    rays = halls.cast_rays([[-100, 0, 40], [-100, 0, 110]], [[100, 0, 40], [-200, 0, 110]])
    assert rays["hit"].tolist() == [True, False]
    assert rays["endpos"][0, 0] == pytest.approx(-4) and rays["entity"].tolist() == [door, -1]
    pc = halls.point_contents([[0, 0, 40], [-100, 0, 40], [0, 0, -8]])
    assert pc["entity"].tolist() == [door, -1, 0]
    assert pc["contents"][0] & cmkit.CONTENTS_SOLID and pc["contents"][1] == 0
    ct = halls.contents(PLAYER, [[0, 0, 1], [-100, 0, 1]])
    assert ct["entity"].tolist() == [door, -1] and ct["contents"][1] == 0
    co = halls.contacts(PLAYER, (-20.5, 0, 1), (1, 0, 0), 1.0, max_contacts=8)
    n = co["count"][0]
    assert n >= 1 and co["entity"].shape == (1, 8)
    assert np.all(co["entity"][0, :n] == door) and np.all(co["entity"][0, n:] == -1)
    # A small box 40 units from a vertical axis at (-20, 40): turned one way it meets the door
    # about 20 degrees on (near y = 2), the other way nothing.
    ro = halls.rotate(cmkit.TraceModel.box((-2, -2, -2), (2, 2, 2)), (-20, 0, 40), (-20, 40, 40), (0, 0, 1),
                      [90, -90])
    assert sorted(ro["entity"].tolist()) == [-1, door]
    assert sorted(ro["fraction"].tolist())[0] < 0.3


def test_world_answers_equal_the_world_models_away_from_the_door(halls):
    model = cmkit.load_map(TWO_HALLS)[0]
    rng = np.random.default_rng(5)
    # The west hall, x -500..-100: the door (x -4..4) is out of reach of every query.
    lo, hi = np.array([-500, -120, 4]), np.array([-100, 120, 124])
    starts = (lo + rng.random((300, 3)) * (hi - lo)).astype(np.float32)
    ends = starts + ((rng.random((300, 3)) - 0.5) * [60, 300, 300]).astype(np.float32)
    small = cmkit.TraceModel.box((-4, -4, -4), (4, 4, 4))

    r = halls.translate(small, starts, ends, start_solid=True)
    assert_same(without_entity(r), model.translate(small, starts, ends, start_solid=True), "translate")
    assert np.array_equal(r["entity"], np.where(r["fraction"] < 1, 0, -1))
    assert (r["fraction"] < 1).sum() > 50

    r = halls.rotate(small, starts, starts + [0, 0, 20], (1, 0, 0), 60)
    assert_same(without_entity(r), model.rotate(small, starts, starts + [0, 0, 20], (1, 0, 0), 60), "rotate")
    r = halls.cast_rays(starts, ends)
    assert_same(without_entity(r), model.cast_rays(starts, ends), "cast_rays")
    assert np.array_equal(r["entity"], np.where(r["hit"], 0, -1))
    r = halls.point_contents(ends)
    assert_same(without_entity(r), model.point_contents(ends), "point_contents")
    r = halls.contents(small, ends)
    assert_same(without_entity(r), model.contents(small, ends), "contents")
    r = halls.contacts(small, starts, ends - starts, 8.0)
    assert_same(without_entity(r), model.contacts(small, starts, ends - starts, 8.0), "contacts")


def test_batches_give_the_same_bits_at_any_thread_count(halls):
    rng = np.random.default_rng(9)
    lo, hi = np.array([-520, -140, -20]), np.array([520, 140, 150])
    starts = (lo + rng.random((2000, 3)) * (hi - lo)).astype(np.float32)
    ends = (lo + rng.random((2000, 3)) * (hi - lo)).astype(np.float32)
    for call in (lambda t: halls.translate(PLAYER, starts, ends, threads=t),
                 lambda t: halls.rotate(PLAYER, starts, ends, (0, 0, 1), 45, threads=t),
                 lambda t: halls.cast_rays(starts, ends, threads=t),
                 lambda t: halls.point_contents(ends, threads=t),
                 lambda t: halls.contents(PLAYER, ends, threads=t),
                 lambda t: halls.contacts(PLAYER, starts, ends - starts, 4.0, threads=t)):
        one, two = call(1), call(2)
        assert_same(one, two)
    # The door is among the entities hit.
    assert np.any(halls.translate(PLAYER, starts, ends)["entity"] == 1)


def test_set_transform_waits_for_queries_in_other_threads(halls):
    # One thread opens and shuts the door while another queries: each batch sees one placement
    # (its rows all stopped by the door, or all passing), never a half-moved world.
    import threading

    door = halls.find("door1")
    _, axis = halls.transform(door)
    starts = np.tile(np.float32([-100, 0, 1]), (4000, 1))
    ends = np.tile(np.float32([100, 0, 1]), (4000, 1))
    stop = threading.Event()

    def toggle():
        up = False
        while not stop.is_set():
            up = not up
            halls.set_transform(door, (0, 0, 176 if up else 48), axis)

    mover = threading.Thread(target=toggle)
    mover.start()
    try:
        seen = set()
        for _ in range(30):
            entity = halls.translate(PLAYER, starts, ends, threads=2)["entity"]
            assert np.all(entity == entity[0])
            seen.add(int(entity[0]))
    finally:
        stop.set()
        mover.join()
    assert seen <= {door, -1}


# ---- the player walk -------------------------------------------------------------------------


def test_walk_up_the_stairs_and_held_by_high_risers(stairs):
    up = stairs.walk((-64, 64, 1), (1, 0), 4.0)
    assert np.allclose(up["end"], [239.75, 64, 60.25], atol=0.01)
    assert up["path"].shape == (240, 3) and up["steps"] == 240
    assert np.array_equal(up["path"][-1], up["end"])
    assert up["on_ground"] and up["ground_entity"] == "worldspawn" and up["ground_entity_id"] == 0
    assert not up["stuck"] and up["stuck_steps"] == 0
    held = stairs.walk((-64, -64, 1), (1, 0), 4.0)
    assert held["end"][0] == pytest.approx(47.75, abs=0.01)
    assert held["on_ground"]
    # The walk is deterministic.
    assert np.array_equal(stairs.walk((-64, 64, 1), (1, 0), 4.0)["path"], up["path"])


def test_walk_into_the_door_then_through_it(halls):
    shut = halls.walk((-64, 0, 1), (1, 0), 2.0)
    assert shut["end"][0] == pytest.approx(-20.25, abs=0.01)
    halls.set_transform("door1", origin=(0, 0, 176))
    opened = halls.walk((-64, 0, 1), (1, 0), 2.0)
    assert opened["end"][0] > 100 and opened["on_ground"]


def test_walk_options(stairs):
    jumped = stairs.walk((-100, 0, 1), (0, 0), 1.0, jump_at=0.1)
    assert jumped["path"][:, 2].max() == pytest.approx(48.25, abs=1.5)
    crouched = stairs.walk((-100, 0, 1), (0, 1), 1.0, crouch=True)
    ran = stairs.walk((-100, 0, 1), (0, 1), 0.5, run=True)
    walked = stairs.walk((-100, 0, 1), (0, 1), 0.5)
    assert crouched["crouched"] and ran["end"][1] > walked["end"][1]
    cyl = stairs.walk((-64, 64, 1), (1, 0), 4.0, shape="cylinder:8:-16,-16,0,16,16,74")
    assert cyl["end"][2] == pytest.approx(60.25, abs=0.01)
    assert stairs.walk((-64, 64, 1), (1, 0), 0)["path"].shape == (0, 3)


def test_ignore_leaves_entities_out(halls):
    # The door stops the box; ignored (by name, id, or in a list) it does not, and every query
    # kind takes the same argument.
    start, end = (-100, 0, 1), (100, 0, 1)
    assert halls.translate(PLAYER, start, end)["entity"][0] == 1
    for ignore in ("door1", 1, ["door1"], (1,), np.array([1])):
        r = halls.translate(PLAYER, start, end, ignore=ignore)
        assert r["fraction"][0] == 1.0 and r["entity"][0] == -1, ignore
    inside = (0, 0, 48)  # in the door's brush
    assert halls.point_contents(inside)["entity"][0] == 1
    assert halls.point_contents(inside, ignore="door1")["entity"][0] == -1
    assert halls.contents(PLAYER, (0, 0, 1))["entity"][0] == 1
    assert halls.contents(PLAYER, (0, 0, 1), ignore="door1")["entity"][0] != 1
    assert halls.cast_rays((-100, 0, 48), (100, 0, 48), ignore="door1")["entity"][0] == -1
    assert halls.contacts(PLAYER, (-21, 0, 1), (1, 0, 0), 8.0, ignore="door1")["count"][0] == 0
    r = halls.rotate(PLAYER, (-30, 0, 1), (-30, 0, 1), (0, 0, 1), 90.0, ignore=[0, "door1"])
    assert r["entity"][0] == -1
    with pytest.raises(KeyError, match="nobody"):
        halls.translate(PLAYER, start, end, ignore="nobody")
    with pytest.raises(TypeError):
        halls.translate(PLAYER, start, end, ignore=[1.5])


def test_walk_goes_on_from_a_velocity(stairs):
    # Up the stairs in one walk, and in two whose second starts with the first's end and
    # velocity: on static ground the state between steps is the feet and the velocity (the
    # ground is found again each step), so the two paths are the same bits.
    whole = stairs.walk((-64, 64, 1), (1, 0), 2.0)
    first = stairs.walk((-64, 64, 1), (1, 0), 1.0)
    second = stairs.walk(first["end"], (1, 0), 1.0, velocity=first["velocity"])
    assert np.array_equal(np.vstack([first["path"], second["path"]]), whole["path"])
    # Without the velocity the second walk starts at rest, and falls behind.
    rested = stairs.walk(first["end"], (1, 0), 1.0)
    assert rested["end"][0] < second["end"][0]
    with pytest.raises(ValueError, match="finite"):
        stairs.walk((0, 0, 1), (1, 0), 1.0, velocity=(np.nan, 0, 0))
    with pytest.raises(ValueError, match="velocity"):
        stairs.walk((0, 0, 1), (1, 0), 1.0, velocity=(1, 2))


def test_door_walk_example(tmp_path):
    # examples/python/door_walk.py: lt4's two doors stop the walk, then let it through once
    # turned open; the same lines as examples/door_walk.cpp prints.
    pytest.importorskip("matplotlib", reason="examples/python/door_walk.py needs Debian's python3-matplotlib")
    import os
    import subprocess
    import sys

    from conftest import LT4

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    picture = tmp_path / "door_walk.png"
    run = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "python" / "door_walk.py"), "--map",
                          str(LT4), "-o", str(picture)], env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    assert lines[1] == "doors closed: stopped at (952.25 -1483.50 -551.75) after 65 steps, stopped by lt4_door_wood_3"
    assert lines[2] == "doors open: arrived at (703.28 -1492.13 -551.75) after 141 steps"
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---- bad arguments ---------------------------------------------------------------------------


def test_bad_arguments_raise(halls):
    with pytest.raises(cmkit.Error, match="nothing.map"):
        cmkit.load_world(MAPS / "nothing.map")
    with pytest.raises(ValueError, match=r"starts must have shape \(N, 3\)"):
        halls.translate(PLAYER, [[1, 2]], [[3, 4, 5]])
    with pytest.raises(cmkit.Error, match="starts and ends"):
        halls.translate(PLAYER, np.zeros((3, 3)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="threads"):
        halls.translate(PLAYER, (0, 0, 0), (1, 0, 0), threads=-1)
    with pytest.raises(TypeError, match="trm must be a cmkit.TraceModel"):
        halls.translate(42, (0, 0, 0), (1, 0, 0))
    with pytest.raises(TypeError):  # a world places its own entities
        halls.translate(PLAYER, (0, 0, 0), (1, 0, 0), origin=(0, 0, 0))
    with pytest.raises(ValueError, match="max_contacts"):
        halls.contacts(PLAYER, (0, 0, 0), (1, 0, 0), 1.0, max_contacts=0)
    # Entities: unknown names and ids are KeyError, other types TypeError.
    for call in (lambda: halls.find("nothing"), lambda: halls.set_transform("nothing", (0, 0, 0)),
                 lambda: halls.set_transform(7, (0, 0, 0)), lambda: halls.transform(-1),
                 lambda: halls.model("nothing")):
        with pytest.raises(KeyError):
            call()
    with pytest.raises(TypeError, match="id .int. or name .str."):
        halls.set_transform(1.5, (0, 0, 0))
    with pytest.raises(ValueError, match="axis"):
        halls.set_transform("door1", (0, 0, 0), axis=np.eye(3) * 2)
    with pytest.raises(ValueError, match="3x3"):
        halls.set_transform("door1", (0, 0, 0), axis=np.eye(2))
    with pytest.raises(ValueError, match="origin"):
        halls.set_transform("door1", (0, 0, np.nan))
    assert np.allclose(halls.transform("door1")[0], [0, 0, 48])  # refused moves left it
    # The walk.
    with pytest.raises(ValueError, match="wish"):
        halls.walk((0, 0, 1), (1,), 1.0)
    with pytest.raises(ValueError, match="wish"):
        halls.walk((0, 0, 1), (np.inf, 0), 1.0)
    for seconds in (-1.0, np.nan, 4000.0):
        with pytest.raises(ValueError, match="seconds"):
            halls.walk((0, 0, 1), (1, 0), seconds)
    with pytest.raises(ValueError, match="jump_at"):
        halls.walk((0, 0, 1), (1, 0), 1.0, jump_at=-1)
    with pytest.raises(TypeError, match="shape"):
        halls.walk((0, 0, 1), (1, 0), 1.0, shape=5)
    with pytest.raises(cmkit.Error):
        halls.walk((0, 0, 1), (1, 0), 1.0, shape=cmkit.TraceModel.point())


def test_audit_finds_the_planted_faults_and_nothing_in_the_sealed_room():
    sealed = cmkit.load_world(MAPS / "audit_sealed.map").audit()
    assert sealed["reachable_cells"] > 800 and sealed["cells"].shape == (sealed["reachable_cells"], 3)
    for kind in ("fallouts", "stuck", "tunnels", "embedded", "open_shells"):
        assert sealed[kind] == [], kind
    assert not sealed["high_severity"]

    hole = cmkit.load_world(MAPS / "audit_hole.map").audit()
    assert hole["fallouts"] and hole["high_severity"]
    for f in hole["fallouts"]:  # the hole is x 64..160, y -48..48
        x, y, _ = f["position"]
        dx, dy = max(64 - x, 0, x - 160), max(-48 - y, 0, y - 48)
        assert (dx * dx + dy * dy) ** 0.5 <= 96, f
        assert f["kind"] == "fallout" and f["severity"] == "high" and len(f["path"]) >= 2
    assert [f["number"] for f in hole["fallouts"]] == list(range(1, len(hole["fallouts"]) + 1))

    pillar = cmkit.load_world(MAPS / "audit_pillar.map").audit(threads=2)
    assert [f["position"] for f in pillar["embedded"]] == [(128.0, 0.0, 1.0)]


def test_audit_is_the_same_at_any_thread_count_and_takes_starts():
    world = cmkit.load_world(MAPS / "audit_wedge.map")
    one, two = world.audit(threads=1), world.audit(threads=2)
    assert np.array_equal(one["cells"], two["cells"])
    assert one["stuck"] == two["stuck"] and len(one["stuck"]) == 1
    more = world.audit(starts=[[160, 160, 1]], open_shells=False)
    assert len(more["starts"]) == 2
    with pytest.raises(ValueError):
        world.audit(starts=[1, 2, 3])
    with pytest.raises(cmkit.Error):
        world.audit(grid=1)

# examples/python/fleet.py: the walkable job on a Dask LocalCluster (2 worker
# processes) gives exactly what the same job gives in this process.
import importlib.util
import pathlib
import shutil
import sys

import numpy as np
import pytest

from conftest import SHARED_DIR, SOURCE_DIR

pytest.importorskip("distributed", reason="needs Debian's python3-distributed (./dev.sh deps installs it)")

FLEET = SOURCE_DIR / "examples" / "python" / "fleet.py"


def load_fleet():
    sys.path.insert(0, str(FLEET.parent))
    spec = importlib.util.spec_from_file_location("fleet", FLEET)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def same(local, remote):
    (s1, h1, x1, y1), (s2, h2, x2, y2) = local, remote
    s1, s2 = dict(s1), dict(s2)
    s1.pop("seconds"), s2.pop("seconds")
    return s1 == s2 and np.array_equal(h1, h2, equal_nan=True) and np.array_equal(x1, x2) and np.array_equal(y1, y2)


def test_distributed_equals_local(tmp_path):
    fleet = load_fleet()
    maps = tmp_path / "maps"
    maps.mkdir()
    shutil.copy(SOURCE_DIR / "data" / "maps" / "lt4" / "lt4.map", maps)
    for name in ("features.map",):
        shutil.copy(SOURCE_DIR / "tests" / "data" / "maps" / name, maps)
    shared = SHARED_DIR / "maps"
    if shared.is_dir():  # a few of the shared maps as well (absent in a user's clone)
        for path in sorted(shared.glob("*/*.map"))[:4]:
            shutil.copy(path, maps / f"shared_{path.parent.name}_{path.name}")
    jobs = fleet.load_folder(maps)
    assert len(jobs) >= 2
    local = fleet.run_local(jobs, 64.0, 0.7)
    remote = fleet.run_distributed(jobs, 64.0, 0.7, workers=2, quiet=True)
    assert len(local) == len(remote) == len(jobs)
    for (name, _), a, b in zip(jobs, local, remote):
        assert same(a, b), name
    lt4 = next(r for (name, _), r in zip(jobs, remote) if name == "lt4")
    assert lt4[0]["walkable_cells"] > 100  # the job found floors, so the comparison means something
    report = fleet.write_report(remote, tmp_path / "out")
    assert (tmp_path / "out" / "fleet.json").is_file()
    assert (tmp_path / "out" / "lt4-walkable.png").is_file()
    assert {r["map"] for r in report} == {name for name, _ in jobs}

# Paths for the cmkit pytest suite (ctest python_pytest sets the environment;
# by hand: PYTHONPATH=BUILD/python python3 -m pytest tests/python).
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CMKIT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SHARED_DIR = pathlib.Path(os.environ.get("CMKIT_SHARED_DIR", SOURCE_DIR.parent / "shared"))
LT4 = SOURCE_DIR / "data" / "maps" / "lt4" / "lt4.map"


@pytest.fixture(scope="session")
def lt4():
    import cmkit

    return cmkit.load_map(LT4)


@pytest.fixture(scope="session")
def shared_dir():
    if not (SHARED_DIR / "reference").is_dir():
        pytest.skip(f"needs the shared data folder {SHARED_DIR} (maps and reference queries beside the clone); "
                    "absent, so skipped")
    return SHARED_DIR

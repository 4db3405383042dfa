"""cmkit: Doom 3 (id Tech 4) collision models for Python.

Load a map's collision models and ask many questions at once, numpy in, numpy out::

    import numpy as np
    import cmkit

    models = cmkit.load_map("data/maps/lt4/lt4.map")
    world = models[0]                       # or models["worldMap"]
    player = cmkit.TraceModel.box((-16, -16, 0), (16, 16, 72))
    r = world.translate(player, starts, ends)   # starts, ends: (N, 3)
    r["fraction"], r["endpos"], r["normal"]

A map's entities placed where its keys say, queried as one, with a player
that walks through them::

    world = cmkit.load_world("tests/data/maps/two_halls.map")
    r = world.translate(player, starts, ends)   # the same dict, plus r["entity"]
    world.set_transform("door1", origin=(0, 0, 176))
    world.walk((-64, 0, 1), (1, 0), 2.0)["end"]

Every batch method runs on all cores (threads=) with the GIL released, and
gives the same bits at any thread count. See docs/python.md.
"""

from collections.abc import Sequence as _Sequence

from ._cmkit import (  # noqa: F401  (re-exported)
    CONTACT_EDGE,
    CONTACT_MODEL_VERTEX,
    CONTACT_NONE,
    CONTACT_TRM_VERTEX,
    CONTENTS_SOLID,
    MASK_ALL,
    MASK_MONSTER_SOLID,
    MASK_OPAQUE,
    MASK_PLAYER_SOLID,
    MASK_SOLID,
    MASK_WATER,
    STATUS_BAD_MODEL_AXIS,
    STATUS_BAD_ROTATION_AXIS,
    STATUS_BAD_TRM_AXIS,
    STATUS_MIXED_MOTION,
    STATUS_NON_FINITE,
    STATUS_OK,
    STATUS_OUT_OF_RANGE,
    Error,
    Model,
    TraceModel,
    World,
    content_names,
    status_name,
)
from . import _cmkit

__all__ = [
    "CONTACT_EDGE", "CONTACT_MODEL_VERTEX", "CONTACT_NONE", "CONTACT_TRM_VERTEX", "CONTENTS_SOLID",
    "MASK_ALL", "MASK_MONSTER_SOLID", "MASK_OPAQUE", "MASK_PLAYER_SOLID", "MASK_SOLID", "MASK_WATER",
    "STATUS_BAD_MODEL_AXIS", "STATUS_BAD_ROTATION_AXIS", "STATUS_BAD_TRM_AXIS", "STATUS_MIXED_MOTION",
    "STATUS_NON_FINITE", "STATUS_OK", "STATUS_OUT_OF_RANGE",
    "Error", "Model", "Models", "TraceModel", "World", "content_names", "load_cm", "load_map", "load_world",
    "parse_cm", "status_name",
]


class Models(_Sequence):
    """The models of a map or .cm file, world first.

    Indexable by position (``models[0]``) and by name (``models["worldMap"]``:
    the first model of that name); iterable; ``len(models)``. ``crc`` is the
    map's geometry CRC (or the .cm file's), ``info`` says how the models were
    loaded (``from_cm``, ``cm_path``, ``proc_path``, ``proc_polygons_removed``).
    Pickles as .cm text.
    """

    def __init__(self, models, crc=0, info=None):
        self._models = list(models)
        self.crc = int(crc)
        self.info = dict(info or {})

    def __len__(self):
        return len(self._models)

    def __getitem__(self, key):
        if isinstance(key, str):
            for m in self._models:
                if m.name == key:
                    return m
            raise KeyError(f"no model named {key!r} (models: {', '.join(self.names)})")
        if isinstance(key, slice):
            return Models(self._models[key], self.crc, self.info)
        return self._models[key]

    def __contains__(self, key):
        if isinstance(key, str):
            return any(m.name == key for m in self._models)
        return key in self._models

    @property
    def names(self):
        """The model names, in order."""
        return [m.name for m in self._models]

    @property
    def world(self):
        """The first model (the world model of a map)."""
        return self._models[0]

    def to_cm(self):
        """All models as the text of one .cm file (with this CRC)."""
        return _cmkit._write_cm(self._models, self.crc)

    def save_cm(self, path):
        """Writes the models to a .cm file (replaced whole, never half-written)."""
        _cmkit._save_cm(str(path), self._models, self.crc)

    def __reduce__(self):
        return (_models_from_cm_text, (self.to_cm(), self.info))

    def __repr__(self):
        return f"<cmkit.Models {len(self)}: {', '.join(self.names[:5])}{', ...' if len(self) > 5 else ''}>"


def _models_from_cm_text(text, info):
    models, crc = _cmkit._parse_cm(text, "<pickled models>")
    return Models(models, crc, info)


def load_map(path, *, force_rebuild=False, use_proc=True):
    """Loads a .map file's collision models (world first) as Models.

    As the original engine: NAME.cm beside the map is used when its CRC
    matches the map (force_rebuild=True always builds); NAME.proc beside it
    prunes the world model (use_proc=False ignores it). Materials get the
    built-in content rules. Raises cmkit.Error ("file:line:column: message")
    for a missing or malformed file.
    """
    models, info = _cmkit._load_map(str(path), force_rebuild, use_proc)
    return Models(models, info["crc"], info)


def load_cm(path):
    """Loads every model of a .cm file as Models. Raises cmkit.Error for a bad file."""
    models, crc = _cmkit._load_cm(str(path))
    return Models(models, crc, {"from_cm": True, "cm_path": str(path)})


def parse_cm(text, name="<text>"):
    """Models from .cm text; `name` is used in error messages."""
    models, crc = _cmkit._parse_cm(text, name)
    return Models(models, crc, {"from_cm": True})


def load_world(path, *, force_rebuild=False, use_proc=True):
    """Loads a .map file as a World: its collision models placed as its entities.

    The models are made as load_map makes them (NAME.cm beside the map when
    its CRC matches, force_rebuild=True always builds; NAME.proc prunes the
    world model unless use_proc=False; the built-in material rules). Entity
    0 is the world model; then every entity with brushes or patches, placed
    by its origin / rotation / angle keys. Raises cmkit.Error
    ("file:line:column: message") for a missing or malformed file.
    """
    return _cmkit._load_world(str(path), force_rebuild, use_proc)

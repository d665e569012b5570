"""Scenes from Python values: overrides as "key=value" strings and whole scenes
from a dict. YAML's flow style is a superset of JSON, so json.dumps writes each
value (numbers, lists, nested dicts) as the scene loader reads it."""

import json
import os
import tempfile


def _scalar(value):
    if isinstance(value, str):
        return value
    return json.dumps(value)


def overrides(mapping):
    """["key=value", ...] from {"bond.k": 200, "gravity": [0, 0, 0]}."""
    out = []
    for key, value in mapping.items():
        if not isinstance(key, str):
            raise TypeError(f"Scene.load(): override keys must be str, not {type(key).__name__}")
        out.append(f"{key}={_scalar(value)}")
    return out


def load_dict(cls, scene, base_dir=None, extra=None):
    """Writes the dict as a YAML (JSON) file in base_dir and loads it with cls.load."""
    directory = os.fspath(base_dir) if base_dir is not None else os.getcwd()
    text = json.dumps(scene, indent=1)
    fd, path = tempfile.mkstemp(prefix="softbond-scene-", suffix=".yaml", dir=directory)
    try:
        with os.fdopen(fd, "w") as handle:
            handle.write(text + "\n")
        return cls.load(path, extra)
    finally:
        os.unlink(path)

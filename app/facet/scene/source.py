"""What a user names on the command line or drops on a window: a scene file or a mesh file,
either way a ``Scene`` (no GL)."""

from __future__ import annotations

from pathlib import Path

from .mesh import Mesh
from .scene import Scene


def is_scene_file(path) -> bool:
    return Path(path).suffix.lower() == ".toml"


def open_scene(path) -> Scene:
    """A scene file read with its settings, or a mesh file as a one-object scene."""
    if is_scene_file(path):
        from .scenefile import load_scene

        return load_scene(path)
    scene = Scene()
    scene.add(Mesh.load(path))
    return scene

"""What a user names on the command line or drops on a window: a scene file or a mesh file,
either way a ``Scene`` (no GL)."""

from __future__ import annotations

from pathlib import Path
from typing import cast

from ..boundary import Crease, FilePath, checked
from ..scene.scene import Scene
from .loading import read_parts


def is_scene_file(path) -> bool:
    return Path(path).suffix.lower() == ".toml"


@checked
def open_scene(path: FilePath, *, crease: Crease = None,
               confine: FilePath | None = None) -> Scene:
    """A scene file read with its settings, or a mesh file as a scene of its parts.

    A model's parts keep their own materials and node transforms; a glTF's cameras become
    named cameras (the default view stays framed on the model), its KHR_lights_punctual
    lights the scene's lights, its animations the scene's (``Scene.at``).

    Parameters
    ----------
    path : str or Path
        A scene file (.toml) or a mesh file (OBJ, STL, PLY, OFF, glTF/GLB, point clouds).
    crease : float, optional
        Where a file has no normals, split them at edges sharper than this many degrees.
    confine : str or Path, optional
        A folder outside which no file is read (facet.guard.confined).

    Returns
    -------
    Scene
        The scene.

    Raises
    ------
    facet.SceneError, facet.MeshError
        When a file cannot be read (one line naming it, the key or the element).
    """
    if confine is not None:
        from ..guard import confined

        with confined(confine):
            return open_scene(path, crease=crease)
    if is_scene_file(path):
        from .scenefile import load_scene

        return load_scene(path, crease=crease)
    from .splat_files import is_splat_file, read_splats

    if is_splat_file(path):  # Gaussian splats (3DGS PLY, .splat): a scene of the cloud
        scene = Scene()
        scene.add(read_splats(Path(path)))
        scene.frame_by_default = True
        return scene
    parts, cameras, lights, rig = read_parts(path, crease)
    scene = Scene()
    ids = [cast(int, scene.add(mesh, transform=matrix, name=name))  # one geometry: an id
           for name, mesh, matrix in parts]
    if rig is not None:
        from ..scene.animation import Animated

        scene.animated.append(Animated(rig, ids, cameras={n: n for n in rig.cameras}))
    for light in lights:
        scene.add_light(light)
    for name, camera in cameras.items():
        scene.add_camera(name, camera)
    scene.frame_by_default = True
    return scene


@checked
def load(path: FilePath, *, crease: Crease = None, confine: FilePath | None = None) -> Scene:
    """``open_scene`` under the short name: ``facet.load("truck.glb")``.

    Parameters
    ----------
    path, crease, confine
        As ``open_scene``'s.

    Returns
    -------
    Scene
        ``open_scene(path, crease=crease, confine=confine)``.
    """
    return open_scene(path, crease=crease, confine=confine)

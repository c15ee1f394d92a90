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
               confine: FilePath | None = None, variants: dict[str, str] | None = None,
               payloads: bool = True, purposes: tuple[str, ...] | None = None,
               joints: dict[str, float] | None = None,
               package_path: tuple[FilePath, ...] | None = None,
               collision: bool = False, subdivide: int = 0) -> Scene:
    """A scene file read with its settings, or a mesh file as a scene of its parts.

    A model's parts keep their own materials and node transforms; a glTF's cameras become
    named cameras (the default view stays framed on the model), its KHR_lights_punctual
    lights the scene's lights, its animations the scene's (``Scene.at``).

    Parameters
    ----------
    path : str or Path
        A scene file (.toml), a mesh file (OBJ, STL, PLY, OFF, glTF/GLB, point clouds) or
        an OpenUSD stage (.usd, .usda, .usdc, .usdz; the ``usd`` extra) or a URDF robot
        (.urdf; the ``urdf`` extra).
    crease : float, optional
        Where a file has no normals, split them at edges sharper than this many degrees.
    confine : str or Path, optional
        A folder outside which no file is read (facet.guard.confined).
    variants : dict, optional
        A USD stage's variant selections, ``{set: variant}`` (on every prim with that set).
    payloads : bool
        Whether a USD stage's payloads are loaded (default True).
    purposes : tuple of str, optional
        The USD purposes drawn (default ``("default", "render")``; add "proxy", "guide").
    subdivide : int
        Refine a USD stage's subdivision surfaces this many levels (Catmull-Clark, Loop;
        default 0: the control cage, as usdview draws it by default).
    joints : dict, optional
        A URDF robot's configuration, ``{joint: value}`` (radians, metres; within the
        joints' limits; mimic joints follow).
    package_path : tuple of str or Path, optional
        Folders where a URDF's ``package://`` names are looked for (before
        ``ROS_PACKAGE_PATH`` and the folders above the file).
    collision : bool
        A URDF robot's collision geometry instead of its visual geometry.

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
            return open_scene(path, crease=crease, variants=variants, payloads=payloads,
                              purposes=purposes, joints=joints, package_path=package_path,
                              collision=collision, subdivide=subdivide)
    if is_scene_file(path):
        from .scenefile import load_scene

        return load_scene(path, crease=crease)
    from .splat_files import is_splat_file, read_splats

    if is_splat_file(path):  # Gaussian splats (3DGS PLY, .splat): a scene of the cloud
        scene = Scene()
        scene.add(read_splats(Path(path)))
        scene.frame_by_default = True
        return scene
    usd = None
    if variants or not payloads or purposes is not None or subdivide:
        from .usd_stage import USD_SUFFIXES

        if Path(path).suffix.lower() not in USD_SUFFIXES:
            from ..errors import InputError

            raise InputError(f"{path}: variants, payloads, purposes and subdivide choose what "
                             "an OpenUSD stage composes; this is not one (a glTF's material "
                             "variants are the 'variant' render option)")
        from .usd import DRAWN_PURPOSES, UsdOptions

        usd = UsdOptions(variants, payloads, purposes or DRAWN_PURPOSES, subdivide)
    urdf = None
    if joints or package_path or collision:
        if Path(path).suffix.lower() != ".urdf":
            from ..errors import InputError

            raise InputError(f"{path}: joints, package_path and collision pose and find a "
                             "URDF robot; this is not one")
        urdf = {"joints": joints, "package_path": package_path, "collision": collision}
    if crease is not None and not subdivide:
        from .usd_stage import USD_SUFFIXES

        if Path(path).suffix.lower() in USD_SUFFIXES:
            import warnings

            from ..errors import FacetWarning

            warnings.warn(f"{Path(path).name}: crease: a stage's meshes without normals are "
                          "shaded as usdview shades them (subdivision cages smooth, polygonal "
                          "meshes flat); the crease angle applies to meshes refined by "
                          "subdivide only", FacetWarning, stacklevel=3)
    parts, cameras, lights, rig = read_parts(path, crease, usd, urdf)
    scene = Scene()
    ids = [cast(int, scene.add(mesh, transform=matrix, name=name))  # one geometry: an id
           for name, mesh, matrix in parts]
    if rig is not None:
        from ..scene.animation import Animated

        scene.animated.append(Animated(rig, ids, cameras={n: n for n in rig.cameras}))
    from ..scene.environment import Environment

    for light in lights:
        if isinstance(light, Environment):  # a USD stage's dome
            scene.environment = light
        elif hasattr(light, "up"):  # a USD stage's upAxis (facet.formats.usd)
            if light.up != "y":
                from ..scene.readers import reader

                scene.options = reader("render options")({"up": light.up})
        else:
            scene.add_light(light)
    for name, camera in cameras.items():
        scene.add_camera(name, camera)
    scene.frame_by_default = True
    return scene


@checked
def load(path: FilePath, *, crease: Crease = None, confine: FilePath | None = None,
         variants: dict[str, str] | None = None, payloads: bool = True,
         purposes: tuple[str, ...] | None = None, joints: dict[str, float] | None = None,
         package_path: tuple[FilePath, ...] | None = None, collision: bool = False,
         subdivide: int = 0) -> Scene:
    """``open_scene`` under the short name: ``facet.load("truck.glb")``.

    Parameters
    ----------
    path, crease, confine, variants, payloads, purposes, joints, package_path, collision,
    subdivide
        As ``open_scene``'s.

    Returns
    -------
    Scene
        ``open_scene(path, ...)`` with the same arguments.
    """
    return open_scene(path, crease=crease, confine=confine, variants=variants,
                      payloads=payloads, purposes=purposes, joints=joints,
                      package_path=package_path, collision=collision, subdivide=subdivide)

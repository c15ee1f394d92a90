"""A scene: meshes placed by model matrices, their materials, lights, ambient and background.

No GL lives here; a ``Renderer`` caches GPU copies keyed by these objects.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Annotated, cast

import numpy as np

from ..boundary import ArgumentError, Array, ArrayLike, Color, checked
from ..errors import InputError
from ..geometry import transforms as T
from ..geometry.camera import Camera
from .light import AreaLight, DirectionalLight, Light, PointLight, SpotLight
from .material import Material, as_color
from .mesh import Mesh
from .readers import reader  # facet.formats (trimesh objects), facet.options (options)

if TYPE_CHECKING:
    from .environment import Environment
    from .pbr import PbrMaterial
    from .points import Lines, Points
    from .shapes import Shape

# The shader's light array size; also the most lights a scene may hold.
MAX_LIGHTS = 16


@dataclass
class SceneObject:
    """One placed mesh. ``transform``: 4x4 object -> world. ``id``: its label in id buffers."""

    id: int
    mesh: Mesh | Points | Lines
    material: Material | PbrMaterial
    transform: np.ndarray = field(default_factory=lambda: np.eye(4))
    name: str = ""
    # Motion blur: the object -> world matrix at shutter close (``transform`` is at shutter
    # open); None for an object that does not move.
    transform_end: np.ndarray | None = None
    # An exact analytic shape (facet.scene.shapes) the ray tracer intersects; ``mesh`` is
    # then its tessellation, which the rasterizer draws. None for meshes.
    shape: Shape | None = None

    @property
    def infinite(self) -> bool:
        return self.shape is not None and self.shape.infinite

    @property
    def world_bounds(self) -> np.ndarray:
        b = self.mesh.bounds
        corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
        w = T.transform_points(self.transform, corners)
        return np.stack([w.min(axis=0), w.max(axis=0)])


DEFAULT_AMBIENT = 0.1  # the notes' ambient term when a scene gives none


class Scene:
    """Objects, lights, ambient light ``I_a``, background colour, and named cameras.

    Parameters
    ----------
    ambient : grey level or (3,) floats in [0, 1], optional
        The ambient intensity I_a. Not given: 0.1 for the rasterizer's and the Whitted
        tracer's ambient term, and no light at all for the path tracer, which lights only
        by what a scene declares (``ambient_declared`` says whether it was given, here or
        by setting ``ambient``).
    background : (3,) or (4,) floats in [0, 1]; alpha 0 gives a transparent background
    options : render options this scene asks for (a scene file's [render] table), e.g.
        ``{"shadows": True, "lights": "scene"}``; explicit arguments override them
        (facet.options.render parses them: a bad value is one error here). Without lights
        the scene is lit by the default key + fill rig following the camera unless
        ``lights`` is "scene".
    """

    @checked
    def __init__(self, ambient: Annotated[ArrayLike | None, Array("", "3")] = None,
                 background: Color = (0.0, 0.0, 0.0, 1.0), options=None) -> None:
        self._ambient = as_color(DEFAULT_AMBIENT if ambient is None else ambient, "ambient")
        self.ambient_declared = ambient is not None
        bg = as_color(background, "background", channels=(3, 4))
        self.background = np.append(bg, 1.0) if bg.size == 3 else bg
        self.objects: list[SceneObject] = []
        # Gaussian splat clouds (facet.scene.splats.SplatObject): the rasterizer draws them
        # over the objects; their ids follow the objects' (one numbering).
        self.splats: list = []
        self.lights: list[Light] = []
        self.cameras: dict[str, Camera] = {}
        # parsed once, here (by facet.options.render's parser): {option: typed value}
        self.options = reader("render options")(options)
        # A facet.scene.environment.Environment: background and reflection source.
        self.environment: Environment | None = None
        # True for a model file's scene: its cameras (glTF's) are there to be chosen by
        # name, the default view frames the model.
        self.frame_by_default = False
        # facet.scene.animation.Animated: rigs (animations, skins, morph targets) that
        # pose some of the objects and cameras at a time (``at``).
        self.animated: list = []

    @property
    def ambient(self) -> np.ndarray:
        """(3,) float: the ambient intensity I_a (0.1 when no one gave one)."""
        return self._ambient

    @ambient.setter
    def ambient(self, value) -> None:
        self._ambient = as_color(value, "ambient")
        self.ambient_declared = True

    @checked
    def add(self, mesh, material: Material | PbrMaterial | None = None,
            transform: Annotated[ArrayLike | None, Array("4,4")] = None, *,
            name: str = "", transform_end: Annotated[ArrayLike | None, Array("4,4")] = None
            ) -> int | list[int]:
        """Place a mesh, a cloud, lines, a shape or a trimesh geometry in the scene.

        Parameters
        ----------
        mesh : Mesh, Points, Lines, Splats, facet.shapes shape, trimesh geometry or Scene
            What to place (trimesh's Trimesh / PointCloud / Scene through
            facet.formats.adapters: colours, uvs, materials; a Scene's parts each placed
            by its graph, then by ``transform``; Splats: Gaussian splats, drawn by the
            rasterizer, with no material; a facet Scene, such as ``facet.load`` of a
            robot in some configuration: its objects placed by ``transform``, with their
            animations and joints, so ``posed`` and ``at`` move them there too).
        material : Material or PbrMaterial, optional
            Default: the file's own material, else a grey ``Material()``.
        transform : (4, 4) float, optional
            Object -> world (default identity; must be invertible).
        name : str
            Label (default: the mesh's name).
        transform_end : (4, 4) float, optional
            The transform at shutter close: the object is motion-blurred between the two.

        Returns
        -------
        int or list of int
            The object's id (0, 1, 2, ...: its value in ``Frame.object_ids``), or a trimesh
            Scene's or a facet Scene's parts' ids.
        """
        from .points import Lines, Points
        from .shapes import Shape
        from .splats import SplatObject, Splats

        if isinstance(mesh, Scene):  # a loaded model (a robot, a stage): its objects
            if material is not None or transform_end is not None:
                raise InputError("Scene.add of a scene: its objects keep their materials "
                                 "and motion; give no material and no transform_end")
            from .articulated import add_scene

            return add_scene(self, mesh, transform)
        if isinstance(mesh, Splats):
            m = np.eye(4) if transform is None else np.asarray(transform, dtype=np.float64)
            if m.shape != (4, 4) or not np.all(np.isfinite(m)):
                raise InputError(f"transform must be a finite 4x4 matrix, got shape {m.shape}")
            T.normal_matrix(m)
            if material is not None or transform_end is not None:
                raise InputError("splats carry their own colours and do not move within a "
                                 "frame: give no material and no transform_end")
            cloud = SplatObject(self._next_id(), mesh, m, name or mesh.name)
            self.splats.append(cloud)
            return cloud.id
        if reader("is trimesh")(mesh):
            parts = reader("trimesh")(mesh, Mesh)
            base = np.eye(4) if transform is None else np.asarray(transform, np.float64)
            ids = [cast(int, self.add(part, material, base @ matrix, name=name or part_name,
                                      transform_end=transform_end))  # one geometry: an id
                   for part_name, part, matrix in parts]
            return ids if type(mesh).__name__ == "Scene" else ids[0]

        shape = mesh if isinstance(mesh, Shape) else None
        if shape is not None:
            mesh = shape.mesh()
        if not isinstance(mesh, (Mesh, Points, Lines)):
            raise ArgumentError(f"Scene.add: mesh: expected a facet.Mesh, facet.Points, "
                                f"facet.Lines, facet.Splats, a facet.shapes shape or a trimesh "
                                f"geometry, got {type(mesh).__name__}")
        m = np.eye(4) if transform is None else np.asarray(transform, dtype=np.float64)
        if m.shape != (4, 4) or not np.all(np.isfinite(m)):
            raise InputError(f"transform must be a finite 4x4 matrix, got shape {m.shape}")
        T.normal_matrix(m)  # rejects singular transforms here rather than at draw time
        own = cast("Material | PbrMaterial | None", shape.material) if shape is not None \
            else None
        material = material or own or mesh.material or Material()
        end = None
        if transform_end is not None:
            end = np.asarray(transform_end, dtype=np.float64)
            if end.shape != (4, 4) or not np.all(np.isfinite(end)):
                raise InputError("transform_end must be a finite 4x4 matrix")
            T.normal_matrix(end)
        obj = SceneObject(self._next_id(), mesh, material, m, name or mesh.name, end, shape)
        self.objects.append(obj)
        return obj.id

    def _next_id(self) -> int:
        return len(self.objects) + len(getattr(self, "splats", ()))

    @checked
    def add_light(self, light: Light) -> Light:
        """Add a light (at most ``MAX_LIGHTS``).

        Parameters
        ----------
        light : DirectionalLight, PointLight, SpotLight or AreaLight
            The light, world space.

        Returns
        -------
        Light
            ``light``.
        """
        if not isinstance(light, (DirectionalLight, PointLight, SpotLight, AreaLight)):
            raise InputError(f"add_light expects a facet light, got {type(light).__name__}")
        if len(self.lights) >= MAX_LIGHTS:
            raise InputError(f"a scene holds at most {MAX_LIGHTS} lights")
        self.lights.append(light)
        return light

    @checked
    def add_camera(self, name: str, camera: Camera) -> Camera:
        """Name a camera (scene files and ``--camera`` select cameras by name).

        Parameters
        ----------
        name : str
            The name.
        camera : Camera
            The camera.

        Returns
        -------
        Camera
            ``camera``.
        """
        if not isinstance(camera, Camera):
            raise InputError(f"add_camera expects a facet.Camera, got {type(camera).__name__}")
        self.cameras[name] = camera
        return camera

    def camera(self, name: str | None = None) -> Camera | None:
        """The camera a render of this scene uses.

        Parameters
        ----------
        name : str, optional
            A camera's name, ``"first"`` (the first camera: a model file's own, such as the
            one it was authored with) or an index ("0", "1", ... in the file's order);
            without one the options' ``camera``, else the first one (none for a model
            file's scene, which is framed).

        Returns
        -------
        Camera or None
            The camera, or None: the renderer frames the scene.
        """
        name = name or self.options.get("camera")
        if name is None and self.frame_by_default:
            return None
        if name is not None:
            return self.cameras[self.camera_key(name)]
        return next(iter(self.cameras.values()), None)

    def camera_key(self, name) -> str:
        """The name of the camera that ``name`` picks.

        Parameters
        ----------
        name : str or int
            A camera's name, ``"first"``, or an index in the order the cameras were added
            (a camera named so wins over the other readings).

        Returns
        -------
        str
            The key of ``cameras``; InputError naming the cameras when ``name`` picks none.
        """
        names = list(self.cameras)
        text = str(name)
        if text in self.cameras:
            return text
        if text == "first" and names:
            return names[0]
        if text.isdigit() and int(text) < len(names):
            return names[int(text)]
        known = ", ".join(names) or "none"
        picks = f"; or 'first', or an index 0-{len(names) - 1}" if names else ""
        raise InputError(f"no camera named {text!r} (cameras: {known}{picks})")

    def at(self, time: float = 0.0, animation=None) -> Scene:
        """The scene as it stands at ``time``, its animations playing, skins and morph
        targets applied (renders do this with their ``time`` and ``animation`` options).

        Parameters
        ----------
        time : float
            Seconds.
        animation : str or int, optional
            Play only the animation of this name or index (default: all of them).

        Returns
        -------
        Scene
            A view sharing everything else (facet.scene.animation).
        """
        from .animation import pose_scene

        return pose_scene(self, time, animation)

    @checked
    def posed(self, joints: dict[str, float]) -> Scene:
        """The scene with its robots (URDF models) in another joint configuration.

        Parameters
        ----------
        joints : dict
            ``{joint: value}``: radians for revolute and continuous joints, metres for
            prismatic ones, within their limits; mimic joints follow. Joints not named
            keep their values.

        Returns
        -------
        Scene
            A view sharing the meshes (facet.scene.articulated); it poses again.

        Raises
        ------
        facet.InputError
            A joint no robot has, a value outside its limits, or no robot in the scene.
        """
        from .articulated import posed

        return posed(self, joints)

    @property
    def joints(self) -> dict[str, tuple[float, float]]:
        """``{joint: (lower, upper)}`` of the scene's robots' joints that take a value."""
        from .articulated import joint_ranges

        return joint_ranges(self)

    @property
    def animations(self) -> list[str]:
        """The names of the animations of the scene's models."""
        return [name for a in self.animated for name in a.rig.clip_names]

    def view(self, objects=None, lights=None) -> Scene:
        """A shallow copy sharing everything but ``objects`` and/or ``lights`` (for passes
        that draw part of a scene or swap its lights; no GL involved).

        Parameters
        ----------
        objects : list of SceneObject, optional
            The objects of the copy.
        lights : list of Light, optional
            The lights of the copy.

        Returns
        -------
        Scene
            The copy.
        """
        copy = Scene.__new__(Scene)
        copy.__dict__.update(self.__dict__)
        if objects is not None:
            copy.objects = list(objects)
        if lights is not None:
            copy.lights = list(lights)
        return copy

    @property
    def bounds(self) -> np.ndarray:
        """World-space bounds of all objects, (2, 3). Infinite planes are left out (unless
        there is nothing else): they would make every framing and shadow map infinite."""
        clouds = [c for c in getattr(self, "splats", ()) if c.splats.count]
        if not self.objects and not clouds:
            raise InputError("the scene is empty; add a mesh first")
        finite = [o for o in self.objects if not o.infinite] or self.objects
        b = np.array([o.world_bounds for o in finite] + [c.world_bounds for c in clouds])
        return np.stack([b[:, 0].min(axis=0), b[:, 1].max(axis=0)])

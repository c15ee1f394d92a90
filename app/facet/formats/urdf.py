"""URDF robots -> facet parts (no GL), through yourdfpy (the ``urdf`` extra) for the
kinematics: what ``facet render robot.urdf --joints ...`` and ``facet.load(robot.urdf,
joints=...)`` read.

The file's bytes come through the guard and are parsed by lxml without a DTD, entities or
the network (a URDF needs none of them); yourdfpy then builds the kinematic tree, and the
configuration (``joints``: {name: value}, radians for revolute and continuous joints,
metres for prismatic ones; mimic joints follow theirs, as yourdfpy computes them) places
every link. A value outside a joint's limits, or a joint the robot does not have, is one
error naming it (and its range, or the joints there are). Each link's visual elements
(``collision`` for its collision elements instead) are parts: boxes, cylinders (along
their z) and spheres as facet's exact shapes; meshes (STL, OBJ, PLY, glTF through facet's
own readers, scaled by ``scale``) found by their path: ``package://PKG/...`` in the
search path (``package_path`` folders, then ``ROS_PACKAGE_PATH``, then the folders above
the URDF: a folder named PKG or holding PKG), ``file://`` and plain paths beside the URDF,
every one read through the guard and inside ``--confine``. A material's colour (its own or
the robot's named one) is the part's base colour; a texture is read the same way. URDF is
z-up: framing and turntables follow.

The forward kinematics are facet's own, in numpy (Kinematics: yourdfpy's rules, checked
against its poses in the tests, a hundred times faster than asking it for every link),
and the parts hang on an Articulation rig, so ``Scene.posed(joints)`` poses a loaded robot
again without reading it (facet.scene.articulated; a dataset's views each in their own
configuration).
"""

from __future__ import annotations

import io
import os
import warnings
from pathlib import Path

import numpy as np

from ..errors import FacetWarning, InputError, MeshError
from ..scene.animation import Binding, Rig

URDF_MISSING = "reading URDF robots needs yourdfpy: pip install 'facet-render[urdf]'"


def _require(path) -> None:
    try:
        import yourdfpy  # noqa: F401
    except ImportError:
        raise MeshError(f"{path}: {URDF_MISSING}") from None


def parse_robot(path: Path):
    """A yourdfpy URDF of the file at ``path`` (its kinematic tree; no mesh read)."""
    _require(path)
    import yourdfpy
    from lxml import etree

    from ..guard import read_bytes

    data = read_bytes(path, "URDF file", MeshError)
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise MeshError(f"{path}: declares a DTD or entities; a URDF needs neither, and "
                        "facet does not expand them")
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False,
                             remove_blank_text=True, huge_tree=False)
    try:
        root = etree.parse(io.BytesIO(data), parser).getroot()
    except etree.XMLSyntaxError as exc:
        raise MeshError(f"{path}: not well-formed XML ({exc})") from None
    if root.tag != "robot":
        raise MeshError(f"{path}: not a URDF (its root element is <{root.tag}>, not "
                        "<robot>)")
    etree.strip_tags(root, etree.Comment)
    try:
        robot = yourdfpy.URDF(robot=yourdfpy.URDF._parse_robot(xml_element=root),
                              build_scene_graph=True, load_meshes=False)
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise MeshError(f"{path}: a URDF yourdfpy cannot read ({exc})") from None
    return robot


class Kinematics:
    """A robot's joint tree posed in numpy: each joint's origin, then its motion (a turn
    by q about its unit axis for revolute and continuous joints, q times its axis for
    prismatic ones; mimic joints q = multiplier x q(theirs) + offset; fixed, floating
    and planar joints their origin, as yourdfpy poses them), parents first from the base
    link. Joints not given stand at 0."""

    def __init__(self, robot, path, notes: list):
        self.path, self.base = path, robot.base_link
        self.joint_map = robot.joint_map
        self.actuated = list(robot.actuated_joint_names)
        self.movable = [name for name in self.actuated  # (the joints that take a value)
                        if self.joint_map[name].type in ("revolute", "continuous",
                                                         "prismatic")]
        by_parent: dict = {}
        for joint in robot.robot.joints:
            by_parent.setdefault(joint.parent, []).append(joint)
        self.chain, todo = [], [self.base]  # joints, parents before children
        while todo:
            for joint in by_parent.get(todo.pop(), []):
                self.chain.append(joint)
                todo.append(joint.child)
        free = [j.name for j in self.chain if j.type in ("floating", "planar")]
        if free:
            notes.append(f"joints {', '.join(free)} (floating, planar) stand at their origin")

    def check(self, joints: dict | None) -> dict:
        """``joints`` checked (the module docstring's rules): {name: float}."""
        path, cfg = self.path, {}
        for name, value in dict(joints or {}).items():
            if name not in self.joint_map:
                raise InputError(f"{path}: no joint named {name!r}; its joints are "
                                 f"{', '.join(self.movable) or 'none'}")
            joint = self.joint_map[name]
            if joint.mimic is not None:
                raise InputError(f"{path}: joint {name!r} mimics {joint.mimic.joint!r}; set "
                                 f"{joint.mimic.joint!r} instead")
            if joint.type not in ("revolute", "continuous", "prismatic"):
                raise InputError(f"{path}: joint {name!r} is {joint.type}; it takes no value")
            v = float(value)
            if not np.isfinite(v):
                raise InputError(f"{path}: joint {name!r}: a value must be finite, got "
                                 f"{value!r}")
            limit = joint.limit
            if joint.type in ("revolute", "prismatic") and limit is not None and \
                    limit.lower is not None and limit.upper is not None and \
                    not limit.lower - 1e-9 <= v <= limit.upper + 1e-9:
                unit = "m" if joint.type == "prismatic" else "rad"
                raise InputError(f"{path}: joint {name!r} = {v:g} {unit} is outside its "
                                 f"limits [{limit.lower:g}, {limit.upper:g}] {unit}")
            cfg[name] = v
        return cfg

    def link_poses(self, cfg: dict) -> dict:
        """{link: 4x4 link -> base} at the checked configuration ``cfg``."""
        poses = {self.base: np.eye(4)}
        for joint in self.chain:
            m = np.eye(4) if joint.origin is None else np.asarray(joint.origin, float)
            q = cfg.get(joint.name, 0.0)
            if joint.mimic is not None:
                mimic = joint.mimic
                q = (cfg.get(mimic.joint, 0.0) if mimic.joint in self.actuated else 0.0) * \
                    (1.0 if mimic.multiplier is None else mimic.multiplier) + \
                    (0.0 if mimic.offset is None else mimic.offset)
            axis = np.array([1.0, 0, 0]) if joint.axis is None else \
                np.asarray(joint.axis, float)
            if joint.type == "prismatic":
                m = m @ _translation(q * axis)
            elif joint.type in ("revolute", "continuous"):
                m = m @ _rotation(q, axis)
            poses[joint.child] = poses[joint.parent] @ m
        return poses


def _translation(v) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = v
    return m


def _rotation(angle: float, axis) -> np.ndarray:
    """The turn by ``angle`` radians about ``axis`` (Rodrigues)."""
    n = np.linalg.norm(axis)
    x, y, z = np.asarray(axis, float) / (n if n > 0 else 1.0)
    c, s = np.cos(angle), np.sin(angle)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + s * k + (1 - c) * (k @ k)
    return m


class Articulation(Rig):
    """A robot's parts on its links, posed by a joint configuration: a facet Rig with no
    clips (each part a node fixed at link pose x its local placement), so a posed robot
    goes wherever a scene goes; ``configured(joints)`` is the same robot in another
    configuration (the joints given set, the others kept)."""

    def __init__(self, kinematics: Kinematics, links: list, local: list, cfg: dict):
        self.kinematics, self.links, self.local = kinematics, links, local
        self.configuration = dict(cfg)
        n = len(links)
        poses = kinematics.link_poses(cfg)
        fixed = {k: poses[link] @ m for k, (link, m) in enumerate(zip(links, local,
                                                                      strict=True))}
        super().__init__(np.full(n, -1), range(n), (np.zeros((n, 3)), np.tile(
            [0, 0, 0, 1.0], (n, 1)), np.ones((n, 3))), fixed, {}, [], [],
            [Binding(k, k, None, None) for k in range(n)])

    def ranges(self) -> dict[str, tuple[float, float]]:
        """{joint: (lower, upper)} of the joints that take a value (continuous joints,
        and those whose file gives no limits: (-pi, pi) radians, (0, 0) metres)."""
        out = {}
        for name in self.kinematics.movable:
            joint = self.kinematics.joint_map[name]
            limit = joint.limit
            if joint.type != "continuous" and limit is not None and \
                    limit.lower is not None and limit.upper is not None:
                out[name] = (float(limit.lower), float(limit.upper))
            else:
                out[name] = (0.0, 0.0) if joint.type == "prismatic" else (-np.pi, np.pi)
        return out

    def configured(self, joints: dict) -> Articulation:
        """This robot with ``joints`` {name: value} set (checked; those it lacks are the
        caller's to refuse), the others as they were."""
        mine = {k: v for k, v in joints.items() if k in self.kinematics.joint_map}
        return Articulation(self.kinematics, self.links, self.local,
                            {**self.configuration, **self.kinematics.check(mine)})

    def placements(self) -> list:
        """Each part's 4x4 part -> robot base at this configuration."""
        return [self.fixed[k] for k in range(len(self.links))]


def _search_path(urdf: Path, extra) -> list[Path]:
    roots = [Path(p) for p in (extra or [])]
    roots += [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    roots += list(urdf.resolve().parents)[:4]
    return roots


def resolve(filename: str, urdf: Path, package_path) -> Path:
    """The file a URDF mesh or texture name refers to (module docstring)."""
    if filename.startswith("package://"):
        pkg, _, rest = filename[len("package://"):].partition("/")
        for root in _search_path(urdf, package_path):
            for candidate in (root / pkg / rest, root / rest if root.name == pkg else None):
                if candidate is not None and candidate.is_file():
                    return candidate
        raise MeshError(f"{urdf}: {filename} is in no folder of the package search path "
                        "(give --package-path DIR, or set ROS_PACKAGE_PATH)")
    if filename.startswith("file://"):
        filename = filename[len("file://"):]
    p = Path(filename)
    return p if p.is_absolute() else urdf.parent / p


def read_urdf(path: Path, load_file, crease: float, joints=None, package_path=None,
              collision: bool = False):
    """``(parts, cameras, lights, rig)`` as facet.formats.loading.load_file returns them
    (lights hold the z-up setting; the rig an Articulation that ``Scene.posed`` poses
    again); ``load_file`` reads the robot's mesh files."""
    from .usd_geometry import StageSettings, axis_turn

    robot = parse_robot(path)
    notes: list = []
    kinematics = Kinematics(robot, path, notes)
    cfg = kinematics.check(joints)
    named = {m.name: m for m in (robot.robot.materials or []) if m.name}
    found: list = []  # (name, args, link, 4x4 part -> link)
    for link in robot.robot.links:
        elements = link.collisions if collision else link.visuals
        for k, element in enumerate(elements or []):
            geometry = element.geometry
            origin = element.origin if element.origin is not None else np.eye(4)
            name = f"{link.name}/{element.name or k}"
            material = None if collision else _material(element.material, named, path,
                                                        package_path)
            if geometry is None:
                continue
            if geometry.box is not None:
                args = {"kind": "shape", "shape": "box",
                        "params": tuple(float(v) for v in geometry.box.size)}
                found.append((name, _with(args, material, path, name), link.name, origin))
            elif geometry.cylinder is not None:
                c = geometry.cylinder
                args = {"kind": "shape", "shape": "cylinder",
                        "params": (float(c.radius), float(c.length))}
                found.append((name, _with(args, material, path, name), link.name,
                              origin @ axis_turn("Z")))
            elif geometry.sphere is not None:
                args = {"kind": "shape", "shape": "sphere",
                        "params": (float(geometry.sphere.radius),)}
                found.append((name, _with(args, material, path, name), link.name, origin))
            elif geometry.mesh is not None:
                mesh_path = resolve(geometry.mesh.filename, path, package_path)
                scale = np.ones(3) if geometry.mesh.scale is None else \
                    np.broadcast_to(np.asarray(geometry.mesh.scale, float), 3)
                raw, _, _, _ = load_file(mesh_path, crease)
                for sub, args, m in raw:
                    if material is not None:
                        args = dict(args, material=material)
                    found.append((f"{name}/{sub}", args, link.name,
                                  origin @ np.diag([*scale, 1.0]) @ m))
    if not found:
        raise MeshError(f"{path}: its links have no {'collision' if collision else 'visual'} "
                        "geometry to draw")
    for note in notes:
        warnings.warn(f"{path.name}: {note}", FacetWarning, stacklevel=4)
    rig = Articulation(kinematics, [f[2] for f in found], [f[3] for f in found], cfg)
    parts = [(name, args, m) for (name, args, _, _), m in zip(found, rig.placements(),
                                                              strict=True)]
    return parts, {}, [StageSettings("z")], rig


def _with(args: dict, material, path, name) -> dict:
    return dict(args, material=material, name=name, path=str(path))


def _material(material, named: dict, path: Path, package_path):
    """A visual's material as a PbrMaterial (its colour, or the robot's named one), or
    None (the mesh file's own, else facet's default)."""
    from ..scene.pbr import PbrMaterial
    from ..scene.texture import Texture
    from ..scene.texture_slot import TextureSlot

    if material is None:
        return None
    if material.color is None and material.texture is None and material.name in named:
        material = named[material.name]
    if material.color is None and material.texture is None:
        return None
    rgba = (1.0, 1.0, 1.0, 1.0) if material.color is None else \
        tuple(float(v) for v in material.color.rgba)
    m = PbrMaterial(base_color=rgba, metallic=0.0, roughness=0.6,
                    alpha_mode="BLEND" if rgba[3] < 1 else "OPAQUE")
    if material.texture is not None and material.texture.filename:
        m.base_color_texture = TextureSlot(Texture.load(
            resolve(material.texture.filename, path, package_path)))
    return m


def describe_robot(path: Path) -> list[str]:
    """``facet info`` lines: links, and joints with their types and limits."""
    robot = parse_robot(path)
    joints = []
    for j in robot.robot.joints:
        limit = j.limit
        span = f" [{limit.lower:g}, {limit.upper:g}]" if limit is not None and \
            limit.lower is not None and limit.upper is not None and \
            j.type in ("revolute", "prismatic") else ""
        mimic = f" mimics {j.mimic.joint}" if j.mimic is not None else ""
        joints.append(f"{j.name} ({j.type}{span}{mimic})")
    return [f"{'urdf links':22} {len(robot.robot.links)}: " +
            ", ".join(lk.name for lk in robot.robot.links),
            f"{'urdf joints':22} " + (", ".join(joints) or "none")]

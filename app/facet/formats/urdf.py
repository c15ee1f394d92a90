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
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from ..errors import InputError, MeshError

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


def configure(robot, joints: dict | None, path) -> None:
    """Set the joint values (the module docstring's rules)."""
    joints = dict(joints or {})
    known = robot.joint_map
    cfg = {}
    for name, value in joints.items():
        if name not in known:
            raise InputError(f"{path}: no joint named {name!r}; its joints are "
                             f"{', '.join(robot.actuated_joint_names) or 'none'}")
        joint = known[name]
        if joint.mimic is not None:
            raise InputError(f"{path}: joint {name!r} mimics {joint.mimic.joint!r}; set "
                             f"{joint.mimic.joint!r} instead")
        if joint.type == "fixed":
            raise InputError(f"{path}: joint {name!r} is fixed; it takes no value")
        v = float(value)
        if not np.isfinite(v):
            raise InputError(f"{path}: joint {name!r}: a value must be finite, got {value!r}")
        limit = joint.limit
        if joint.type in ("revolute", "prismatic") and limit is not None and \
                limit.lower is not None and limit.upper is not None and \
                not limit.lower - 1e-9 <= v <= limit.upper + 1e-9:
            unit = "m" if joint.type == "prismatic" else "rad"
            raise InputError(f"{path}: joint {name!r} = {v:g} {unit} is outside its limits "
                             f"[{limit.lower:g}, {limit.upper:g}] {unit}")
        cfg[name] = v
    if cfg:
        robot.update_cfg(cfg)


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
    (lights hold the z-up setting); ``load_file`` reads the robot's mesh files."""
    from .usd_geometry import StageSettings, axis_turn

    robot = parse_robot(path)
    configure(robot, joints, path)
    named = {m.name: m for m in (robot.robot.materials or []) if m.name}
    parts: list = []
    base = robot.base_link
    for link in robot.robot.links:
        pose = robot.get_transform(frame_to=link.name, frame_from=base)
        elements = link.collisions if collision else link.visuals
        for k, element in enumerate(elements or []):
            geometry = element.geometry
            origin = element.origin if element.origin is not None else np.eye(4)
            place = pose @ origin
            name = f"{link.name}/{element.name or k}"
            material = None if collision else _material(element.material, named, path,
                                                        package_path)
            if geometry is None:
                continue
            if geometry.box is not None:
                args = {"kind": "shape", "shape": "box",
                        "params": tuple(float(v) for v in geometry.box.size)}
                parts.append((name, _with(args, material, path, name), place))
            elif geometry.cylinder is not None:
                c = geometry.cylinder
                args = {"kind": "shape", "shape": "cylinder",
                        "params": (float(c.radius), float(c.length))}
                parts.append((name, _with(args, material, path, name),
                              place @ axis_turn("Z")))
            elif geometry.sphere is not None:
                args = {"kind": "shape", "shape": "sphere",
                        "params": (float(geometry.sphere.radius),)}
                parts.append((name, _with(args, material, path, name), place))
            elif geometry.mesh is not None:
                mesh_path = resolve(geometry.mesh.filename, path, package_path)
                scale = np.ones(3) if geometry.mesh.scale is None else \
                    np.broadcast_to(np.asarray(geometry.mesh.scale, float), 3)
                raw, _, _, _ = load_file(mesh_path, crease)
                for sub, args, m in raw:
                    if material is not None:
                        args = dict(args, material=material)
                    parts.append((f"{name}/{sub}", args, place @ np.diag([*scale, 1.0]) @ m))
    if not parts:
        raise MeshError(f"{path}: its links have no {'collision' if collision else 'visual'} "
                        "geometry to draw")
    return parts, {}, [StageSettings("z")], None


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

"""The benchmark models of benchmarks/stages.py, written with pxr and numpy: a stage of
10,000 prims and 1M triangles, and a robot of 50 links (each a mesh of its own) on
revolute joints."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh


def sphere_cage(segments: int = 10, rings: int = 7) -> tuple[np.ndarray, list, list]:
    """A latitude-longitude sphere as USD polygons: (points (P, 3), counts, indices);
    10 x 7 gives 40 quads and 20 triangles: 100 triangles."""
    pts = [(0.0, 1.0, 0.0)]
    for r in range(1, rings - 1):
        phi = np.pi * r / (rings - 1)
        for s in range(segments):
            th = 2 * np.pi * s / segments
            pts.append((np.sin(phi) * np.cos(th), np.cos(phi), np.sin(phi) * np.sin(th)))
    pts.append((0.0, -1.0, 0.0))
    counts, idx = [], []
    bottom = len(pts) - 1
    for s in range(segments):
        counts.append(3)
        idx += [0, 1 + (s + 1) % segments, 1 + s]
    for r in range(rings - 3):
        a, b = 1 + r * segments, 1 + (r + 1) * segments
        for s in range(segments):
            counts.append(4)
            idx += [a + s, a + (s + 1) % segments, b + (s + 1) % segments, b + s]
    last = 1 + (rings - 3) * segments
    for s in range(segments):
        counts.append(3)
        idx += [bottom, last + s, last + (s + 1) % segments]
    return np.array(pts), counts, idx


def write_stage(path: Path, prims: int = 10_000) -> Path:
    """``prims`` Mesh prims of 100 triangles each (each its own points and translation,
    its displayColor one of a palette of 24, as an assembly's parts share colours) on a
    square grid, y up, as a .usdc."""
    from pxr import Gf, Usd, UsdGeom, Vt

    pts, counts, idx = sphere_cage()
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.Xform.Define(stage, "/World")
    side = int(np.ceil(np.sqrt(prims)))
    rng = np.random.default_rng(0)
    palette = rng.uniform(0.2, 0.9, (24, 3))
    for k in range(prims):
        mesh = UsdGeom.Mesh.Define(stage, f"/World/m{k:05d}")
        scale = rng.uniform(0.2, 0.45, 3)
        mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy((pts * scale).astype(np.float32)))
        mesh.CreateFaceVertexCountsAttr(counts)
        mesh.CreateFaceVertexIndicesAttr(idx)
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        mesh.CreateDisplayColorAttr([Gf.Vec3f(*palette[k % len(palette)])])
        UsdGeom.Xformable(mesh).AddTranslateOp().Set(
            Gf.Vec3d(k % side - side / 2, 0.0, k // side - side / 2))
    stage.Save()
    return path


def write_robot(folder: Path, links: int = 50) -> Path:
    """A chain of ``links`` links on revolute joints (alternating axes, limits +-1 rad),
    each link's visual a mesh file of its own (an ellipsoid of 1,280 triangles) found by
    package://; the URDF's path."""
    meshes = folder / "bench_robot" / "meshes"
    meshes.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(1)
    parts, joints = [], []
    for i in range(links):
        ball = trimesh.creation.icosphere(subdivisions=3)
        ball.apply_scale([0.04, 0.04, 0.06] * rng.uniform(0.8, 1.2, 3))
        ball.export(meshes / f"link{i}.stl")
        parts.append(f'<link name="l{i}"><visual><origin xyz="0 0 0.05"/><geometry>'
                     f'<mesh filename="package://bench_robot/meshes/link{i}.stl"/>'
                     f'</geometry></visual></link>')
        if i:
            joints.append(f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
                          f'<child link="l{i}"/><origin xyz="0 0 0.1"/>'
                          f'<axis xyz="{i % 2} {(i + 1) % 2} 0"/>'
                          '<limit lower="-0.4" upper="0.4" effort="1" velocity="1"/></joint>')
    path = folder / "bench_robot" / "chain.urdf"
    path.write_text('<?xml version="1.0"?>\n<robot name="chain">\n' + "\n".join(parts + joints)
                    + "\n</robot>\n")
    return path

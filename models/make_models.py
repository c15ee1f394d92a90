"""Writes facet's own small models into this folder. Run once: python models/make_models.py

* default.obj + default.mtl: a (2, 3) torus knot tube, the model ``facet render`` draws when
  given none (warm orange Phong material in the MTL).
* icosphere.ply: a unit icosphere (subdivision 3, 1280 faces), binary PLY.
* cube.stl: a unit cube centred at the origin, STL (triangle soup, no shared vertices).
* torus.off: a torus (major radius 1, minor 0.3), OFF.
* globe.obj: a unit UV sphere (32 x 16 segments) with texture coordinates and normals, for
  texturing examples (``--texture checker``).
* helix-points.ply: a point cloud of 600 coloured points on a helix, ASCII PLY (the
  vertex-only kind scanners write), for point-cloud examples.
* bending-strip.glb: a skinned strip (two joints) whose animation "bend" bends it 90
  degrees and back over 2 s, for animation examples (--time, --animation).
* wire-cube.obj: a cube's 12 edges as OBJ `l` lines, for line examples.

Deterministic: the same numpy and trimesh give the same bytes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent


def torus_knot(p: int = 2, q: int = 3, segments: int = 240, sides: int = 20,
               tube: float = 0.28) -> trimesh.Trimesh:
    """A tube of radius ``tube`` around the (p, q) torus knot curve."""
    t = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    r = 2.0 + np.cos(q * t)
    curve = np.stack([r * np.cos(p * t), r * np.sin(p * t), -np.sin(q * t)], axis=1) * 0.5
    tangent = np.roll(curve, -1, axis=0) - np.roll(curve, 1, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    # Tube frame: the component of the position (from the knot's centre) across the tangent.
    normal = curve - np.sum(curve * tangent, axis=1, keepdims=True) * tangent
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    binormal = np.cross(tangent, normal)
    a = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    ring = np.cos(a)[None, :, None] * normal[:, None] + np.sin(a)[None, :, None] * binormal[:, None]
    vertices = (curve[:, None] + tube * ring).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(segments), np.arange(sides), indexing="ij")
    i1, j1 = (i + 1) % segments, (j + 1) % sides
    v00, v01 = i * sides + j, i * sides + j1
    v10, v11 = i1 * sides + j, i1 * sides + j1
    faces = np.concatenate([np.stack([v00, v10, v11], -1).reshape(-1, 3),
                            np.stack([v00, v11, v01], -1).reshape(-1, 3)])
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    if mesh.volume < 0:  # make the winding counter-clockwise seen from outside
        mesh.invert()
    return mesh


def globe(segments: int = 32, rings: int = 16) -> str:
    """A unit UV sphere as OBJ text: u around from +x towards -z, v from the south pole
    (0) to the north (1); the seam's and poles' vertices are repeated with their own uv."""
    u, v = np.meshgrid(np.linspace(0, 1, segments + 1), np.linspace(0, 1, rings + 1))
    phi, theta = 2 * np.pi * u, np.pi * (v - 0.5)
    pos = np.stack([np.cos(theta) * np.cos(phi), np.sin(theta), -np.cos(theta) * np.sin(phi)],
                   -1).reshape(-1, 3)
    uv = np.stack([u, v], -1).reshape(-1, 2)
    i, j = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a, b = i * (segments + 1) + j, i * (segments + 1) + j + 1
    c, d = a + segments + 1, b + segments + 1
    faces = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3),
                            np.stack([a, d, c], -1).reshape(-1, 3)])
    faces = faces[np.abs(np.cross(pos[faces[:, 1]] - pos[faces[:, 0]],
                                  pos[faces[:, 2]] - pos[faces[:, 0]])).sum(1) > 1e-12]
    lines = ["# a unit UV sphere with texture coordinates, written by models/make_models.py"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in pos]
    lines += [f"vt {s:.6f} {t:.6f}" for s, t in uv]
    lines += [f"vn {x:.6f} {y:.6f} {z:.6f}" for x, y, z in pos]
    lines += ["f " + " ".join(f"{k + 1}/{k + 1}/{k + 1}" for k in f) for f in faces]
    return "\n".join(lines) + "\n"


def main() -> None:
    knot = torus_knot()
    (HERE / "default.mtl").write_text(
        "# facet's default material: warm orange, moderately glossy\n"
        "newmtl knot\nKa 1 1 1\nKd 0.90 0.45 0.15\nKs 0.5 0.5 0.5\nNs 64\n")
    lines = ["# facet default model: (2, 3) torus knot, written by models/make_models.py",
             "mtllib default.mtl", "usemtl knot"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in knot.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in knot.faces]
    (HERE / "default.obj").write_text("\n".join(lines) + "\n")
    trimesh.creation.icosphere(subdivisions=3).export(HERE / "icosphere.ply")
    trimesh.creation.box().export(HERE / "cube.stl")
    trimesh.creation.torus(major_radius=1.0, minor_radius=0.3).export(HERE / "torus.off")
    (HERE / "globe.obj").write_text(globe())
    (HERE / "helix-points.ply").write_text(helix_points())
    bending_strip(HERE / "bending-strip.glb")
    (HERE / "wire-cube.obj").write_text(wire_cube())


def wire_cube() -> str:
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8)
             if sum(u != v for u, v in zip(corners[a], corners[b], strict=True)) == 1]
    lines = ["# facet: a unit cube's 12 edges as lines, written by models/make_models.py"]
    lines += [f"v {x} {y} {z}" for x, y, z in corners]
    lines += [f"l {a + 1} {b + 1}" for a, b in edges]
    return "\n".join(lines) + "\n"


def bending_strip(path: Path) -> None:
    """A two-sided strip 0.4 wide from y = 0 to 2, skinned to a joint at the origin and one
    at y = 1; the animation "bend" turns the second 90 degrees about z and back (2 s)."""
    from pygltflib import (
        GLTF2,
        Accessor,
        Animation,
        AnimationChannel,
        AnimationChannelTarget,
        AnimationSampler,
        Buffer,
        BufferView,
        Material,
        Mesh,
        Node,
        PbrMetallicRoughness,
        Primitive,
        Scene,
        Skin,
    )

    ys = np.linspace(0.0, 2.0, 17)
    pos = np.array([[x, y, 0.0] for y in ys for x in (-0.2, 0.2)], "f4")
    faces = np.array([[2 * r, 2 * r + 1, 2 * r + 3] for r in range(16)] +
                     [[2 * r, 2 * r + 3, 2 * r + 2] for r in range(16)], "u2")
    w1 = np.clip(pos[:, 1] - 0.5, 0.0, 1.0)
    joints = np.tile(np.array([0, 1, 0, 0], "u1"), (len(pos), 1))
    weights = np.stack([1 - w1, w1, 0 * w1, 0 * w1], axis=1).astype("f4")
    ibm = np.stack([np.eye(4), np.eye(4)]).astype("f4")
    ibm[1, 1, 3] = -1.0  # inverse of the joint's bind translation (0, 1, 0)
    ibm = ibm.transpose(0, 2, 1).reshape(2, 16)  # column-major
    times = np.array([0.0, 1.0, 2.0], "f4")
    s = np.sin(np.pi / 4)
    rotations = np.array([[0, 0, 0, 1], [0, 0, s, s], [0, 0, 0, 1]], "f4")
    g = GLTF2()
    blob = bytearray()
    for array, kind, component in ((pos, "VEC3", 5126), (faces.reshape(-1), "SCALAR", 5123),
                                   (joints, "VEC4", 5121), (weights, "VEC4", 5126),
                                   (ibm, "MAT4", 5126), (times, "SCALAR", 5126),
                                   (rotations, "VEC4", 5126)):
        while len(blob) % 4:
            blob.append(0)
        g.bufferViews.append(BufferView(buffer=0, byteOffset=len(blob),
                                        byteLength=array.nbytes))
        blob.extend(array.tobytes())
        extra = {"min": pos.min(0).tolist(), "max": pos.max(0).tolist()} if array is pos \
            else {"min": [0.0], "max": [2.0]} if array is times else {}
        g.accessors.append(Accessor(bufferView=len(g.bufferViews) - 1, componentType=component,
                                    count=len(array), type=kind, **extra))
    g.materials = [Material(pbrMetallicRoughness=PbrMetallicRoughness(
        baseColorFactor=[0.3, 0.7, 0.35, 1.0], metallicFactor=0.0, roughnessFactor=0.6),
        doubleSided=True)]
    g.meshes = [Mesh(primitives=[Primitive(
        attributes={"POSITION": 0, "JOINTS_0": 2, "WEIGHTS_0": 3}, indices=1, material=0)])]
    g.nodes = [Node(children=[1], name="root"), Node(translation=[0, 1, 0], name="tip"),
               Node(mesh=0, skin=0, name="strip")]
    g.skins = [Skin(joints=[0, 1], inverseBindMatrices=4)]
    g.animations = [Animation(name="bend", samplers=[AnimationSampler(input=5, output=6)],
                              channels=[AnimationChannel(sampler=0, target=AnimationChannelTarget(
                                  node=1, path="rotation"))])]
    g.scenes = [Scene(nodes=[0, 2])]
    g.scene = 0
    g.buffers = [Buffer(byteLength=len(blob))]
    g.set_binary_blob(bytes(blob))
    g.save_binary(str(path))


def helix_points(n: int = 600) -> str:
    t = np.linspace(0, 6 * np.pi, n)
    p = np.stack([np.cos(t), t / (6 * np.pi) * 2 - 1, np.sin(t)], axis=1)
    c = (np.stack([0.5 + 0.5 * np.cos(t), 0.5 + 0.5 * np.sin(t), np.linspace(0.2, 1, n)], 1)
         * 255).astype(int)
    lines = ["ply", "format ascii 1.0",
             f"comment facet: a helix of {n} coloured points (made for facet, CC0)",
             f"element vertex {n}", "property float x", "property float y", "property float z",
             "property uchar red", "property uchar green", "property uchar blue", "end_header"]
    lines += [f"{a:.5f} {b:.5f} {z:.5f} {r} {g} {bl}"
              for (a, b, z), (r, g, bl) in zip(p, c, strict=True)]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()

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

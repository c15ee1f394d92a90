"""Back-face culling where it cannot change the picture (the ``cull`` option, "auto").

A back face can only be seen through a hole, from inside, or through what is not opaque.
So an object is culled when its mesh is closed and consistently wound
(``Mesh.closed``), its material is opaque and drawn by facet (not a user's shader, not a
planar mirror), its object -> world matrix is not singular (one that mirrors flips the
winding that faces front, which the pass sets per draw), and its world bounds lie wholly in
front of the camera's near plane (so the camera is outside it and the near plane cuts
nothing open). glTF's single-sided materials are culled in any case (their meaning);
"on" culls every opaque object, "off" none.

Culled and unculled pictures are the same pixel for pixel, with one exception: at a
silhouette a front face seen exactly edge-on has no area and covers nothing, and the back
face behind it may cover a pixel centre or an MSAA sample; unculled, that pixel shows a
sliver of back face, culled it does not (a handful of silhouette pixels of a real mesh;
tests/test_culling.py bounds them).

Closedness costs a sort over the edges: small meshes are checked at once, large ones in a
background thread when first drawn (drawn with both faces until the answer is in, which
gives the same picture).
"""

from __future__ import annotations

import threading

import numpy as np

SYNC_FACES = 100_000  # meshes up to this size are checked when first drawn


def det3(m) -> float:
    """The determinant of the upper 3x3 of ``m`` (negative: the transform mirrors), in
    plain floats: this runs per object per frame."""
    (a, b, c), (d, e, f), (g, h, i) = (row[:3] for row in np.asarray(m)[:3].tolist())
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


class Culling:
    """Per renderer: which objects to cull this frame."""

    def __init__(self):
        self._pending: dict[int, threading.Thread] = {}  # id(mesh) -> its checker

    def closed(self, mesh) -> bool:
        """Whether ``mesh`` is known to be closed (False while it is being found out)."""
        known = getattr(mesh, "_closed", None)
        if known is not None:
            self._pending.pop(id(mesh), None)
            return known
        if mesh.face_count <= SYNC_FACES:
            return mesh.closed
        if id(mesh) not in self._pending:
            # A daemon thread: the property caches its answer on the mesh (numpy's sort
            # releases the GIL), and a process that is done does not wait for it.
            worker = threading.Thread(target=lambda: mesh.closed, daemon=True,
                                      name="facet-closed")
            self._pending[id(mesh)] = worker
            worker.start()
        return False

    def cull(self, obj, mode: str, view: np.ndarray, near: float,
             det: float | None = None) -> bool:
        """Whether to draw only the front faces of ``obj`` (module docstring); ``det``:
        its transform's ``det3`` when the caller has it (the pass sets the front winding
        by its sign)."""
        m = obj.material
        if mode == "off":
            return False
        if not getattr(m, "double_sided", True):
            return True  # a glTF single-sided material
        if m.transparent or m.shader is not None or m.mirror:
            return False
        if mode == "on":
            return True
        m = obj.transform
        if (det3(m) if det is None else det) == 0:  # flattened: no side faces front
            return False
        # The largest view-space z over the corners of the object's box (object space):
        # z(p) = r.p + r_w with r the view's z row carried into object space, so its
        # maximum over the box is r.centre + r_w + |r|.half-extent.
        # (In plain floats: this runs per object per frame.)
        rx, ry, rz, rw = (view[2] @ m).tolist()
        mesh = obj.mesh  # (a skinned pose's loose box: its vertices may not exist here)
        (x0, y0, z0), (x1, y1, z1) = getattr(mesh, "loose_bounds", mesh.bounds).tolist()
        z_max = ((rx * (x0 + x1) + ry * (y0 + y1) + rz * (z0 + z1)) * 0.5 + rw
                 + (abs(rx) * (x1 - x0) + abs(ry) * (y1 - y0) + abs(rz) * (z1 - z0)) * 0.5)
        if z_max > -near:  # some of it is not wholly in front of the near plane
            return False
        return self.closed(obj.mesh)

    def cull_many(self, objects, transforms: np.ndarray, mode: str, view: np.ndarray,
                  near: float, det: np.ndarray) -> np.ndarray:
        """``cull`` for objects sharing one mesh and one material (an instanced batch):
        (N,) bools, from their (N, 4, 4) ``transforms`` and (N,) ``det`` at once."""
        m, n = objects[0].material, len(objects)
        if mode == "off" or (getattr(m, "double_sided", True) and (
                m.transparent or m.shader is not None or m.mirror)):
            return np.zeros(n, bool)
        if not getattr(m, "double_sided", True) or mode == "on":
            return np.ones(n, bool)
        r = np.einsum("j,njk->nk", view[2], transforms)  # each box's view z row
        lo, hi = objects[0].mesh.bounds
        z_max = r[:, :3] @ ((lo + hi) * 0.5) + r[:, 3] + np.abs(r[:, :3]) @ ((hi - lo) * 0.5)
        ok = (det != 0) & (z_max <= -near)
        return ok & self.closed(objects[0].mesh) if ok.any() else ok

    def release(self) -> None:
        self._pending.clear()

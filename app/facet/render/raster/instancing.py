"""Instanced drawing: the objects that share one mesh and one material (a glTF node's
EXT_mesh_gpu_instancing, a mesh placed many times) go to the GPU in one draw per winding and
culling state, their matrices per instance (glsl/mesh/phong.vert's INSTANCED).

The per-instance matrices are composed here in float64, as the per-object uniforms are
(``mvp = P V M``, the normal matrix ``(M^-1)^T``), so an instance draws exactly what the
same object drawn alone draws. Everything per object is numpy over the batch: no Python
loop over instances but the one that gathers their matrices.
"""

from __future__ import annotations

import numpy as np

INSTANCE_FLOATS = 16 + 16 + 9 + 1  # model, mvp, normal matrix, object id (as int bits)
# The instance buffer's layout: (format, *attributes), one row per instance ("/i").
INSTANCE_LAYOUT = ("16f 16f 9f 1i /i", "in_model", "in_mvp", "in_normal_matrix",
                   "in_object_id")
MIN_BATCH = 2  # fewer objects of one mesh and material are drawn one by one


def batches(objects, alone) -> list:
    """``objects`` in draw order as items: an object, or a list of objects sharing mesh and
    material (at least MIN_BATCH; in the order first met). ``alone(obj)``: objects that
    must be drawn by themselves (a user's shader, a mirror, transmission)."""
    groups: dict[tuple[int, int], list] = {}
    items: list = []
    for obj in objects:
        if alone(obj):
            items.append(obj)
            continue
        key = (id(obj.mesh), id(obj.material))
        group = groups.get(key)
        if group is None:
            group = groups[key] = []
            items.append(group)
        group.append(obj)
    return [item[0] if isinstance(item, list) and len(item) < MIN_BATCH else item
            for item in items]


def instance_rows(objects, view_projection: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((N, INSTANCE_FLOATS) float32 rows for the instance buffer, (N,) determinants of
    the objects' upper 3x3) of a batch."""
    models = np.stack([o.transform for o in objects])  # (N, 4, 4) float64
    mvp = view_projection @ models
    linear = models[:, :3, :3]
    det = np.linalg.det(linear)
    safe = np.where(det[:, None, None] != 0, linear, np.eye(3))
    normal = np.linalg.inv(safe).transpose(0, 2, 1)
    rows = np.empty((len(objects), INSTANCE_FLOATS), np.float32)
    # GLSL matrices are column-major: each row holds the transposes.
    rows[:, 0:16] = models.transpose(0, 2, 1).reshape(-1, 16)
    rows[:, 16:32] = mvp.transpose(0, 2, 1).reshape(-1, 16)
    rows[:, 32:41] = normal.transpose(0, 2, 1).reshape(-1, 9)
    rows[:, 41] = np.array([o.id + 1 for o in objects], np.int32).view(np.float32)
    return rows, det

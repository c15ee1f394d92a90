"""glTF cameras -> facet cameras (no GL): a node's perspective or orthographic camera,
looking down its -z, with a far plane past the model when the file gives none."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..scene.animation import camera_view


def gltf_camera(gltf, index: int, world: np.ndarray, parts, fail) -> Camera:
    """glTF camera ``index`` on a node of world matrix ``world``, its far plane (when the file
    gives none) past every part's box (``parts``: the reader's)."""
    cam = gltf.cameras[index]
    try:
        view = camera_view(world)  # glTF cameras look down their -z, y up
    except InputError as exc:
        fail(f"camera {index} ({cam.name or 'unnamed'}): {exc}")
    corners = []
    for _, args, m in parts:  # every part's box corners, in the file's frame
        b = np.stack([args["positions"].min(axis=0), args["positions"].max(axis=0)])
        box = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
        corners.append(box @ m[:3, :3].T + m[:3, 3])
    corners = np.concatenate(corners)
    corners = np.hstack([corners, np.ones((len(corners), 1))])
    depth = -(corners @ view[2])  # along the viewing axis
    reach = float(max(depth.max(), 1e-3)) * 1.01
    if cam.type == "orthographic" and cam.orthographic is not None:
        o = cam.orthographic
        return Camera(view, ortho_height=2.0 * abs(o.ymag or 1.0),
                      near=max(o.znear or 0.0, 1e-4), far=o.zfar or reach)
    p = cam.perspective
    if p is None:
        fail(f"camera {index} has neither perspective nor orthographic data")
    near = p.znear or 0.01
    return Camera(view, fov_y=float(np.degrees(p.yfov)), near=near,
                  far=p.zfar or max(reach, near * 10))

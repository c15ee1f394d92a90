"""A job's cameras as a COLMAP text model, beside its transforms.json (``colmap = true``):

    JOB/sparse/0/cameras.txt   CAMERA_ID PINHOLE W H fx fy cx cy (one per distinct lens)
    JOB/sparse/0/images.txt    IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, then an empty
                               line (no 2D keypoints); NAME is the file in JOB/images/
    JOB/sparse/0/points3D.txt  POINT3D_ID X Y Z R G B ERROR (no tracks): points on the
                               model's surface, read from the rendered views

This is the layout COLMAP writes and what Gaussian-splatting and NeRF trainers read
(``JOB`` as their source folder). COLMAP's conventions: the pose is world-to-camera in
OpenCV axes (x right, y down, looking down +z) as a unit quaternion (w first) and a
translation; pixel coordinates put the centre of the top-left pixel at (0.5, 0.5), as
transforms.json does. The surface points (at most ``POINTS_PER_VIEW`` per view, chosen
with the job's seed) give those trainers the initial point cloud they need.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..image.writers import write_atomic

POINTS_PER_VIEW = 2000
GL_TO_CV = np.diag([1.0, -1.0, -1.0])  # camera axes: OpenGL (y up, -z ahead) -> OpenCV


def surface_points(frame, rng: np.random.Generator) -> np.ndarray:
    """(N, 6) world positions and 0-255 colours of up to POINTS_PER_VIEW pixels of ``frame``
    that hit something (it was rendered with depth and position)."""
    hit = np.flatnonzero(frame.depth.reshape(-1) > 0)
    if len(hit) > POINTS_PER_VIEW:
        hit = np.sort(rng.choice(hit, POINTS_PER_VIEW, replace=False))
    xyz = frame.position.reshape(-1, 3)[hit].astype(np.float64)
    rgb = np.asarray(frame.color).reshape(-1, frame.color.shape[-1])[hit, :3]
    if rgb.dtype != np.uint8:  # float colour: 0..1
        rgb = np.clip(np.round(rgb * 255), 0, 255)
    return np.hstack([xyz, rgb.astype(np.float64)])


def quaternion(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (Shepperd's method:
    divide by the largest of the four candidates, so no precision is lost near 180 deg)."""
    t = np.trace(R)
    k = int(np.argmax([t, R[0, 0], R[1, 1], R[2, 2]]))
    if k == 0:
        s = 2.0 * np.sqrt(1.0 + t)
        q = [s / 4, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i, j, m = k - 1, k % 3, (k + 1) % 3
        s = 2.0 * np.sqrt(1.0 + R[i, i] - R[j, j] - R[m, m])
        q = np.zeros(4)
        q[0] = (R[m, j] - R[j, m]) / s
        q[1 + i] = s / 4
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + m] = (R[m, i] + R[i, m]) / s
    q = np.asarray(q, dtype=np.float64)
    return (q if q[0] >= 0 else -q) / np.linalg.norm(q)


def write_colmap(folder: Path, size, cameras, names: list[str], points: np.ndarray) -> None:
    """cameras.txt, images.txt and points3D.txt under ``folder / "sparse/0"``."""
    w, h = size
    lenses: dict[tuple, int] = {}
    image_lines = []
    for k, (cam, name) in enumerate(zip(cameras, names, strict=True), start=1):
        K = cam.K(w, h)
        lens = (float(K[0, 0]), float(K[1, 1]), float(K[0, 2]) + 0.5, float(K[1, 2]) + 0.5)
        cam_id = lenses.setdefault(lens, len(lenses) + 1)
        view = np.asarray(cam.view, dtype=np.float64)  # world -> OpenGL camera
        R, t = GL_TO_CV @ view[:3, :3], GL_TO_CV @ view[:3, 3]
        q = quaternion(R)
        image_lines.append(f"{k} {' '.join(repr(float(x)) for x in (*q, *t))} {cam_id} {name}")
        image_lines.append("")  # no 2D points
    camera_lines = [f"{i} PINHOLE {w} {h} {' '.join(repr(v) for v in lens)}"
                    for lens, i in lenses.items()]
    point_lines = [f"{i} {x!r} {y!r} {z!r} {int(r)} {int(g)} {int(b)} 0"
                   for i, (x, y, z, r, g, b) in enumerate(points.tolist(), start=1)]
    sparse = folder / "sparse" / "0"
    for name, header, lines in (
            ("cameras.txt", ["CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]"], camera_lines),
            ("images.txt", ["IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME",
                            "POINTS2D[] as (X, Y, POINT3D_ID)"], image_lines),
            ("points3D.txt", ["POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as "
                              "(IMAGE_ID, POINT2D_IDX)"], point_lines)):
        text = "".join(f"# {line}\n" for line in header) + "\n".join(lines) + "\n"
        with write_atomic(sparse / name) as tmp:
            Path(tmp).write_text(text, encoding="utf-8")

"""A dataset's files, laid out as the 3D-learning and reconstruction tools read them:

    DATASET/index.jsonl               one line per job: job, model, views, files, seconds,
                                      status (done / failed / skipped), error; appended as
                                      jobs finish, then one line per job (its latest
                                      outcome; a rerun's "skipped" keeps the "done" line)
    DATASET/JOB/images/0000.png       colour (RGBA when the background is transparent)
    DATASET/JOB/depth/0000.npy        float32 linear depth, 0 = nothing (and normals/,
                                      position/, uv/ the same way when asked for); with
                                      float_files = ["exr"] (or both) 0000.exr, float32
                                      exact: depth as the grey channel Y, the others R, G(, B)
    DATASET/JOB/masks/0000.png        8-bit mask of the model (when ids are asked for),
    DATASET/JOB/ids/0000.npy          and the int32 object ids
    DATASET/JOB/sparse/0/*.txt        COLMAP text model, with colmap = true
                                      (facet.batch.colmap)
    DATASET/JOB/transforms.json       nerfstudio / instant-ngp cameras (written last)

transforms.json holds the intrinsics fl_x, fl_y, cx, cy, w, h and camera_angle_x, with the
pixel-corner convention these tools use (a pixel's centre at (i + 0.5, j + 0.5); facet's
OpenCV K puts it at (i, j)), and per frame the colour file_path, the depth_file_path and
mask_path where written, and the camera-to-world transform_matrix in OpenGL axes (x right,
y up, looking down -z). A job is finished exactly when its transforms.json exists with the
job's digest: every other file is written before it, each one atomically.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..guard import check_output, parse_json, read_bytes
from ..image.writers import save_array, save_exr, save_image, to_uint8, write_atomic

CHANNEL_DIRS = {"depth": "depth", "normals": "normals", "position": "position", "uv": "uv"}


def finished(folder: Path, digest: str) -> bool:
    """Whether ``folder`` holds a finished job with this digest (its transforms.json, a
    regular file inside the output folder: a FIFO there is not opened)."""
    try:
        path = check_output(folder / "transforms.json")
        if not path.is_file():
            return False
        data = parse_json(read_bytes(path, "dataset record", confine=False), str(path))
    except (OSError, ValueError, RecursionError):  # (InputError is a ValueError)
        return False
    return isinstance(data, dict) and isinstance(data.get("facet"), dict) and \
        data["facet"].get("digest") == digest


def write_view(folder: Path, index: int, frame, outputs, float_files=("npy",)) -> dict:
    """One view's files; returns its transforms.json frame entry (without the matrix).
    ``float_files``: the formats of the float channels, "npy" and / or "exr"."""
    name = f"{index:04d}"
    entry = {"file_path": f"images/{name}.png"}
    save_image(folder / entry["file_path"], to_uint8(frame.color))
    for channel, sub in CHANNEL_DIRS.items():
        if channel in outputs:
            array = np.ascontiguousarray(getattr(frame, channel))
            if "npy" in float_files:
                save_array(folder / sub / f"{name}.npy", array)
            if "exr" in float_files:
                save_exr(folder / sub / f"{name}.exr", array)
    if "depth" in outputs:
        entry["depth_file_path"] = f"depth/{name}.{float_files[0]}"
    if "ids" in outputs:
        ids = frame.object_ids
        save_array(folder / "ids" / f"{name}.npy", ids)
        mask = np.where(ids >= 0, 255, 0).astype(np.uint8)
        save_image(folder / "masks" / f"{name}.png", np.repeat(mask[..., None], 3, axis=2))
        entry["mask_path"] = f"masks/{name}.png"
    return entry


def write_transforms(folder: Path, job, size, cameras, entries: list[dict]) -> Path:
    """transforms.json (module docstring) of images of ``size`` (w, h), the job's last
    file."""
    w, h = size
    K = cameras[0].K(w, h)
    fl_x, fl_y = float(K[0, 0]), float(K[1, 1])
    data = {
        "camera_model": "OPENCV", "w": w, "h": h, "fl_x": fl_x, "fl_y": fl_y,
        "cx": float(K[0, 2]) + 0.5, "cy": float(K[1, 2]) + 0.5,  # pixel-corner convention
        "k1": 0.0, "k2": 0.0, "p1": 0.0, "p2": 0.0,
        "camera_angle_x": float(2 * np.arctan(w / (2 * fl_x))),
        "camera_angle_y": float(2 * np.arctan(h / (2 * fl_y))),
        "frames": [dict(entry, transform_matrix=np.linalg.inv(cam.view).tolist(),
                        near=cam.near, far=cam.far)
                   for entry, cam in zip(entries, cameras, strict=True)],
        "facet": {"digest": job.digest(), "model": str(job.model), "views": len(cameras),
                  "plan": job.views.kind},
    }
    path = folder / "transforms.json"
    with write_atomic(path) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=1), encoding="utf-8")
    return path


def append_index(path: Path, record: dict) -> None:
    """One JSON line in the dataset's index (appended and flushed at once)."""
    check_output(path)  # inside the output folder, not a FIFO: never a link followed out
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NOFOLLOW, 0o666)
    with open(fd, "a", encoding="utf-8") as f:
        f.write(json.dumps(record) + "\n")
        f.flush()


def compact_index(path: Path) -> None:
    """Rewrite the index with one line per job (first-seen order): its latest record, where
    a rerun's "skipped" keeps the record of the run that rendered it. Lines cut short by a
    crash are dropped."""
    try:
        if not check_output(path).is_file():
            return
        lines = read_bytes(path, "dataset index", confine=False).decode(
            "utf-8", "replace").splitlines()
    except (OSError, ValueError):  # (InputError is a ValueError)
        return
    latest: dict = {}
    for line in lines:
        try:
            record = json.loads(line)
            key = (record["job"], record.get("model"))
        except (ValueError, KeyError, TypeError):
            continue
        if record.get("status") != "skipped" or key not in latest:
            latest[key] = record
    with write_atomic(path) as tmp:
        Path(tmp).write_text("".join(json.dumps(r) + "\n" for r in latest.values()),
                             encoding="utf-8")

"""Environment maps (no GL): the six faces of a cube map as float images, to show as the
background and to reflect and refract (materials' ``reflectivity`` and ``ior``).

Face order and texel orientation are OpenGL's (+X, -X, +Y, -Y, +Z, -Z; row 0 first, as
uploaded): texel (s, t) of a face, with sc = 2 s - 1 and tc = 2 t - 1, looks along

    +X: ( 1, -tc, -sc)   -X: (-1, -tc,  sc)   +Y: (sc,  1,  tc)
    -Y: (sc, -1, -tc)    +Z: (sc, -tc,  1)    -Z: (-sc, -tc, -1)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError

FACE_NAMES = ("px", "nx", "py", "ny", "pz", "nz")


def face_directions(size: int) -> np.ndarray:
    """(6, size, size, 3) unit directions of every texel centre (module docstring)."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    tc, sc = np.meshgrid(c, c, indexing="ij")  # rows: t, columns: s
    one = np.ones_like(sc)
    dirs = np.stack([np.stack([one, -tc, -sc], -1), np.stack([-one, -tc, sc], -1),
                     np.stack([sc, one, tc], -1), np.stack([sc, -one, -tc], -1),
                     np.stack([sc, -tc, one], -1), np.stack([-sc, -tc, -one], -1)])
    return dirs / np.linalg.norm(dirs, axis=-1, keepdims=True)


def sky_color(directions, zenith, horizon, ground) -> np.ndarray:
    """The generated sky: horizon -> zenith above, a darker ground below (smooth in y)."""
    d = np.asarray(directions, dtype=np.float64)
    y = d[..., 1:2]
    up = np.sqrt(np.clip(y, 0.0, 1.0))
    down = np.clip(-y * 4.0, 0.0, 1.0)
    zenith, horizon, ground = (np.asarray(c, dtype=np.float64) for c in (zenith, horizon,
                                                                          ground))
    return np.where(y >= 0, horizon + (zenith - horizon) * up, horizon + (ground - horizon) * down)


class Environment:
    """``faces``: (6, S, S, 3) float32 in [0, 1], OpenGL cube-map order."""

    SKY = ((0.25, 0.45, 0.85), (0.85, 0.9, 1.0), (0.3, 0.28, 0.25))

    def __init__(self, faces, name: str = "environment"):
        f = np.asarray(faces, dtype=np.float32)
        if f.ndim != 4 or f.shape[0] != 6 or f.shape[1] != f.shape[2] or f.shape[3] != 3:
            raise InputError(f"{name}: a cube map needs 6 square RGB faces of one size, got "
                             f"{f.shape}")
        self.faces = np.ascontiguousarray(np.clip(f, 0.0, 1.0))
        self.name = name

    @classmethod
    def sky(cls, zenith=SKY[0], horizon=SKY[1], ground=SKY[2], size: int = 128) -> Environment:
        """A generated sky gradient."""
        return cls(sky_color(face_directions(size), zenith, horizon, ground), "sky")

    @classmethod
    def constant(cls, color) -> Environment:
        """The same radiance from every direction (``color``: linear RGB)."""
        from .material import as_color

        c = as_color(color, "environment color")
        return cls(np.broadcast_to(c[:3], (6, 1, 1, 3)), "constant environment")

    @classmethod
    def from_faces(cls, paths) -> Environment:
        """Six images, in the order +X, -X, +Y, -Y, +Z, -Z."""
        from .texture import Texture

        if len(paths) != 6:
            raise InputError(f"a cube map needs 6 face images (+X -X +Y -Y +Z -Z), got "
                             f"{len(paths)}")
        faces = [Texture.load(p).pixels[..., :3] for p in paths]
        sizes = {f.shape[:2] for f in faces}
        if len(sizes) != 1 or faces[0].shape[0] != faces[0].shape[1]:
            listing = ", ".join(f"{Path(p).name} {f.shape[1]}x{f.shape[0]}"
                                for p, f in zip(paths, faces, strict=True))
            raise InputError(f"cube map faces must be square and all the same size: {listing}")
        return cls(np.stack(faces) / 255.0, "cube map")

    @classmethod
    def from_equirect(cls, path, size: int = 256) -> Environment:
        """An equirectangular (latitude-longitude) image resampled onto the cube (its
        bytes sampled where they are: no float copy of the whole image)."""
        from .texture import Texture

        img = Texture.load(path).pixels
        d = face_directions(size)
        u = 0.5 + np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi)
        v = np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi  # 0 at the zenith (image top)
        h, w = img.shape[:2]
        x = np.clip((u * w).astype(int), 0, w - 1)
        y = np.clip((v * h).astype(int), 0, h - 1)
        return cls(img[y, x, :3].astype(np.float32) / 255.0, Path(path).name)

    @property
    def size(self) -> int:
        return self.faces.shape[1]


def load_environment(spec: str, base: Path | None = None) -> Environment:
    """``sky``, an equirectangular image file, or a folder with px/nx/py/ny/pz/nz images."""
    if spec == "sky":
        return Environment.sky()
    from ..guard import check_confined

    path = Path(base or ".") / spec
    check_confined(path, "environment file")
    if path.is_dir():
        faces = []
        for name in FACE_NAMES:
            found = sorted(path.glob(f"{name}.*"))
            if not found:
                raise InputError(f"{path}: no {name}.* face image (a cube map folder holds "
                                 f"{', '.join(FACE_NAMES)})")
            faces.append(found[0])
        return Environment.from_faces(faces)
    return Environment.from_equirect(path)

"""3D Gaussian splats (Kerbl et al. 2023, "3D Gaussian Splatting for Real-Time Radiance Field
Rendering"): what 3DGS, nerfstudio and gsplat train, as arrays, with the reference forward
pass's colour and covariance (the rasterizer draws them: facet.render.raster.splats).

A splat is a Gaussian of mean ``mu``, covariance ``Sigma = R S S^T R^T`` (``S`` the
diagonal of its scales, ``R`` its unit quaternion w x y z as a rotation), an opacity in
(0, 1) and a colour of spherical harmonics of degree 0-3 (RGB coefficients; the colour in
direction ``d``, from the camera to the mean, is ``sum_k c_k Y_k(d) + 0.5``, clamped at 0,
with the reference implementation's constants, ``SH_C0`` ...).

The files (facet.formats.splat_files) keep log-scales and an opacity logit; here they are
the values (``exp``, the sigmoid), and the quaternions normalised.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, FilePath, checked
from ..errors import InputError

# The reference implementation's real spherical harmonics constants (degrees 0-3).
SH_C0 = 0.28209479177387814
SH_C1 = 0.4886025119029199
SH_C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
         -1.0925484305920792, 0.5462742152960396)
SH_C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
         -0.4570457994644658, 1.445305721320277, -0.5900435899266435)
MAX_SCALE = 1e6  # a scale above this (in scene units) is a broken file, not a splat


def sh_basis(d: np.ndarray, degree: int) -> np.ndarray:
    """The real SH basis of the reference forward pass at unit directions ``d`` (N, 3):
    (N, (degree + 1)^2), signs and order as its ``computeColorFromSH``."""
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    out = [np.full_like(x, SH_C0)]
    if degree >= 1:
        out += [-SH_C1 * y, SH_C1 * z, -SH_C1 * x]
    if degree >= 2:
        xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
        out += [SH_C2[0] * xy, SH_C2[1] * yz, SH_C2[2] * (2.0 * zz - xx - yy),
                SH_C2[3] * xz, SH_C2[4] * (xx - yy)]
    if degree >= 3:
        out += [SH_C3[0] * y * (3.0 * xx - yy), SH_C3[1] * xy * z,
                SH_C3[2] * y * (4.0 * zz - xx - yy),
                SH_C3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy),
                SH_C3[4] * x * (4.0 * zz - xx - yy), SH_C3[5] * z * (xx - yy),
                SH_C3[6] * x * (xx - 3.0 * yy)]
    return np.stack(out, axis=1)


def quaternion_matrices(q: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations of unit quaternions (N, 4) w x y z."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)


@checked
@dataclass(eq=False)
class Splats:
    """A cloud of 3D Gaussians (module docstring).

    Parameters
    ----------
    means : (N, 3) float
        Centres.
    scales : (N, 3) float
        Standard deviations along the splat's axes (positive; files keep their logs).
    rotations : (N, 4) float
        Quaternions w x y z (normalised here; not all zero).
    opacities : (N,) float
        In [0, 1] (files keep their logits).
    sh : (N, K, 3) float
        Spherical harmonics coefficients, K = (degree + 1)^2 with degree 0-3; ``sh[:, 0]``
        the DC term (colour = SH_C0 sh[:, 0] + 0.5 seen from anywhere).
    name : str
        Label.
    """

    means: Annotated[ArrayLike, Array("N,3")]
    scales: Annotated[ArrayLike, Array("N,3")]
    rotations: Annotated[ArrayLike, Array("N,4")]
    opacities: Annotated[ArrayLike, Array("N")]
    sh: Annotated[ArrayLike, Array("N,K,3", "N,3")]
    name: str = "splats"

    def __post_init__(self) -> None:
        n = _rows(self.means, "means", 3)
        self.means = _finite(self.means, "means", (n, 3)).astype(np.float32)
        scales = _finite(self.scales, "scales", (n, 3))
        if n and (scales.min() <= 0 or scales.max() > MAX_SCALE):
            bad = int(np.flatnonzero((scales <= 0).any(1) | (scales > MAX_SCALE).any(1))[0])
            raise InputError(f"splat {bad}: scale {scales[bad].tolist()} is not in "
                             f"(0, {MAX_SCALE:g}] (a file keeps log-scales: exp them)")
        self.scales = scales.astype(np.float32)
        q = _finite(self.rotations, "rotations", (n, 4)).astype(np.float64)
        norms = np.linalg.norm(q, axis=1)
        if n and norms.min() < 1e-12:
            bad = int(np.argmin(norms))
            raise InputError(f"splat {bad}: its rotation quaternion is zero (w x y z "
                             "expected, any length)")
        self.rotations = (q / norms[:, None]).astype(np.float32) if n else \
            q.astype(np.float32)
        a = _finite(self.opacities, "opacities", (n,))
        if n and (a.min() < 0 or a.max() > 1):
            bad = int(np.flatnonzero((a < 0) | (a > 1))[0])
            raise InputError(f"splat {bad}: opacity {a[bad]:g} is not in [0, 1] (a file "
                             "keeps logits: take their sigmoid)")
        self.opacities = a.astype(np.float32)
        sh = np.asarray(self.sh, dtype=np.float64)
        if sh.ndim == 2 and sh.shape[1] == 3:
            sh = sh[:, None, :]
        if sh.ndim != 3 or sh.shape[0] != n or sh.shape[2] != 3 or \
                sh.shape[1] not in (1, 4, 9, 16):
            raise InputError(f"sh: expected (N, K, 3) coefficients with K 1, 4, 9 or 16 "
                             f"(degree 0-3) for the {n} splats of means, got shape {sh.shape}")
        self.sh = _finite(sh, "sh", sh.shape).astype(np.float32)

    # -- reading ---------------------------------------------------------------------------
    @classmethod
    @checked
    def load(cls, path: FilePath) -> Splats:
        """Read a 3DGS PLY (the reference implementation's layout, any SH degree) or a
        ``.splat`` file (the web viewers' 32 bytes a splat).

        Parameters
        ----------
        path : str or Path
            The file.

        Returns
        -------
        Splats
            Its splats.
        """
        from .readers import reader

        return reader("splat file")(Path(path))

    @classmethod
    @checked
    def from_colors(cls, means: Annotated[ArrayLike, Array("N,3")],
                    scales: Annotated[ArrayLike, Array("N,3")],
                    rotations: Annotated[ArrayLike, Array("N,4")],
                    opacities: Annotated[ArrayLike, Array("N")],
                    colors: Annotated[ArrayLike, Array("N,3")],
                    name: str = "splats") -> Splats:
        """Splats of SH degree 0 seen in the same colour from everywhere.

        Parameters
        ----------
        means, scales, rotations, opacities : arrays
            As the class's: (N, 3), (N, 3), (N, 4), (N,).
        colors : (N, 3) float
            RGB in [0, 1]: the DC term's colour (SH_C0 c + 0.5).
        name : str
            Label.

        Returns
        -------
        Splats
            The cloud.
        """
        if len(colors) != len(means):
            raise InputError(f"Splats.from_colors: colors: {len(colors)} rows, one for each "
                             f"of the {len(means)} rows of means expected")
        dc = (np.asarray(colors, np.float64) - 0.5) / SH_C0
        return cls(means, scales, rotations, opacities, dc[:, None, :], name)

    # -- what they are ---------------------------------------------------------------------
    @property
    def count(self) -> int:
        """How many splats."""
        return int(self.means.shape[0])

    @property
    def degree(self) -> int:
        """The SH degree, 0-3."""
        return int(round(np.sqrt(self.sh.shape[1]))) - 1

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3): the box of the means widened by three standard deviations."""
        if not self.count:
            return np.zeros((2, 3))
        reach = 3.0 * self.scales.max(axis=1, keepdims=True)
        return np.stack([(self.means - reach).min(0), (self.means + reach).max(0)])

    def covariances(self, linear: np.ndarray | None = None) -> np.ndarray:
        """Each splat's covariance ``R S S^T R^T``.

        Parameters
        ----------
        linear : (3, 3) float, optional
            The linear part A of an object -> world transform: the covariances carried by
            it (``A Sigma A^T``).

        Returns
        -------
        (N, 3, 3) float64 ndarray
            The covariances.
        """
        m = quaternion_matrices(self.rotations.astype(np.float64)) * \
            self.scales.astype(np.float64)[:, None, :]
        if linear is not None:
            m = np.asarray(linear, np.float64) @ m
        return m @ np.transpose(m, (0, 2, 1))

    def colors(self, directions: np.ndarray) -> np.ndarray:
        """The colours seen along ``directions``: SH + 0.5, clamped at 0.

        Parameters
        ----------
        directions : (N, 3) float
            Unit vectors from the camera to each mean, in the splats' own frame.

        Returns
        -------
        (N, 3) float32 ndarray
            RGB (display values; above 1 where the SH says so).
        """
        basis = sh_basis(np.asarray(directions, np.float32), self.degree)
        rgb = np.einsum("nk,nkc->nc", basis, self.sh, optimize=True) + 0.5
        return np.maximum(rgb, 0.0).astype(np.float32)

    def subset(self, index) -> Splats:
        """Some of the splats, as a new cloud.

        Parameters
        ----------
        index : (N,) bool or (M,) int array, or slice
            Which splats.

        Returns
        -------
        Splats
            Those splats (same SH degree).
        """
        return Splats(self.means[index], self.scales[index], self.rotations[index],
                      self.opacities[index], self.sh[index], self.name)

    def save(self, path) -> Path:
        """Write a 3DGS PLY in the reference implementation's layout (log-scales,
        opacity logits, SH channel-major).

        Parameters
        ----------
        path : str or Path

        Returns
        -------
        Path
            The file written.
        """
        from .readers import reader

        return reader("splat writer")(self, Path(path))


def _rows(a, what: str, width: int) -> int:
    shape = np.shape(a)
    if len(shape) != 2 or shape[1] != width:
        raise InputError(f"{what}: expected (N, {width}), got shape {shape}")
    return int(shape[0])


def _finite(a, what: str, shape) -> np.ndarray:
    arr = np.asarray(a, dtype=np.float64)
    if arr.shape != tuple(shape):
        raise InputError(f"{what}: expected shape {tuple(shape)} (a row for each row of "
                         f"means), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero((~np.isfinite(arr.reshape(arr.shape[0], -1))).any(1))[0])
        raise InputError(f"splat {bad}: {what} is not finite (NaN or infinity)")
    return arr


@dataclass(eq=False)
class SplatObject:
    """A cloud placed in a scene (``Scene.add`` of a ``Splats``): its id (shared with the
    scene's objects: ``Frame.object_ids``), cloud, object -> world transform and name."""

    id: int
    splats: Splats
    transform: np.ndarray
    name: str = ""

    @property
    def world_bounds(self) -> np.ndarray:
        lo, hi = self.splats.bounds
        corners = np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                            for z in (lo[2], hi[2])])
        world = corners @ self.transform.T
        return np.stack([world[:, :3].min(0), world[:, :3].max(0)])



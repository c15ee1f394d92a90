"""View plans: where a dataset job's cameras look from (numpy only).

    turntable N [elevation E]   N views around the up axis at elevation E degrees (20)
    sphere N                    N directions spread evenly over the sphere (Fibonacci)
    band N [elevations A B]     N views, azimuths evenly spread, elevations evenly from A
                                to B degrees (-10 to 40)
    random N [seed S]           N directions uniformly at random on the sphere, seeded
    cameras FILE                the cameras of a transforms.json (NeRF synthetic, instant-ngp,
                                nerfstudio: facet.batch.transforms_file)

With ``joints = [{...}, ...]`` (one configuration per view, the count its length) or
``random_joints = true`` (each joint uniform within its limits, seeded) a robot's views
each stand in their own configuration (facet.scene.articulated); every view is framed on
the bounds of them all, and transforms.json records each frame's ``joints``.

With ``times = [A, B]`` each view also stands at its own time of the scene's animations:
spread evenly over [A, B) in view order, or with ``random_times`` uniformly at random in
[A, B] (seeded); transforms.json records each frame's time.

Every view but ``cameras`` looks at the centre of the model's bounds from the distance
that fits them (facet.geometry.camera.Camera.frame) with a vertical field of view of FOV
degrees; directions are in the frame whose up axis is the job's ``up``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError

PLANS = ("turntable", "sphere", "band", "random", "cameras")
FOV = 40.0


@dataclass(frozen=True)
class ViewPlan:
    kind: str = "sphere"
    count: int = 8
    elevation: float = 20.0
    elevations: tuple[float, float] = (-10.0, 40.0)
    seed: int = 0
    file: str | None = None
    times: tuple[float, float] | None = None
    random_times: bool = False
    joints: tuple | None = None  # one {joint: value} per view
    random_joints: bool = False

    def view_joints(self, scene) -> list[dict] | None:
        """One joint configuration per view of ``scene``'s robots (module docstring), or
        None."""
        if self.joints is not None:
            return [dict(c) for c in self.joints]
        if self.random_joints:
            from ..scene.articulated import random_configurations

            return random_configurations(scene, self.count, self.seed + 2)
        return None

    def view_times(self, n: int) -> list[float] | None:
        """(n,) seconds, one per view (module docstring), or None."""
        if self.times is None:
            return None
        a, b = self.times
        if self.random_times:
            return np.random.default_rng(self.seed + 1).uniform(a, b, n).tolist()
        return [a + (b - a) * k / n for k in range(n)]

    def directions(self) -> np.ndarray:
        """(N, 3) unit viewing directions (from the camera towards the model), y up."""
        n = self.count
        if self.kind == "turntable":
            az = 2 * np.pi * np.arange(n) / n
            el = np.full(n, np.radians(self.elevation))
        elif self.kind == "band":
            az = 2 * np.pi * np.arange(n) / n
            lo, hi = np.radians(self.elevations)
            el = np.linspace(lo, hi, n) if n > 1 else np.array([(lo + hi) / 2])
        elif self.kind == "sphere":
            k = np.arange(n) + 0.5
            y = 1 - 2 * k / n  # Fibonacci lattice: even area per point
            az = np.pi * (1 + 5 ** 0.5) * k
            el = np.arcsin(y)
        elif self.kind == "random":
            rng = np.random.default_rng(self.seed)
            y = rng.uniform(-1, 1, n)
            az = rng.uniform(0, 2 * np.pi, n)
            el = np.arcsin(y)
        else:
            raise InputError(f"view plan {self.kind!r} has no directions")
        # The camera sits at (cos el sin az, sin el, cos el cos az) and looks back.
        eye = np.stack([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)], 1)
        return -eye

    def cameras(self, bounds, up=(0.0, 1.0, 0.0), aspect: float = 1.0, base: Path | None = None,
                size=None):
        """The plan's facet Cameras for a model with world ``bounds`` (2, 3); a cameras
        file's for images of ``size`` (facet.batch.transforms_file)."""
        from ..geometry import transforms as T
        from ..geometry.camera import Camera

        if self.kind == "cameras":
            from .transforms_file import read_transforms

            return read_transforms(Path(base or ".") / self.file, bounds, size)
        u = np.asarray(up, dtype=np.float64)
        u /= np.linalg.norm(u)
        y = np.array([0.0, 1.0, 0.0])
        axis, c = np.cross(y, u), float(np.dot(y, u))
        turn = np.eye(3)
        if np.linalg.norm(axis) > 1e-12:
            turn = T.rotate(axis, np.degrees(np.arctan2(np.linalg.norm(axis), c)))[:3, :3]
        elif c < 0:
            turn = np.diag([-1.0, -1.0, 1.0])
        cams = []
        for d in self.directions() @ turn.T:
            # Straight up or down: any other up keeps look_at defined.
            view_up = u if abs(np.dot(d, u)) < 0.999 else turn @ np.array([0.0, 0.0, -1.0])
            cams.append(Camera.frame(bounds, d, view_up, fov_y=FOV, aspect=aspect))
        return cams

"""Pure-numpy geometry: homogeneous transforms and cameras. Never imports GL."""

from . import transforms
from .camera import Camera
from .intrinsics import Intrinsics

__all__ = ["transforms", "Camera", "Intrinsics"]

"""Pure-numpy geometry: homogeneous transforms and cameras. Never imports GL."""

from . import transforms
from .camera import Camera, Intrinsics

__all__ = ["transforms", "Camera", "Intrinsics"]

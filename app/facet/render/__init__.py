"""Render passes over a scene and a camera: the Renderer and its Frame."""

from .renderer import Frame, Renderer

__all__ = ["Frame", "Renderer"]

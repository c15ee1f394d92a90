"""Scene description without GL: meshes, materials, lights and the scene that holds them."""

from . import primitives
from .light import AreaLight, DirectionalLight, PointLight, SpotLight
from .material import Material
from .mesh import Mesh
from .scene import MAX_LIGHTS, RenderSettings, Scene, SceneObject
from .texture import Texture


def load_scene(path) -> Scene:
    """Read a TOML scene file (see docs/scene-format.md) into a ``Scene``."""
    from .scenefile import load_scene as _load

    return _load(path)

__all__ = ["AreaLight", "DirectionalLight", "PointLight", "SpotLight", "Material", "Mesh", "Scene",
           "SceneObject", "MAX_LIGHTS", "RenderSettings", "load_scene", "primitives", "Texture"]

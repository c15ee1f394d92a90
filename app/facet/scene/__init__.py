"""Scene description without GL: meshes, materials, lights and the scene that holds them."""

from .light import DirectionalLight, PointLight, SpotLight
from .material import Material
from .mesh import Mesh
from .scene import MAX_LIGHTS, Scene, SceneObject

__all__ = ["DirectionalLight", "PointLight", "SpotLight", "Material", "Mesh", "Scene",
           "SceneObject", "MAX_LIGHTS"]

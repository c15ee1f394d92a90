"""The scene model without GL: meshes, points and lines, materials, lights, shapes,
environments, animation rigs, and the scene that holds them. Files are read by
facet.formats and render options parsed by facet.options (both found through
facet.scene.readers). Names are imported on first use."""

from ..lazy import lazy_exports

_EXPORTS = {
    "AreaLight": "light", "DirectionalLight": "light", "PointLight": "light",
    "SpotLight": "light", "Material": "material", "Mesh": "mesh",
    "MAX_LIGHTS": "scene", "Scene": "scene", "SceneObject": "scene", "Texture": "texture",
    "PbrMaterial": "pbr", "TextureSlot": "pbr", "primitives": "primitives", "shapes": "shapes",
}
__all__ = sorted(_EXPORTS)
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

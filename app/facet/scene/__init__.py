"""Scene description without GL: meshes, materials, lights, the scene that holds them, and
the render options a scene asks for. Names are imported on first use, so that importing
``facet.options.render`` alone (the command line's ``--help``) loads no numpy."""

from importlib import import_module

_EXPORTS = {
    "AreaLight": "light", "DirectionalLight": "light", "PointLight": "light",
    "SpotLight": "light", "Material": "material", "Mesh": "mesh",
    "MAX_LIGHTS": "scene", "Scene": "scene", "SceneObject": "scene", "Texture": "texture",
    "PbrMaterial": "pbr", "TextureSlot": "pbr",
}
__all__ = sorted([*_EXPORTS, "primitives", "shapes"])


def __getattr__(name: str):
    if name in ("primitives", "shapes"):
        return import_module(f"{__name__}.{name}")
    if name in _EXPORTS:
        value = getattr(import_module(f"{__name__}.{_EXPORTS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))

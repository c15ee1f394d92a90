"""facet: a headless-first Python GPU renderer on moderngl.

Public API (imported lazily, so ``import facet.geometry`` never loads GL)::

    import facet
    mesh = facet.Mesh.load("bunny.obj")
    scene = facet.Scene()
    scene.add(mesh, facet.Material(color=(0.9, 0.6, 0.3)))
    scene.add_light(facet.DirectionalLight(direction=(-1, -1, -1)))
    with facet.Renderer(640, 480) as r:
        frame = r.render(scene, facet.Camera.frame(scene.bounds, aspect=640 / 480))
    frame.save("bunny.png")

Errors a user can cause raise ``facet.FacetError`` subclasses.
"""

from importlib import import_module

from . import formats as _formats  # noqa: F401 - registers the readers (facet.scene.readers)

__version__ = "0.1.0"

_EXPORTS = {
    "Camera": "facet.geometry.camera",
    "Intrinsics": "facet.geometry.intrinsics",
    "transforms": "facet.geometry",
    "Mesh": "facet.scene.mesh",
    "Points": "facet.scene.points",
    "Lines": "facet.scene.points",
    "Material": "facet.scene.material",
    "DirectionalLight": "facet.scene.light",
    "PointLight": "facet.scene.light",
    "SpotLight": "facet.scene.light",
    "AreaLight": "facet.scene.light",
    "Scene": "facet.scene.scene",
    "RenderOptions": "facet.options.render",
    "load_scene": "facet.formats",
    "open_scene": "facet.formats",
    "load": "facet.formats",
    "PbrMaterial": "facet.scene.pbr",
    "TextureSlot": "facet.scene.pbr",
    "primitives": "facet.scene",
    "shapes": "facet.scene",
    "Texture": "facet.scene.texture",
    "Environment": "facet.scene.environment",
    "Renderer": "facet.render.renderer",
    "Frame": "facet.render.renderer",
    "SHADING_MODELS": "facet.render.shading",
    "view": "facet.window.viewer",
    "show": "facet.notebook.show",
    "ShaderToy": "facet.lab.shadertoy",
    "batch": "facet",
    "UserShader": "facet.scene.shader",
    "Viewer": "facet.window.viewer",
    "FacetError": "facet.errors",
    "FacetWarning": "facet.errors",
    "InputError": "facet.errors",
    "MeshError": "facet.errors",
    "ShaderError": "facet.errors",
    "ContextError": "facet.errors",
    "SceneError": "facet.errors",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        module = _EXPORTS[name]
        value = import_module(f"{module}.{name}") if module == "facet" else \
            getattr(import_module(module), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'facet' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))

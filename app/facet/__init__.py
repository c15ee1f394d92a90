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

from . import formats as _formats  # noqa: F401 - registers the readers (facet.scene.readers)
from .lazy import lazy_exports

__version__ = "0.1.0"

_EXPORTS = {
    "Camera": "geometry.camera",
    "Intrinsics": "geometry.intrinsics",
    "transforms": "geometry",
    "Mesh": "scene.mesh",
    "Points": "scene.points",
    "Lines": "scene.points",
    "Splats": "scene.splats",
    "Material": "scene.material",
    "DirectionalLight": "scene.light",
    "PointLight": "scene.light",
    "SpotLight": "scene.light",
    "AreaLight": "scene.light",
    "SphereLight": "scene.light",
    "Scene": "scene.scene",
    "RenderOptions": "options.render",
    "load_scene": "formats",
    "open_scene": "formats",
    "load": "formats",
    "PbrMaterial": "scene.pbr",
    "TextureSlot": "scene.texture_slot",
    "primitives": "scene",
    "shapes": "scene",
    "Texture": "scene.texture",
    "Environment": "scene.environment",
    "Renderer": "render.renderer",
    "Frame": "render.renderer",
    "SHADING_MODELS": "render.shading",
    "view": "window.viewer",
    "show": "notebook.show",
    "ShaderToy": "lab.shadertoy",
    "batch": "batch",
    "UserShader": "scene.shader",
    "Viewer": "window.viewer",
    "FacetError": "errors",
    "FacetWarning": "errors",
    "InputError": "errors",
    "MeshError": "errors",
    "ShaderError": "errors",
    "ContextError": "errors",
    "SceneError": "errors",
}

__all__ = sorted(_EXPORTS)
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

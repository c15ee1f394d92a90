"""Files -> scene objects (no GL): glTF (behind its validating layer, facet.formats.
gltf_check), OBJ/STL/PLY/OFF and point files (loading, point_files), trimesh objects
(adapters), facet's scene files (scenefile and its lights and materials), and the images of
textures and environments (images, environment_files, hdr_image). Only here are files read,
through the one guarded opener (facet.guard).

Importing this package registers the readers that the scene model's classes call
(facet.scene.readers: ``Mesh.load``, ``Texture.load``, ``Environment.from_equirect`` ...);
it imports nothing heavy itself.
"""

from ..lazy import lazy_exports
from ..scene.readers import register

register("mesh file", "facet.formats.loading", "read_parts")
register("texture", "facet.formats.images", "read_texture")
register("splat file", "facet.formats.splat_files", "read_splats")
register("splat writer", "facet.formats.splat_files", "write_ply")
register("environment", "facet.formats.environment_files", "environment_from_image")
register("cube faces", "facet.formats.environment_files", "environment_from_faces")
register("trimesh", "facet.formats.adapters", "trimesh_parts")
register("is trimesh", "facet.formats.adapters", "is_trimesh")
register("render options", "facet.options.render", "parse_layer")

_EXPORTS = {"load_scene": "scenefile", "open_scene": "source", "load": "source",
            "load_environment": "environment_files"}
__all__ = sorted(_EXPORTS)
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

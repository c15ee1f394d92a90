"""Where the scene model's classes find their file readers; there is no reading here.

The readers live in facet.formats (the one package that reads files), above the scene model
in the layers: a data class may not import them. facet.formats registers one reader per kind
(``register``, a module and a function name: nothing is imported until it is used), and
``import facet`` imports facet.formats, so every ``Mesh.load`` or ``Texture.load`` finds its
reader through ``reader`` without the scene model depending on it.

Kinds: ``mesh file`` (facet.formats.loading.read_parts), ``texture`` (an image file),
``environment`` (an equirectangular image or a cube-map folder), ``cube faces`` (six images),
``trimesh`` (trimesh objects' parts); and ``render options``, the parser of a scene's own
options (facet.options.render.parse_layer), which sits above the model as the readers do.
"""

from __future__ import annotations

from importlib import import_module

_READERS: dict[str, tuple[str, str]] = {}


def register(kind: str, module: str, function: str) -> None:
    """Name ``module.function`` as the reader of ``kind`` (facet.formats does)."""
    _READERS[kind] = (module, function)


def reader(kind: str):
    """The function that reads ``kind`` (its module is imported now)."""
    module, function = _READERS[kind]
    return getattr(import_module(module), function)

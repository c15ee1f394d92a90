"""Texture images from files (through the guarded opener, facet.guard): what
``facet.Texture.load`` reads (facet.scene.readers)."""

from __future__ import annotations

from ..errors import InputError
from ..scene.texture import Texture


def read_texture(path) -> Texture:
    """The image at ``path`` as a Texture named after the file; InputError when it cannot
    be read or is beyond facet's pixel budget."""
    from PIL import UnidentifiedImageError

    from ..guard import open_image, regular_file

    p = regular_file(path, "texture file")
    try:
        with open_image(p, str(p)) as img:
            return Texture.from_pil(img, p.name)
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise InputError(f"{p}: cannot read the texture image ({exc})") from None

"""The GL side of Shadertoy channels (facet.lab.project.Channel): image, cube-map and
volume textures (loaded once per file and flip), the keyboard texture, the noise texture,
black, and one sampler object per (filter, wrap) setting.

The keyboard texture is Shadertoy's: 256 x 3 texels, x = the JavaScript key code; row 0:
held down, row 1: pressed this frame, row 2: toggled by each press (values 0 or 1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError

KEYBOARD_SIZE = (256, 3)
NOISE_SIZE = 256  # texels a side of the noise texture (Shadertoy's "RGBA Noise Medium")
NOISE_SEED = 0


class ChannelResources:
    """Textures and samplers shared by a ShaderToy's passes (released with it)."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._textures: dict[tuple, tuple] = {}  # (kind, path, vflip) -> (texture, size)
        self._samplers: dict[tuple, object] = {}
        black = np.zeros((1, 1, 4), np.uint8)
        self.black = ctx.texture((1, 1), 4, black.tobytes())
        self.black_cube = ctx.texture_cube((1, 1), 4, black.tobytes() * 6)
        self.keys = np.zeros(KEYBOARD_SIZE[::-1], np.uint8)  # rows: down, pressed, toggled
        self.keyboard = ctx.texture(KEYBOARD_SIZE, 1, self.keys.tobytes())
        self.keyboard.filter = (ctx.NEAREST, ctx.NEAREST)
        self._keys_sent = self.keys.copy()
        self._noise = None

    @property
    def noise(self):
        """256 x 256 RGBA random bytes, mipmapped (made on first use, the same every run)."""
        if self._noise is None:
            rng = np.random.default_rng(NOISE_SEED)
            data = rng.integers(0, 256, (NOISE_SIZE, NOISE_SIZE, 4), np.uint8)
            self._noise = self.ctx.texture((NOISE_SIZE, NOISE_SIZE), 4, data.tobytes())
            self._noise.build_mipmaps()
        return self._noise

    def image(self, source, vflip: bool):
        """(texture, (w, h)) of an image file or a facet Texture, mipmapped."""
        from ..scene.texture import Texture

        key = ("image", id(source) if isinstance(source, Texture) else str(source), vflip)
        if key not in self._textures:
            texture = source if isinstance(source, Texture) else Texture.load(source)
            # Rows go up in order: GL's first row is v = 0. vflip puts the image's bottom
            # row there (Shadertoy's default for images); without, its top row.
            rows = texture.pixels[::-1] if vflip else texture.pixels
            tex = self.ctx.texture(texture.size, 4, np.ascontiguousarray(rows).tobytes())
            tex.build_mipmaps()
            self._textures[key] = (tex, texture.size)
        return self._textures[key]

    def cube(self, source):
        """(cube texture, (s, s)) of a folder of six faces or an environment image."""
        from ..formats.environment_files import load_environment

        key = ("cube", str(source), False)
        if key not in self._textures:
            path = Path(source)
            if not path.exists():
                raise InputError(f"{path}: no such cube map (a folder of six faces px nx py "
                                 "ny pz nz, or an equirectangular image)")
            env = load_environment(str(path))
            s = env.size
            tex = self.ctx.texture_cube((s, s), 4, _rgba(env.faces).tobytes(), dtype="f4")
            tex.build_mipmaps()
            self._textures[key] = (tex, (s, s))
        return self._textures[key]

    def volume(self, source):
        """(3D texture, (x, y, z)) of a ``.bin`` volume file, or of the noise volume
        ``"grey"`` / ``"rgba"`` (facet.lab.volumes), mipmapped."""
        from .volumes import noise_volume, read_volume

        key = ("volume", str(source), False)
        if key not in self._textures:
            texels = noise_volume(source) if source in ("grey", "rgba") else \
                read_volume(source)
            z, y, x, channels = texels.shape
            dtype = "f1" if texels.dtype == np.uint8 else "f4"
            tex = self.ctx.texture3d((x, y, z), channels, texels.tobytes(), dtype=dtype)
            tex.build_mipmaps()
            self._textures[key] = (tex, (x, y, z))
        return self._textures[key]

    def sampler(self, filter_: str, wrap: str):
        key = (filter_, wrap)
        if key not in self._samplers:
            ctx = self.ctx
            minify = {"nearest": ctx.NEAREST, "linear": ctx.LINEAR,
                      "mipmap": ctx.LINEAR_MIPMAP_LINEAR}[filter_]
            magnify = ctx.NEAREST if filter_ == "nearest" else ctx.LINEAR
            repeat = wrap == "repeat"
            self._samplers[key] = ctx.sampler(repeat_x=repeat, repeat_y=repeat,
                                              repeat_z=repeat, filter=(minify, magnify))
        return self._samplers[key]

    def upload_keys(self) -> None:
        """Send the key state if it changed (one small write, no allocation otherwise)."""
        if not np.array_equal(self.keys, self._keys_sent):
            self.keyboard.write(self.keys.tobytes())
            self._keys_sent[...] = self.keys

    def release(self) -> None:
        for tex, _ in self._textures.values():
            tex.release()
        self._textures.clear()
        for s in self._samplers.values():
            s.release()
        self._samplers.clear()
        for tex in (self.black, self.black_cube, self.keyboard, self._noise):
            if tex is not None:
                tex.release()


def _rgba(faces: np.ndarray) -> np.ndarray:
    """(6, S, S, 3) floats -> (6, S, S, 4) float32 with alpha 1."""
    alpha = np.ones(faces.shape[:3] + (1,), np.float32)
    return np.concatenate([faces.astype(np.float32), alpha], axis=-1)

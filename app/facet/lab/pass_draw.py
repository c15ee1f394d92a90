"""The shader lab's passes on the GPU: each pass's inputs (its channels 0-3 and named
samplers: buffers, images, cube maps, the keyboard, noise, black), bound and drawn into its
target, a cube pass face by face; and the one warning line for a channel read that nothing
gives. ``PassDrawing`` is ShaderToy's base (facet.lab.shadertoy holds its state)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..errors import FacetWarning
from ..gl.glsl_source import display_path
from ..gl.uniforms import write_sized
from . import project as P
from .channels import NOISE_SIZE


class PassDrawing:
    """Binding and drawing ShaderToy's passes (its ``project``, ``resources``, ``targets``,
    ``programs`` and ``vaos``)."""

    def _bind(self) -> None:
        """Each pass's inputs: its channels 0-3, then its named samplers."""
        self._bindings = {p.key: self._bind_channels(p) for p in self.project.ordered()}
        self._named = {p.key: [(name, self._input(ch)) for name, ch in p.samplers.items()]
                       for p in self.project.ordered()}

    def _bind_channels(self, p: P.Pass) -> list:
        """Per channel 0-3: (texture getter, sampler, resolution, GLSL sampler type)."""
        return [self._input(p.channels.get(n, P.NOISE)) for n in range(4)]

    def _input(self, ch: P.Channel) -> tuple:
        """(texture getter, sampler, resolution or None for the output's, GLSL sampler
        type)."""
        sampler = self.resources.sampler(ch.filter, ch.wrap)
        kind = ch.sampler_type
        if ch.kind == "buffer":
            cube = ch.source == "cube"
            return (self.targets.latest(ch.source), sampler,
                    (self.cube_size,) * 2 if cube else None, kind)
        if ch.kind == "texture":
            tex, size = self.resources.image(ch.source, ch.vflip)
            return (lambda: tex), sampler, size, kind
        if ch.kind == "cube":
            tex, size = self.resources.cube(ch.source)
            return (lambda: tex), sampler, size, kind
        if ch.kind == "volume":
            tex, size = self.resources.volume(ch.source)
            return (lambda: tex), sampler, size, kind
        if ch.kind == "black-cube":  # (a channel the code samples as a cube: nothing given)
            cube = self.resources.black_cube
            return (lambda: cube), sampler, (1, 1), kind
        if ch.kind == "keyboard":
            kb = self.resources.keyboard
            return (lambda: kb), sampler, (256, 3), kind
        if ch.kind == "noise":  # made when first drawn with: its mipmaps cost a compile
            return (lambda: self.resources.noise), sampler, (NOISE_SIZE,) * 2, kind
        black = self.resources.black
        return (lambda: black), sampler, (1, 1), kind

    def _where(self, p: P.Pass) -> str:
        """How a warning names pass ``p``: by its pass name when there are several, else
        by its file."""
        return f"{p.name} pass" if len(self.project.passes) > 1 else display_path(p.path)

    def _warn_unbound(self) -> None:
        """One warning line per channel a pass reads that nobody gave (it reads the noise
        texture, facet.lab.project): never a silent stand-in."""
        for p in self.project.ordered():
            prog = self.programs[p.key].gl
            for n in range(4):
                if n in p.channels:
                    continue
                for name in (f"iChannel{n}", f"u_tex{n}"):
                    if name in prog:
                        warnings.warn(f"{self._where(p)} reads {name}, which nothing is "
                                      "bound to: it reads facet's noise texture (Shadertoy's "
                                      "RGBA Noise Medium stand-in); give --channel"
                                      f"{n} SOURCE, or none for black", FacetWarning,
                                      stacklevel=3)

    def _draw_pass(self, p: P.Pass, shared: dict, time: float) -> None:
        prog: Any = self.programs[p.key].gl  # moderngl types a member as any kind of one
        cube = p.key == "cube"
        w, h = (self.cube_size,) * 2 if cube else (self.width, self.height)
        values = dict(shared, iResolution=(float(w), float(h), 1.0),
                      u_resolution=(float(w), float(h)))
        resolutions = []
        for n, (texture, sampler, size, _) in enumerate(self._bindings[p.key]):
            size = size or (self.width, self.height)
            resolutions.append((float(size[0]), float(size[1]),
                                float(size[2]) if len(size) > 2 else 1.0))
            read = [name for name in (f"iChannel{n}", f"u_tex{n}") if name in prog]
            if read:  # a channel the compiled pass does not read is not bound (nor made)
                texture().use(location=n)
                sampler.use(location=n)
            for name in read:
                prog[name].value = n
        for k, (name, (texture, sampler, _, _)) in enumerate(self._named[p.key]):
            unit = len(resolutions) + k  # after the four channels
            texture().use(location=unit)
            sampler.use(location=unit)
            if name in prog:
                prog[name].value = unit
        for name, value in values.items():
            if name in prog:
                write_sized(prog[name], value)
        # Arrays are written as bytes: the compiler may keep fewer elements than declared
        # (one, for a shader that reads iChannelResolution[0] only), and moderngl's value
        # setter wants a single value for a one-element array.
        if "iChannelResolution" in prog:
            m = prog["iChannelResolution"]
            m.write(np.array(resolutions[:m.array_length], np.float32).tobytes())
        if "iChannelTime" in prog:
            m = prog["iChannelTime"]
            m.write(np.full(m.array_length, time, np.float32).tobytes())
        if cube:
            face_tex, fbo = self.targets["cube"]["face"]
            target = self.targets["cube"]["cubes"][0]
            pixels = self.targets["cube"]["pixels"]
            fbo.use()
            for face in range(6):
                if "facet_face" in prog:
                    prog["facet_face"].value = face
                self.vaos[p.key].render(vertices=3)
                fbo.read_into(pixels, components=4, dtype="f4")  # GPU to GPU, no copy out
                target.write(face, pixels)
            if any(ch.is_cube and ch.filter == "mipmap" for q in self.project.ordered()
                   for ch in q.channels.values()):
                target.build_mipmaps()
            self.targets["cube"]["cubes"].reverse()  # [1]: the latest finished cube map
            return
        out = self.targets[p.key][0][1]
        out.use()
        self.vaos[p.key].render(vertices=3)
        if p.key != "image":
            if self._mipmapped(p.key):
                self.targets[p.key][0][0].build_mipmaps()
            self.targets[p.key].reverse()

    def _mipmapped(self, key: str) -> bool:
        return any(ch.kind == "buffer" and ch.source == key and ch.filter == "mipmap"
                   for q in self.project.ordered() for ch in q.channels.values())

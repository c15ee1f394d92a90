"""Full-screen shaders, Shadertoy-compatible: a host ``main()`` around the user's
``mainImage(out vec4 fragColor, in vec2 fragCoord)``, the standard inputs, buffers A-D with
feedback, channels from images or buffers, a ``common`` file, user uniforms, and hot reload.

Passes run in the order A, B, C, D, image. A buffer that reads itself sees its previous
frame; a pass that reads a buffer rendered earlier in the frame sees this frame's result,
a later one its previous frame (Shadertoy's rules; each buffer is a ping-pong pair).
Buffers are RGBA32F; the image pass renders to RGBA32F too and ``render`` returns its float
values (row 0 at the top).

Reloading never breaks what runs: ``reload()`` compiles every pass anew and swaps them in
only if all compiled; otherwise the last good programs stay and the result carries the
errors (``path:line:col: error: ...``, mapped through includes to the user's files).
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import FacetError, InputError, ShaderError
from ..gl.glsl_source import file_digest, glsl_root
from ..gl.shaders import GL_TYPES, INT_TYPES, Program, compile_program

BUFFERS = ("a", "b", "c", "d")
FILLED = ("iResolution", "iTime", "iTimeDelta", "iFrame", "iFrameRate", "iMouse", "iDate",
          "iSampleRate", "iChannelTime", "iChannelResolution", "iChannel0", "iChannel1",
          "iChannel2", "iChannel3")


@dataclass
class ReloadResult:
    """What ``reload()`` did: ``success`` (all passes compiled and are in use), ``changed``
    (some file's content differed), ``errors`` (compiler-style text) and ``diagnostics``."""

    success: bool
    changed: bool = True
    errors: str = ""
    diagnostics: list = field(default_factory=list)



class ShaderToy:
    """A Shadertoy-style program set over one GL context (a headless one by default)."""

    def __init__(self, image, *, buffers: dict | None = None, common=None,
                 channels: dict | None = None, size=(640, 360), context=None):
        from ..gl import context as glcontext

        self.paths = {"image": _existing(image, "shader")}
        for key, path in (buffers or {}).items():
            if key not in BUFFERS:
                raise InputError(f"buffer {key!r}: buffers are a, b, c and d")
            self.paths[key] = _existing(path, f"buffer {key}")
        self.common = _existing(common, "common file") if common else None
        self.width, self.height = _size(size)
        self._own_context = context is None
        self.ctx = glcontext.create_headless() if context is None else context
        self.uniforms: dict[str, object] = {}
        self.programs: dict[str, Program] = {}
        self._hashes: dict[Path, str | None] = {}
        self.frame, self.time = 0, 0.0
        self._vertex = glsl_root() / "shadertoy" / "fullscreen.vert"
        self.vaos: dict = {}
        with self.ctx:
            self.targets = self._make_targets()
            self.channel_specs = self._channels(channels or {})
            result = self.reload(force=True)
        if not result.success:
            self.close()
            raise ShaderError(result.errors, result.diagnostics)

    # -- construction --------------------------------------------------------------------
    def _make_targets(self) -> dict:
        """Ping-pong float targets per buffer, and one for the image pass."""
        size = (self.width, self.height)
        targets = {}
        for key in [*[k for k in BUFFERS if k in self.paths], "image"]:
            pair = []
            for _ in range(2 if key != "image" else 1):
                tex = self.ctx.texture(size, 4, dtype="f4")
                tex.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
                fbo = self.ctx.framebuffer([tex])
                fbo.clear(0.0, 0.0, 0.0, 0.0)
                pair.append((tex, fbo))
            targets[key] = pair
        return targets

    def _channels(self, channels: dict) -> dict:
        """Channel index -> ("buffer", key) or ("texture", gl texture)."""
        from ..gl.resources import upload_texture
        from ..scene.texture import Texture

        specs = {}
        for index, spec in channels.items():
            if index not in range(4):
                raise InputError(f"channel {index}: channels are 0 to 3")
            text = str(spec)
            if text.startswith("buffer-") and text[7:] in BUFFERS:
                if text[7:] not in self.paths:
                    raise InputError(f"--channel{index} {text}: no {text} was given "
                                     f"(--buffer-{text[7:]} FILE)")
                specs[index] = ("buffer", text[7:])
            else:
                texture = spec if isinstance(spec, Texture) else Texture.load(spec)
                specs[index] = ("texture", upload_texture(self.ctx, texture, srgb=False),
                                texture.size)
        return specs

    # -- programs and reloading ------------------------------------------------------------
    def _host_text(self, path: Path) -> str:
        host = (glsl_root() / "shadertoy" / "host.frag").read_text()
        includes = [f'#include "{self.common.resolve()}"'] if self.common else []
        includes.append(f'#include "{path.resolve()}"')
        return host.replace("\nFACET_USER_CODE\n", "\n" + "\n".join(includes) + "\n")

    def watched_files(self) -> list[Path]:
        """Every file the programs were built from (includes too)."""
        files = [p for p in self.paths.values()] + ([self.common] if self.common else [])
        for prog in self.programs.values():
            files += prog.sources["fragment"].files
        return sorted({f.resolve() for f in files})

    def changed(self) -> bool:
        """Whether any watched file's content differs from the last (re)load."""
        return any(file_digest(f) != self._hashes.get(f) for f in self.watched_files())

    def reload(self, force: bool = False) -> ReloadResult:
        """Recompile every pass when a file changed (or ``force``); keep the old programs if
        any pass fails."""
        if not force and not self.changed():
            return ReloadResult(True, changed=False)
        new, errors, diagnostics = {}, [], []
        with self.ctx:
            for key, path in self.paths.items():
                try:
                    new[key] = compile_program(self.ctx, self._vertex,
                                               glsl_root() / "shadertoy" / "host.frag",
                                               fragment_text=self._host_text(path))
                except ShaderError as exc:
                    errors.append(str(exc))
                    diagnostics += exc.diagnostics
                except FacetError as exc:
                    errors.append(str(exc))
            self._hashes = {f: file_digest(f) for f in {*self.watched_files(),
                                                   *(f for p in new.values()
                                                     for f in p.sources["fragment"].files)}}
            if errors:
                for prog in new.values():
                    prog.release()
                return ReloadResult(False, errors="\n".join(errors), diagnostics=diagnostics)
            for key, prog in self.programs.items():
                self.vaos.pop(key).release()
                prog.release()
            self.programs = new
            # Attribute-less vertex arrays: the vertex shader makes the triangle itself.
            self.vaos = {key: self.ctx.vertex_array(prog.gl, []) for key, prog in new.items()}
        for name, value in list(self.uniforms.items()):  # user uniforms survive a reload
            self._write_user_uniform(name, value)
        return ReloadResult(True)

    # -- uniforms ------------------------------------------------------------------------
    def active_uniforms(self) -> dict[str, tuple[str, int, bool]]:
        """name -> (GLSL type, array length, filled by facet) over every pass (the linked
        programs' active uniforms: ones the compiler optimised away are not listed)."""
        found = {}
        for prog in self.programs.values():
            for name, (gl_type, length) in prog.uniform_types().items():
                found[name] = (gl_type, length, name in FILLED)
        return dict(sorted(found.items()))

    def set_uniform(self, name: str, value) -> None:
        """Set a user uniform in every pass that uses it (kept across reloads)."""
        active = self.active_uniforms()
        if name not in active or active[name][2]:
            user = [n for n, (_, _, filled) in active.items() if not filled]
            raise InputError(f"no user uniform named {name!r} in "
                             f"{', '.join(str(p) for p in self.paths.values())}; "
                             f"it has: {', '.join(user) or 'none'}")
        gl_type, length, _ = active[name]
        values = np.atleast_1d(np.asarray(value, dtype=np.float64)).ravel()
        size = {"float": 1, "int": 1, "bool": 1, "uint": 1, "mat2": 4, "mat3": 9,
                "mat4": 16}.get(gl_type, int(gl_type[-1]) if gl_type[-1].isdigit() else 1)
        if values.size != size * length or not np.all(np.isfinite(values)):
            raise InputError(f"uniform {name} is {gl_type}"
                             f"{f'[{length}]' if length > 1 else ''}: expected {size * length}"
                             f" finite number(s), got {values.size}")
        if gl_type in INT_TYPES and not np.all(values == np.round(values)):
            raise InputError(f"uniform {name} is {gl_type}: expected integers, got "
                             f"{values.tolist()}")
        self.uniforms[name] = values
        self._write_user_uniform(name, values)

    def _write_user_uniform(self, name: str, values: np.ndarray) -> None:
        with self.ctx:
            for prog in self.programs.values():
                if name in prog.gl:
                    member = prog.gl[name]
                    dtype = "i4" if GL_TYPES.get(member.gl_type) in INT_TYPES else "f4"
                    member.write(values.astype(dtype).tobytes())

    # -- rendering -----------------------------------------------------------------------
    def step(self, time: float, time_delta: float, mouse=(0.0, 0.0, 0.0, 0.0),
             date: datetime.datetime | None = None, fps: float = 60.0) -> None:
        """Run every pass once: frame ``self.frame`` at ``time`` seconds."""
        date = date or datetime.datetime.now()
        seconds = date.hour * 3600 + date.minute * 60 + date.second + date.microsecond / 1e6
        inputs = {"iResolution": (float(self.width), float(self.height), 1.0),
                  "iTime": float(time), "iTimeDelta": float(time_delta),
                  "iFrame": int(self.frame), "iFrameRate": float(fps),
                  "iMouse": tuple(float(m) for m in mouse),
                  "iDate": (float(date.year), float(date.month - 1), float(date.day), seconds),
                  "iSampleRate": 44100.0}
        with self.ctx:
            self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND)
            for key in [*[k for k in BUFFERS if k in self.paths], "image"]:
                prog = self.programs[key]
                resolutions = np.zeros((4, 3), np.float32)
                for index, spec in self.channel_specs.items():
                    if spec[0] == "buffer":
                        # pair[1] holds the buffer's latest result: last frame's while it is
                        # not drawn yet (or for itself, drawing into pair[0]), this frame's
                        # once it is (the pair is swapped after each draw).
                        tex = self.targets[spec[1]][1][0]
                        size = (self.width, self.height)
                    else:
                        tex, size = spec[1], spec[2]
                    tex.use(location=index)
                    resolutions[index] = (size[0], size[1], 1.0)
                    if f"iChannel{index}" in prog.gl:
                        prog.gl[f"iChannel{index}"].value = index
                for name, value in inputs.items():
                    if name in prog.gl:
                        prog.gl[name].value = value
                if "iChannelResolution" in prog.gl:
                    prog.gl["iChannelResolution"].write(
                        resolutions[:prog.gl["iChannelResolution"].array_length].tobytes())
                if "iChannelTime" in prog.gl:
                    n = prog.gl["iChannelTime"].array_length
                    prog.gl["iChannelTime"].write(np.full(n, time, np.float32).tobytes())
                out = self.targets[key][0][1]
                out.use()
                self.vaos[key].render(vertices=3)
                if key != "image":
                    self.targets[key].reverse()
        self.frame += 1
        self.time = time

    def render(self, time: float = 0.0, *, fps: float = 60.0, mouse=(0.0, 0.0, 0.0, 0.0),
               date=None) -> np.ndarray:
        """The image at ``time`` seconds as float32 (H, W, 4), row 0 at the top. With buffers,
        frames run from 0 at a fixed step of 1 / ``fps`` up to ``time`` (so feedback is
        deterministic); without, one frame is drawn."""
        target = int(round(time * fps))
        if len(self.paths) == 1:
            self.frame = target
            self.step(time, 1.0 / fps, mouse, date, fps)
        else:
            if target < self.frame:
                self.restart()
            while self.frame <= target:
                self.step(self.frame / fps, 1.0 / fps, mouse, date, fps)
        return self.read()

    def resize(self, width: int, height: int) -> None:
        """New output size (a window was resized): buffers start again from frame 0."""
        if (width, height) == (self.width, self.height):
            return
        with self.ctx:
            for pair in self.targets.values():
                for tex, fbo in pair:
                    fbo.release()
                    tex.release()
            self.width, self.height = _size((width, height))
            self.targets = self._make_targets()
        self.frame = 0

    @property
    def image_framebuffer(self):
        """Where the image pass draws (bottom-up, like any GL framebuffer)."""
        return self.targets["image"][0][1]

    def restart(self) -> None:
        """Back to frame 0 with cleared buffers."""
        with self.ctx:
            for pair in self.targets.values():
                for _, fbo in pair:
                    fbo.clear(0.0, 0.0, 0.0, 0.0)
        self.frame, self.time = 0, 0.0

    def read(self) -> np.ndarray:
        out = np.empty((self.height, self.width, 4), np.float32)
        with self.ctx:
            self.targets["image"][0][1].read_into(out, components=4, dtype="f4")
        return np.ascontiguousarray(out[::-1])  # fragCoord's origin is the bottom-left

    def close(self) -> None:
        if self.ctx is None:
            return
        with self.ctx:
            for vao in self.vaos.values():
                vao.release()
            for prog in self.programs.values():
                prog.release()
            for pair in getattr(self, "targets", {}).values():
                for tex, fbo in pair:
                    fbo.release()
                    tex.release()
            for spec in getattr(self, "channel_specs", {}).values():
                if spec[0] == "texture":
                    spec[1].release()
        if self._own_context:
            self.ctx.release()
        self.ctx = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _existing(path, what: str) -> Path:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such {what}" if not p.exists() else
                         f"{p}: is a directory, expected a {what}")
    return p


def _size(size) -> tuple[int, int]:
    w, h = (int(v) for v in size)
    if w < 1 or h < 1:
        raise InputError(f"size must be at least 1x1, got {w}x{h}")
    return w, h

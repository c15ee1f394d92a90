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
from pathlib import Path

import numpy as np

from ..errors import InputError, ShaderError
from ..gl.fullscreen import fullscreen_vertex
from ..gl.glsl_source import glsl_root
from ..gl.shaders import Program, compile_program
from .programs import ReloadResult, WatchedPrograms
from .uniforms import check_uniform, write_uniform

BUFFERS = ("a", "b", "c", "d")
FILLED = ("iResolution", "iTime", "iTimeDelta", "iFrame", "iFrameRate", "iMouse", "iDate",
          "iSampleRate", "iChannelTime", "iChannelResolution", "iChannel0", "iChannel1",
          "iChannel2", "iChannel3")


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
        self.uniforms: dict[str, np.ndarray] = {}  # user uniforms, kept across reloads
        self.frame, self.time = 0, 0.0
        self.vaos: dict = {}
        self.watched = WatchedPrograms()
        self.watched.watch(*self.paths.values(), *([self.common] if self.common else []))
        with self.ctx:
            self.targets = self._make_targets()
            self.channel_specs = self._channels(channels or {})
            for key, path in self.paths.items():
                self.watched.add(key, lambda path=path: self._compile(path))
        result = self.reload(force=True)  # not nested: see facet.gl.context
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

    def _compile(self, path: Path) -> Program:
        prog = compile_program(self.ctx, fullscreen_vertex(),
                               glsl_root() / "shadertoy" / "host.frag",
                               fragment_text=self._host_text(path))
        for name, values in self.uniforms.items():  # user uniforms survive a reload
            write_uniform(prog, name, values)
        return prog

    def _make_vaos(self) -> None:
        for vao in self.vaos.values():
            vao.release()
        # Attribute-less vertex arrays: the vertex shader makes the triangle itself.
        self.vaos = {key: self.ctx.vertex_array(prog.gl, [])
                     for key, prog in self.programs.items()}

    @property
    def programs(self) -> dict[str, Program]:
        return self.watched.programs

    def watched_files(self) -> list[Path]:
        """Every file the programs were built from (includes too)."""
        return self.watched.files()

    def changed(self) -> bool:
        """Whether any watched file's content differs from the last (re)load."""
        return self.watched.changed()

    def reload(self, force: bool = False) -> ReloadResult:
        """Recompile every pass when a file changed (or ``force``); keep the old programs if
        any pass fails."""
        with self.ctx:
            result = self.watched.reload(force)
            if result.success and result.changed:
                self._make_vaos()
        return result

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
        where = ", ".join(str(p) for p in self.paths.values())
        values = check_uniform(name, value, list(self.programs.values()), set(FILLED), where)
        if values is None:
            return
        self.uniforms[name] = values
        with self.ctx:
            for prog in self.programs.values():
                write_uniform(prog, name, values)

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
            self.vaos.clear()
            self.watched.release()
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

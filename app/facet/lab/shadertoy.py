"""Full-screen shaders as people paste them: Shadertoy's ``mainImage`` with its passes
(Image, Buffer A-D with feedback, Cube A rendering a cube map), each pass with its own four
channels and their sampler settings (facet.lab.project), a common file, user uniforms and
hot reload; and glslViewer / Book of Shaders files with their own ``main()``
(facet.lab.dialect decides which).

Shadertoy's environment: ``HW_PERFORMANCE`` is 1, unset channels are black, buffers clamp
and filter linearly unless a channel says otherwise, the keyboard is a 256 x 3 texture,
``iDate`` is fixed (DEFAULT_DATE, or ``date``; None: the wall clock, as the live window
does) so a render at a given time is always the same.

Passes run in the order A, B, C, D, Cube A, Image. A buffer that reads itself sees its
previous frame; a pass that reads a buffer rendered earlier in the frame sees this frame's
result, a later one its previous frame (Shadertoy's rules; each buffer is a ping-pong
pair). Buffers are RGBA32F; the image pass renders to RGBA32F too and ``render`` returns
its float values (row 0 at the top). Nothing GL is made per frame.

Reloading never breaks what runs: ``reload()`` compiles every pass anew and swaps them in
only if all compiled; otherwise the last good programs stay and the result carries the
errors, each line naming its pass, errors before warnings, mapped to the user's files.
"""

from __future__ import annotations

import datetime
import functools
import warnings
from collections.abc import Hashable
from pathlib import Path
from typing import Annotated

import numpy as np

from ..boundary import Array, ArrayLike, Count, FilePath, Positive, Real, Size, checked
from ..errors import FacetWarning, InputError, ShaderError
from ..gl.glsl_source import display_path
from ..gl.reload import ReloadResult, WatchedPrograms
from ..gl.shaders import Program
from ..gl.uniforms import check_uniform, write_uniform
from . import project as P
from .assemble import check_channels, from_arguments, with_glslviewer_buffers
from .channels import ChannelResources
from .pass_draw import PassDrawing
from .passes import compile_pass
from .passes import source as pass_source
from .targets import PassTargets

Mouse = Annotated[ArrayLike, Array("2", "3", "4")]  # iMouse: x, y[, click x, click y]

DEFAULT_DATE = datetime.datetime(2000, 1, 1)  # iDate of headless renders (deterministic)
CUBE_SIZE = 512  # texels along a Cube A face
# Inputs that change from frame to frame (a program reading one is animated).
TIME_INPUTS = ("iTime", "iTimeDelta", "iFrame", "iDate", "iChannelTime", "u_time", "u_delta",
               "u_frame", "u_date")
FILLED = ("iResolution", "iTime", "iTimeDelta", "iFrame", "iFrameRate", "iMouse", "iDate",
          "iSampleRate", "iChannelTime", "iChannelResolution", "iChannel0", "iChannel1",
          "iChannel2", "iChannel3", "facet_face", "u_resolution", "u_time", "u_mouse",
          "u_date", "u_delta", "u_frame", "u_tex0", "u_tex1", "u_tex2", "u_tex3",
          "iMousePrev", "iVirtualDesktopCount")  # (the KDE dialect's other inputs: settable)


class ShaderToy(PassDrawing):
    """A Shadertoy-style program set (Image, Buffer A-D, Cube A, Common) over one GL
    context, headless by default; ``close()`` releases it.

    Parameters
    ----------
    image : str or Path, optional
        The Image pass's file (Shadertoy's ``mainImage``, or a glslViewer ``main``).
    buffers : dict, optional
        ``{"a": path, ...}``: Buffer A-D.
    common : str or Path, optional
        Code put before every pass.
    channels : dict, optional
        ``{0: "buffer-a", 1: "wood.png", ...}`` for every pass that sets none of its own
        (what facet.lab.project.channel takes, or Channel objects).
    size : (int, int)
        The output size.
    context : moderngl.Context, optional
        A context to draw in (a window's); default a headless one.
    project : facet.lab.project.Project, optional
        A whole project instead (a TOML project, a Shadertoy JSON export).
    pass_channels : dict, optional
        ``{"image": {0: ...}, "a": {...}}``: channels of one pass.
    cube : str or Path, optional
        The Cube A pass (``mainCubemap``).
    cube_size : int
        Texels along a side of Cube A's faces.
    date : datetime.datetime, optional
        ``iDate`` (default 2000-01-01 00:00:00; None: the wall clock).
    """

    @checked
    def __init__(self, image: FilePath | None = None, *, buffers: dict | None = None,
                 common: FilePath | None = None, channels: dict | None = None,
                 size: Size = (640, 360), context=None,
                 project: P.Project | None = None, pass_channels: dict | None = None,
                 cube=None, cube_size: int = CUBE_SIZE, date=DEFAULT_DATE):
        from ..gl import context as glcontext

        self.project = with_glslviewer_buffers(
            project or from_arguments(image, buffers, common, cube, channels or {},
                                      pass_channels or {}))
        check_channels(self.project)
        self.width, self.height = _size(size)
        self.cube_size = int(cube_size)
        self.date = date
        self._own_context = context is None
        self.ctx = glcontext.create_headless() if context is None else context
        self.uniforms: dict[str, np.ndarray] = {}  # user uniforms, kept across reloads
        self.frame, self.time = 0, 0.0
        self.draws = 0  # passes drawn so far (a cube pass counts once for its six faces)
        self.vaos: dict = {}
        self.dialects: dict[str, str] = {}
        self.watched = WatchedPrograms()
        files = [p.path for p in self.project.ordered() if p.code is None]
        if self.project.common is not None and self.project.common_code is None:
            files.append(self.project.common)
        if self.project.origin is not None:  # a TOML project or a JSON export
            files.append(self.project.origin)
        self.watched.watch(*files)
        with self.ctx:
            self.resources = ChannelResources(self.ctx)
            self.targets = self._make_targets()
            self._bind()
            for p in self.project.ordered():
                self.watched.add(p.key, functools.partial(self._compile, p))
                self.watched.labels[p.key] = p.name
            if len(self.project.passes) == 1:
                self.watched.labels.clear()  # one pass: no need to name it
        result = self.reload(force=True)  # not nested: see facet.gl.context
        if not result.success:
            self.close()
            raise ShaderError(result.errors, result.diagnostics)
        self._warn_unbound()

    @property
    def paths(self) -> dict[str, Path]:
        return {p.key: p.path for p in self.project.ordered()}

    # -- targets and channels ------------------------------------------------------------
    def _make_targets(self) -> PassTargets:
        return PassTargets(self.ctx, [p.key for p in self.project.ordered()],
                           (self.width, self.height), self.cube_size)

    # -- programs and reloading ------------------------------------------------------------
    def _compile(self, p: P.Pass) -> Program:
        types = [kind for _, _, _, kind in self._bindings[p.key]]
        try:
            prog, self.dialects[p.key] = compile_pass(self.ctx, self.project, p, types)
        except ShaderError as exc:
            sampled = self._sampled_as_cubes(p, exc)
            if not sampled:
                raise
            # Channels nothing was given for, which the code samples with a direction (a
            # cube map in the original): bound as cube maps, black, and said.
            for n in sampled:
                p.channels[n] = P.Channel("black-cube")
                warnings.warn(f"{self._where(p)} samples iChannel{n} with a direction "
                              "(vec3): it is a cube map on Shadertoy; facet binds a black "
                              f"one; give --channel{n} cube:FOLDER (six faces) or an "
                              "equirectangular image", FacetWarning, stacklevel=4)
            self._bindings[p.key] = self._bind_channels(p)
            types = [kind for _, _, _, kind in self._bindings[p.key]]
            prog, self.dialects[p.key] = compile_pass(self.ctx, self.project, p, types)
        for uniform, values in self.uniforms.items():  # user uniforms survive a reload
            write_uniform(prog, uniform, values)
        return prog

    def _sampled_as_cubes(self, p: P.Pass, exc: ShaderError) -> list[int]:
        """The channels of ``p`` that were given nothing (they read facet's noise, a 2D
        texture) and that the failed compile ``exc`` says are sampled with a vec3: the
        iChannelN named on each line where ``texture(sampler2D, vec3)`` matched nothing."""
        import re

        lines = {(path, line) for path, line, _col, _sev, message in exc.diagnostics
                 if re.search(r"texture\w*\(sampler2D, vec3", message)}
        if not lines:
            return []
        text = pass_source(self.project, p).splitlines()
        found = set()
        for path, line in lines:
            if path != display_path(p.path) or not 0 < line <= len(text):
                continue
            found |= {int(n) for n in re.findall(r"\biChannel([0-3])\b", text[line - 1])}
        return sorted(n for n in found if n not in p.channels)

    def _make_vaos(self) -> None:
        for vao in self.vaos.values():
            vao.release()
        # Attribute-less vertex arrays: the vertex shader makes the triangle itself.
        self.vaos = {key: self.ctx.vertex_array(prog.gl, [])
                     for key, prog in self.programs.items()}

    @property
    def programs(self) -> dict[Hashable, Program]:
        """The compiled programs, by pass key."""
        return self.watched.programs

    def changed(self) -> bool:
        """Whether any watched file's content differs from the last (re)load (a missing
        include that now exists counts).

        Returns
        -------
        bool
            True when a ``reload`` would compile.
        """
        return self.watched.changed()

    def reload(self, force: bool = False) -> ReloadResult:
        """Recompile every pass when a file changed; keep the old programs if any pass fails.

        Parameters
        ----------
        force : bool
            Recompile even when nothing changed.

        Returns
        -------
        ReloadResult
            ``success``, ``changed`` and ``errors`` (compiler-style lines, mapped to your
            files).
        """
        with self.ctx:
            result = self.watched.reload(force)
            if result.success and result.changed:
                self._make_vaos()
        return result

    # -- what the programs read ------------------------------------------------------------
    def _reads(self, names) -> bool:
        return any(name in prog.gl for prog in self.programs.values() for name in names)

    @property
    def animated(self) -> bool:
        """Whether frames differ with time alone: a pass reads a time or frame input, or a
        buffer reads its own last frame (feedback). A window redraws only then (or when a
        file, the mouse or a key changes something, ``reads_mouse``, ``reads_keys``)."""
        if self._reads(TIME_INPUTS):
            return True
        order = [p.key for p in self.project.ordered()]
        return any(ch.kind == "buffer" and order.index(ch.source) >= order.index(p.key)
                   for p in self.project.ordered() for ch in p.inputs().values())

    @property
    def reads_mouse(self) -> bool:
        return self._reads(("iMouse", "u_mouse"))

    @property
    def reads_keys(self) -> bool:
        return any(ch.kind == "keyboard" for p in self.project.ordered()
                   for ch in p.inputs().values())

    # -- uniforms ------------------------------------------------------------------------
    def active_uniforms(self) -> dict[str, tuple[str, int, bool]]:
        """The active uniforms over every pass (ones the compiler optimised away are not
        listed).

        Returns
        -------
        dict
            ``{name: (GLSL type, array length, filled by facet)}``.
        """
        found = {}
        for prog in self.programs.values():
            for name, (gl_type, length) in prog.uniform_types().items():
                found[name] = (gl_type, length, name in FILLED)
        return dict(sorted(found.items()))

    @checked
    def set_uniform(self, name: str, value) -> None:
        """Set a user uniform in every pass that uses it (kept across reloads).

        Parameters
        ----------
        name : str
            The uniform (not one facet fills).
        value : float or sequence of float
            Its value(s), as many as its type holds.
        """
        where = ", ".join(str(p) for p in self.paths.values())
        values = check_uniform(name, value, list(self.programs.values()), set(FILLED), where)
        if values is None:
            return
        self.uniforms[name] = values
        with self.ctx:
            for prog in self.programs.values():
                write_uniform(prog, name, values)

    # -- rendering -----------------------------------------------------------------------
    @checked
    def step(self, time: Real, time_delta: Real, mouse: Mouse = (0.0, 0.0, 0.0, 0.0),
             date: datetime.datetime | None = None, fps: Positive = 60.0) -> None:
        """Run every pass once: frame ``self.frame`` at ``time`` seconds.

        Parameters
        ----------
        time : float
            ``iTime``, seconds.
        time_delta : float
            ``iTimeDelta``.
        mouse : (4,) float
            ``iMouse``, pixels.
        date : datetime.datetime, optional
            ``iDate`` (default ``self.date``; the wall clock where that is None).
        fps : float
            ``iFrameRate``.
        """
        self._step(time, time_delta, mouse, date, fps, None)

    def _step(self, time, time_delta, mouse, date, fps, keys) -> None:
        """``step``, drawing only the passes in ``keys`` (None: every one)."""
        date = date or self.date or datetime.datetime.now()
        seconds = date.hour * 3600 + date.minute * 60 + date.second + date.microsecond / 1e6
        day = (float(date.year), float(date.month - 1), float(date.day), seconds)
        shared = {"iTime": float(time), "iTimeDelta": float(time_delta),
                  "iFrame": int(self.frame), "iFrameRate": float(fps),
                  "iMouse": tuple(float(m) for m in mouse), "iDate": day,
                  "iSampleRate": 44100.0, "u_time": float(time), "u_delta": float(time_delta),
                  "u_frame": int(self.frame), "u_mouse": tuple(float(m) for m in mouse[:2]),
                  "u_date": day, "iMousePrev": tuple(float(m) for m in mouse[:2]),
                  "iVirtualDesktopCount": 1}
        with self.ctx:
            self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND | self.ctx.CULL_FACE)
            self.resources.upload_keys()
            for p in self.project.ordered():
                if keys is None or p.key in keys:
                    self._draw_pass(p, shared, time)
                    self.draws += 1
            self.ctx.clear_samplers(0, 4 + max(len(n) for n in self._named.values()))
        self.frame += 1
        self.time = time

    @checked
    def render(self, time: Real = 0.0, *, fps: Positive = 60.0,
               mouse: Mouse = (0.0, 0.0, 0.0, 0.0),
               date: datetime.datetime | None = None) -> np.ndarray:
        """The image at ``time`` seconds. With buffers, frames run from 0 at a fixed step of
        1 / ``fps`` up to ``time`` (so feedback is deterministic), though a pass that does not
        feed a later frame is drawn on the last one only; without buffers, one frame is drawn.

        Parameters
        ----------
        time : float
            Seconds.
        fps : float
            The step of the frames that lead up to ``time``.
        mouse : (4,) float
            ``iMouse``, pixels.
        date : datetime.datetime, optional
            ``iDate``.

        Returns
        -------
        (H, W, 4) float32 ndarray
            Row 0 at the top.
        """
        target = int(round(time * fps))
        if len(self.project.passes) == 1:
            self.frame = target
            self.step(time, 1.0 / fps, mouse, date, fps)
        else:
            if target < self.frame:
                self.restart()
            carried = self._carried()
            while self.frame <= target:  # frames before the one shown: what feeds forward
                self._step(self.frame / fps, 1.0 / fps, mouse, date, fps,
                           None if self.frame == target else carried)
        return self.read()

    def _pass_reads(self, key: str, name) -> bool:
        """Whether pass ``key``'s compiled program reads input ``name`` (a channel number
        or a sampler's name): the compiler drops what the code never samples."""
        prog = self.programs[key].gl
        names = (f"iChannel{name}", f"u_tex{name}") if isinstance(name, int) else (name,)
        return any(n in prog for n in names)

    def _carried(self) -> set[str]:
        """The passes a frame needs from the frames before it: each pass some pass reads
        last frame's picture of (itself, or one drawn later in the frame), and every pass
        these read. The others (the Image pass always) depend on the frame's inputs and
        this frame's buffers alone, so ``render`` draws them on the frame it shows only:
        the same picture, without the work of every frame on the way."""
        order = [p.key for p in self.project.ordered()]
        reads = {p.key: {ch.source for name, ch in p.inputs().items()
                         if ch.kind == "buffer" and ch.source in order
                         and self._pass_reads(p.key, name)}
                 for p in self.project.ordered()}
        needed = {source for key in order for source in reads[key]
                  if order.index(source) >= order.index(key)}
        todo = list(needed)
        while todo:
            for source in reads[todo.pop()] - needed:
                needed.add(source)
                todo.append(source)
        return needed

    @checked
    def resize(self, width: Annotated[int, Count(1, 1 << 16)],
               height: Annotated[int, Count(1, 1 << 16)]) -> None:
        """A new output size (a window was resized): buffers start again from frame 0.

        Parameters
        ----------
        width, height : int
            Pixels.
        """
        if (width, height) == (self.width, self.height):
            return
        with self.ctx:
            self.targets.release()
            self.width, self.height = _size((width, height))
            self.targets = self._make_targets()
            self._bind()
        self.frame = 0

    @property
    def image_texture(self):
        """The Image pass's picture as a texture (RGBA32F, bottom-up)."""
        return self.targets["image"][0][0]

    @property
    def image_framebuffer(self):
        """Where the image pass draws (bottom-up, like any GL framebuffer)."""
        return self.targets.image_framebuffer

    def restart(self) -> None:
        """Back to frame 0 with cleared buffers."""
        with self.ctx:
            self.targets.clear()
        self.frame, self.time = 0, 0.0

    def read(self) -> np.ndarray:
        """The Image pass's latest picture.

        Returns
        -------
        (H, W, 4) float32 ndarray
            Row 0 at the top.
        """
        with self.ctx:
            return self.targets.read()

    def read_cube(self) -> np.ndarray:
        """The Cube A pass's latest cube map.

        Returns
        -------
        (6, S, S, 4) float32 ndarray
            OpenGL's face order, rows as written (t = 0 first).
        """
        with self.ctx:
            return self.targets.read_cube()

    def close(self) -> None:
        if self.ctx is None:
            return
        with self.ctx:
            for vao in self.vaos.values():
                vao.release()
            self.vaos.clear()
            self.watched.release()
            if hasattr(self, "targets"):
                self.targets.release()
            if hasattr(self, "resources"):
                self.resources.release()
        if self._own_context:
            self.ctx.release()
        self.ctx = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _size(size) -> tuple[int, int]:
    w, h = (int(v) for v in size)
    if w < 1 or h < 1:
        raise InputError(f"size must be at least 1x1, got {w}x{h}")
    return w, h

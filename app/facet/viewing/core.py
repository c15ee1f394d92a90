"""What every viewer front shares (no glfw, no GL of its own): the scene and its file, the
render options (the scene's < the command line's < the keys' < the moment's), the orbit
camera, the clock, the keys' actions, the pointer's drags, file and shader reloads, and
drawing one frame (progressive refinement while the view is still) into a framebuffer.

A front (the glfw window, a headless canvas) subclasses ``ViewerCore`` and gives it a
renderer, ``surface_size`` (pixels drawn), ``pointer_size`` (the events' coordinate space),
``grab``, ``quit`` and ``show_status``; it turns its own events into ``press`` / ``move`` /
``release`` / ``scroll`` / ``char``.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path
from typing import Annotated

import numpy as np

from ..boundary import Count, Crease, FilePath, Number, Size, checked
from ..errors import FacetError, InputError
from ..gl.glsl_source import file_digest
from ..options.render import options_for, parse_layer
from ..render.capabilities import view_sampling
from ..scene.pbr import as_phong
from ..scene.scene import Scene
from .actions import ViewerActions
from .debounce import Debounce
from .keys import KEYMAP

Source = Scene | FilePath  # what a viewer shows: a scene, or a file (reloaded when it changes)

FRONT = "view"  # the viewer's defaults (facet.options.render.FRONT_DEFAULTS)


def explicit_layer(options=None, size=None, msaa=None):
    """The viewer's explicit layer: raw ``options`` (e.g. the command line's), with
    ``size`` and ``msaa`` when given, parsed once."""
    given = {"size": size, "msaa": msaa}
    return parse_layer({**(options or {}), **{k: v for k, v in given.items() if v is not None}})


def screenshot_folder(folder) -> Path:
    """The folder the viewer's keys write pictures into: ``folder``, an existing directory
    (else one InputError saying so), or the working directory when None."""
    if folder is None:
        return Path(".")
    path = Path(folder)
    if not path.is_dir():
        raise InputError(f"screenshots: {path} is not a folder (create it, or leave the option "
                         "out to write into the working directory)")
    return path


class ViewerCore(ViewerActions):
    """The viewer's state and controls over ``source`` (a Scene, or a mesh or scene file).

    ``options``: raw render options over the scene's (e.g. the command line's); ``size`` and
    ``msaa``, when given, join them; ``shader``: a UserShader replacing the file's
    materials' shaders; ``crease``: how files without normals are read; ``time_end``: the
    animations loop from the options' time to it; ``sizes``: point and line sizes over the
    file's; ``screenshots``: the folder the ``s``, ``S`` and ``t`` keys write into (default:
    the working directory). A subclass calls ``start(renderer)`` once its surface exists.
    """

    status_name = "facet view"  # how errors printed to stderr begin

    @checked
    def __init__(self, source: Source, size: Size | None = None,
                 msaa: Annotated[int | None, Count(0, 64)] = None, shader=None, options=None,
                 crease: Crease = None, time_end: Annotated[float | None, Number()] = None,
                 sizes: dict | None = None, screenshots: FilePath | None = None):
        self.screenshots = screenshot_folder(screenshots)
        self.path = Path(source) if isinstance(source, (str, Path)) else None
        self.crease = crease
        self.user_shader = shader
        self.sizes = sizes or {}
        self.explicit = explicit_layer(options, size, msaa)
        self.scene = self._load(self.path) if self.path else source
        self.time_end = time_end
        self.keys: dict = {}  # render options the keys changed (facet.viewing.actions)
        self.fixed_rig = None  # the default lights frozen in the world (key l)
        self.error = ""
        self._samples = 0  # supersamples accumulated for the current view
        self._sample_count = 0  # supersamples the current view refines to (0: none)
        self._settled = False  # the view's noise is below the options' (noise given)
        self._drag = None
        self._cursor = (0.0, 0.0)
        self._dirty = True

    @property
    def initial_size(self) -> tuple[int, int]:
        """The size a new surface opens at: the options' (the scene's, else the viewer's
        default, facet.options.render.FRONT_DEFAULTS)."""
        return options_for(self.scene, self.explicit, front=FRONT).size

    def start(self, renderer) -> None:
        """Draw through ``renderer`` from now on (the surface exists: its size is known)."""
        self.renderer = renderer
        self._set_scene(self.scene, frame=True)
        self._set_playback()
        self._file_digest = file_digest(self.path) if self.path else None
        self._file_watch, self._shader_watch = Debounce(), Debounce()

    # -- what a front provides -----------------------------------------------------------
    @property
    def surface_size(self) -> tuple[int, int]:
        """Pixels drawn (w, h)."""
        raise NotImplementedError

    @property
    def pointer_size(self) -> tuple[float, float]:
        """The size of the space pointer events come in (a window's screen coordinates, a
        page's CSS pixels), which may differ from the pixels drawn."""
        return self.surface_size

    def show_status(self, text: str) -> None:
        """Show a one-line status (a window's title)."""

    front = "window"  # what keys.help_text describes: "window", or "page" (served, notebook)

    def say(self, text: str) -> None:
        """A notice for the person at this viewer (a key's result, the key map, a warning):
        a window's terminal here; a page's overlay in facet.viewing.session."""
        print(text)

    # -- scene, options and camera ---------------------------------------------------------
    def _load(self, path):
        from ..formats.source import open_scene

        scene = open_scene(path, crease=self.crease)
        if self.sizes:
            from ..scene.points import resize_scene

            resize_scene(scene, self.sizes)
        if self.user_shader is not None:
            for obj in scene.objects:
                obj.material = replace(as_phong(obj.material), shader=self.user_shader)
        return scene

    def options(self, **changes):
        """The render options of the picture now: the scene's < the command line's < the
        keys' < ``changes``, at the surface's size and the clock's time."""
        now = {"size": self.surface_size, "time": self.playback.time()}
        return self.renderer.options(self.scene, options_for(
            self.scene, self.explicit, self.keys, {**now, **changes}, front=FRONT))

    def shown_scene(self):
        """The scene as drawn: with the default lights frozen in place if ``l`` did that."""
        return self.scene if self.fixed_rig is None else self.scene.view(lights=self.fixed_rig)

    @property
    def aa(self) -> str:
        return str(self.options().aa)

    def view_options(self):
        """The options a still view refines by: ``options()`` with the engine's own view
        count when they name no sample count (the path tracer refines to
        facet.render.capabilities.VIEW_PATHS, or until ``noise``; ``view_sampling``).
        Screenshots at another scale and turntables render by ``options()``."""
        return view_sampling(self.options())

    @property
    def refining(self) -> bool:
        """Progressive supersampling still has samples to add (and, with ``noise``, the
        picture is still noisier than that)."""
        if self._settled:
            return False
        return self._samples < self.renderer.samples(self.shown_scene(), self.camera(),
                                                     self.view_options())

    @property
    def animated(self) -> bool:
        """The animations play, or a user's shader on the scene reads u_time: keep drawing
        while it is shown (its programs are made at the first draw, which every new scene
        gets)."""
        if not self.playback.playing:
            return False
        user = self.renderer.user_programs()
        return bool(self.scene.animations) or (
            user is not None and any(o.material.shader is not None for o in self.scene.objects)
            and user.reads_time())

    @property
    def wants_frame(self) -> bool:
        """Something changed, plays or refines: draw another frame (else idle)."""
        return self._dirty or self.animated or self.refining

    def _set_playback(self) -> None:
        """The clock of a newly opened scene: from the options' time, looping over --time
        A:B or else the length of the animations that play."""
        from .playback import Playback

        opts = options_for(self.scene, self.explicit, front=FRONT)
        end = self.time_end
        if end is None and self.scene.animated:
            end = max(a.rig.duration(opts.animation if a.rig.has(opts.animation) else None)
                      for a in self.scene.animated)
        self.playback = Playback(opts.time, end if end and end > opts.time else None)

    def _set_scene(self, scene, frame: bool) -> None:
        from ..geometry.orbit import OrbitControl

        self.scene = scene
        opts = options_for(scene, self.explicit, front=FRONT)
        if frame or not hasattr(self, "control"):
            self.control = OrbitControl(scene.at(opts.time, opts.animation).bounds, up=opts.up,
                                        aspect=self.aspect)
            camera = scene.camera(opts.camera)
            if camera is not None:
                self.control.set_camera(camera)
        else:
            self.control.bounds = np.asarray(scene.at(opts.time, opts.animation).bounds)
        self.triangles = sum(o.mesh.face_count for o in scene.objects)
        self.splat_count = sum(c.splats.count for c in getattr(scene, "splats", ()))
        self.request_frame()

    @property
    def aspect(self) -> float:
        w, h = self.surface_size
        return w / max(h, 1)

    def camera(self):
        """The camera the viewer shows now."""
        return self.control.camera(self.aspect)

    def set_camera(self, camera) -> None:
        self.control.set_camera(camera)
        self.request_frame()

    def request_frame(self) -> None:
        self._dirty = True

    # -- drawing -------------------------------------------------------------------------
    def draw_into(self, framebuffer) -> None:
        """Draw one frame into ``framebuffer`` (bottom-up, like GL; the renderer's context
        current): a moving or changed view gets one quick picture, a still one adds a
        supersample towards the headless picture."""
        camera, scene = self.camera(), self.shown_scene()
        opts = self.view_options()
        moving = self._dirty or self.animated
        n = self._sample_count = self.renderer.samples(scene, camera, opts)
        if n and (opts.aa.supersampled or not moving):
            # One more sample per frame while nothing changes; a change starts over with one
            # sample (or, for the distributed effects, one plain picture): moving stays fast.
            self._samples = self.renderer.present(
                scene, camera, framebuffer, opts, sample=0 if moving else self._samples)
            # (with noise: the view is done once no pixel is noisier: facet.render.budget)
            self._settled = opts.noise is not None and self.renderer.view_settled
        else:
            self.renderer.present(scene, camera, framebuffer, opts)
            self._samples = 0
            self._settled = False
        self._dirty = False

    def state(self) -> dict:
        """What the status line says, as data for pages and tests to wait on: the engine,
        the supersamples drawn of those the view refines to (0 of 0: none), whether its noise
        is below the options' (``settled``: noise given, the view done early), the triangles
        shown and the error ("" without one)."""
        return {"engine": self.options().engine, "samples": self._samples,
                "of": self._sample_count, "settled": self._settled,
                "triangles": self.triangles, "error": self.error}

    def status(self, fps: float | None = None) -> str:
        """One line: the file, triangles, engine, clock, refinement and any error."""
        name = self.path.name if self.path else "scene"
        text = f"facet - {name} - {self.triangles:,} triangles"
        if getattr(self, "splat_count", 0):
            text += f" - {self.splat_count:,} splats"
        if fps is not None:
            text += f" - {fps:.0f} fps"
        engine = self.options().engine  # the keys', the flag's or the scene file's
        if engine != "raster":
            text += f" - engine {engine}"
        if self.scene.animations:
            text += f" - {self.playback.time():.2f} s" + (
                "" if self.playback.playing else " (paused: p plays)")
        if self._sample_count:  # progressive supersampling: how far it has refined
            text += f" - {self._samples}/{self._sample_count} samples"
            if self._settled:
                text += f" (noise {self.options().noise:g} reached)"
        return f"{text} - error: {self.error}" if self.error else text

    # -- events (a front translates its own into these) -----------------------------------
    def _run_action(self, method: str, *args) -> None:
        try:
            getattr(self, method)(*args)
            self.error = ""
        except FacetError as exc:
            self._report(str(exc))
        self.request_frame()

    def char(self, char: str) -> None:
        """A typed character: a key of KEYMAP, or 1-9 for the scene file's cameras."""
        if len(char) == 1 and char in "123456789":
            self._run_action("use_camera", int(char) - 1)
        elif char in KEYMAP:
            self._run_action(KEYMAP[char].method)

    def press(self, x: float, y: float, pan: bool) -> None:
        """A button went down at (x, y) (pointer coordinates): a drag orbits or pans."""
        self._cursor = (x, y)
        self._drag = ("pan" if pan else "orbit", (x, y))

    def release(self) -> None:
        self._drag = None

    def move(self, x: float, y: float) -> None:
        """The pointer moved to (x, y): a drag orbits (arcball) or pans."""
        self._cursor = (x, y)
        if self._drag is None:
            return
        kind, (x0, y0) = self._drag
        w, h = self.pointer_size
        if kind == "orbit":
            self.control.orbit((x0, y0), (x, y), w, h)
        else:
            self.control.pan(x - x0, y - y0, w, h)
        self._drag = (kind, (x, y))
        self.request_frame()

    def scroll(self, notches: float, x: float | None = None, y: float | None = None) -> None:
        """Zoom ``notches`` (positive: in) towards (x, y), by default the last pointer
        position."""
        if x is None or y is None:
            x, y = self._cursor
        w, h = self.pointer_size
        self.control.zoom(notches, x, y, w, h)
        self.request_frame()

    def open(self, path) -> None:
        """Show another mesh or scene file (framed anew)."""
        try:
            scene = self._load(path)
        except FacetError as exc:
            self._report(str(exc))
            return
        self.path = Path(path)
        self.fixed_rig = None
        self._set_scene(scene, frame=True)
        self._set_playback()
        self._file_digest = file_digest(self.path)
        self.error = ""

    def fail_frame(self, message: str) -> None:
        """A frame could not be drawn (a front caught why): ``message`` goes to the status
        line, and nothing is drawn again until something changes."""
        self.error = message.splitlines()[0] if message else "the frame failed"
        self._dirty = False

    def _report(self, message: str) -> None:
        self.error = message.splitlines()[0]
        print(f"{self.status_name}: error: {message}", file=sys.stderr)
        self.show_status(self.status())

    def _check_shaders(self) -> None:
        """Reload user shaders whose files changed and then stayed put; a failure keeps the
        last good program. The caller holds the renderer's context (a window's is always
        current; a Session's frame enters it): a ``with ctx:`` block of its own here would
        leave the caller's drawing without a context when it ends (facet.gl.context)."""
        user = self.renderer.user_programs()
        if user is None or not self._shader_watch.due(user.changed):
            return
        result = user.reload()
        if not result.changed:
            return
        if result.success:
            self.error = ""
            print("shaders reloaded", file=sys.stderr)
        else:
            self._report(result.errors)
        self.request_frame()

    def check_files(self) -> None:
        """Reload user shaders and the open file when their content changed and then stayed
        put (a failure keeps what was shown); with the renderer's context current."""
        self._check_shaders()
        if self.path is None:
            return

        def changed():  # a file gone, or no longer readable here, is a change too
            token = file_digest(self.path) or "unreadable"
            return token if token != (self._file_digest or "unreadable") else None

        if not self._file_watch.due(changed):
            return
        self._file_digest = file_digest(self.path)
        try:
            scene = self._load(self.path)
        except FacetError as exc:
            self._report(str(exc))
            return
        self._set_scene(scene, frame=False)
        self.error = ""
        print(f"reloaded {self.path}")

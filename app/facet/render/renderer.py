"""``Renderer``: owns a GL context and everything made in it, and runs the one pass sequence.

    with Renderer(640, 480) as r:
        frame = r.render(scene, camera, outputs=("color", "depth", "ids", "normals"))

``render`` (an offscreen target, read back to numpy; facet.render.frame) and ``present`` (a
window's framebuffer) are two destinations of the same sequence, ``_sequence``, whatever
the engine (facet.render.engine: the ``engine`` option picks it once per call):

1. prepare: the options (facet.options.render, resolved once per call), the engine (and
   one warning line for each thing it cannot honour), the camera and its lens, the lights
   that shine (the default rig when the scene has none), background and environment; the
   frame's shared state (facet.render.state);
2. what the engine's samples share (the rasterizer's shadow maps, the tracer's geometry);
3. the exact channels (depth, ids, normals, position, uv) at pixel centres: with the
   colour in one pass, or (MSAA, supersampling) in a pass of their own, drawn when
   first read (facet.render.frame says why);
4. colour: one picture (the rasterizer's, MSAA when asked), or the sum of supersamples
   carrying the distributed effects (facet.render.antialias): all of them offscreen, one
   more per call in a window, so a still view refines;
5. finishing (facet.render.finish): mean, straight alpha, sRGB, into the destination.

A call changes nothing the next one sees: targets are kept per size, sample count and
format, programs per variant, meshes per Mesh; options are never stored.
"""

from __future__ import annotations

import contextlib
import weakref
from collections.abc import Iterator
from dataclasses import replace

import numpy as np

from ..boundary import checked
from ..errors import InputError
from ..geometry.camera import Camera
from ..geometry.lens import with_lens
from ..gl import context as glcontext
from ..gl.resources import ResourceCache
from ..options.render import (
    ParsedLayer,
    RenderOptions,
    clamp_msaa,
    options_for,
    parse_layer,
)
from ..scene.scene import Scene
from ..scene.staging import staged
from .antialias import point_lights_for
from .denoise import denoise_lines
from .destination import Destination, Surfaces
from .engine import UserShaderPrograms
from .finish import Finisher
from .frame import Frame
from .prepare import prepare_frame, say_if_nothing_in_view
from .sequence import PassSequence


class Renderer(PassSequence):
    """Renders scenes headlessly (``render``) or into a window (``present``).

    The options given here are this renderer's, for every call: above a scene's own and below
    each call's keywords (facet.options.render). ``close()`` (or leaving a ``with`` block)
    releases the context and every GL object.

    Parameters
    ----------
    width, height : int, optional
        The image size (both or neither: without, the scene's size, else 1280x720).
    msaa : int, optional
        Multisample anti-aliasing samples (0, 2, 4 or 8: MSAA_CHOICES; within what the GL
        allows, said in one line where it allows fewer).
    context : moderngl.Context, optional
        A window's GL context (used, not owned); otherwise a headless one is made.
    device : int, optional
        The EGL device (GPU) index for the headless context.
    backend : str, optional
        ``auto``, ``egl`` or ``osmesa`` (facet.gl.context).
    **options
        Render options, e.g. ``shading="blinn"``, ``srgb=True``, ``float_color=True``.

    Raises
    ------
    facet.ContextError
        When no OpenGL context can be made (says what was tried and what to install).
    """

    def __init__(self, width: int | None = None, height: int | None = None,
                 msaa: int | None = None, *, context=None, device: int | None = None,
                 backend: str | None = None, **options):
        # (width, height and msaa are the size and msaa options: the one options parser
        # checks them, as every other option, and names them)
        if (width is None) != (height is None):
            raise InputError("give both width and height (or neither: the scene's size)")
        layer = {"size": (width, height) if width is not None else None, "msaa": msaa,
                 **options}
        self.defaults = parse_layer(layer)  # this renderer's explicit options
        self._own_context = context is None
        # ``device``: the EGL device (GPU) index for the headless context (batch workers);
        # ``backend``: auto / egl / osmesa (facet.gl.context).
        self.ctx = (glcontext.create_headless(device=device, backend=backend)
                    if context is None else context)
        self.cache = ResourceCache(self.ctx)
        self._engines: dict = {}  # name -> engine (facet.render.engine), made on first use
        self._finisher: Finisher | None = None  # the finishing pass, made on first use
        self._warned: set[str] = set()  # what the engines cannot honour, said once
        self._surfaces: Surfaces | None = None
        self._closed = False
        # The last Frame with channels still on the GPU (weakly).
        self._unread: weakref.ref[Frame] | None = None
        self._inside = False  # the context is current (current(), render, present)
        with self.ctx:
            # What the MSAA policy needs to know (facet.options.render.clamp_msaa).
            self._limits = (self.ctx.max_samples, self.ctx.info.get("GL_RENDERER", "this GL"))
            if width is not None:  # fail early on a size this GL cannot render
                self._surfaces_for((width, height))

    @property
    def size(self) -> tuple[int, int]:
        return self.defaults.get("size", RenderOptions.size)

    width = property(lambda self: self.size[0])
    height = property(lambda self: self.size[1])

    @property
    def info(self) -> dict[str, object]:
        return glcontext.describe(self.ctx)

    def options(self, scene: Scene, options=None, *, front: str | None = None,
                **kwargs) -> RenderOptions:
        """The options a call with these arguments renders with.

        Parameters
        ----------
        scene : Scene
            The scene (its own options are a layer).
        options : RenderOptions or mapping, optional
            A ``RenderOptions`` is used as it is (a front resolved it), with ``kwargs`` on top;
            a mapping is one more layer.
        front : str, optional
            Whose defaults (facet.options.render.FRONT_DEFAULTS: ``view``, ...).
        **kwargs
            Render options, the top layer.

        Returns
        -------
        RenderOptions
            The front's defaults < the scene's < this renderer's < ``options`` < ``kwargs``,
            MSAA clamped to what this GL supports.
        """
        if isinstance(options, RenderOptions):
            opts = options.merged(kwargs)
        else:
            opts = options_for(scene, self.defaults, options, kwargs, front=front)
        aa = clamp_msaa(opts.aa, *self._limits)
        return opts if aa is opts.aa else replace(opts, aa=aa)

    def camera(self, scene: Scene, opts: RenderOptions) -> Camera:
        """The camera a render of ``scene`` uses when none is given.

        Parameters
        ----------
        scene : Scene
            The scene.
        opts : RenderOptions
            The options (their ``camera`` name, ``time`` and ``up``).

        Returns
        -------
        Camera
            The scene's camera the options name (else its first), else one framing it at the
            options' time.
        """
        scene = staged(scene, opts)
        return scene.camera(opts.camera) or Camera.frame(scene.bounds, up=opts.up,
                                                         aspect=opts.width / opts.height)

    @checked
    def render(self, scene: Scene, camera: Camera | None = None, options=None,
               **kwargs) -> Frame:
        """Render ``scene`` into numpy arrays.

        Parameters
        ----------
        scene : Scene
            What to draw.
        camera : Camera, optional
            Default: ``camera(scene, options)`` (the scene's, else framed).
        options : RenderOptions or mapping, optional
            Render options for this call.
        **kwargs
            Render options for this call (``outputs``, ``aa``, ``msaa``, ``spp``, ``shadows``,
            ``shading``, ``engine``, ``time``, ``srgb``, ``background``, ...); a call never
            changes the next one.

        Returns
        -------
        Frame
            ``color`` (H, W, 4) uint8 (or float32 with ``float_color``), ``depth`` (H, W)
            float32 linear, ``object_ids`` (H, W) int32, and the other outputs asked for.
        """
        self._check_open()
        opts = self.options(scene, options, **kwargs)
        scene = staged(scene, opts)
        with self.current():  # several renderers (contexts) may live in one thread
            camera = camera or self.camera(scene, opts)
            say_if_nothing_in_view(scene, camera, opts)
            return self._sequence(scene, camera, opts, Destination())

    @checked
    def present(self, scene: Scene, camera: Camera, framebuffer, options=None, *,
                sample: int | None = None, **kwargs) -> int:
        """Draw into a window's framebuffer with ``render``'s sequence (call it with the
        window's context current).

        Parameters
        ----------
        scene : Scene
            What to draw.
        camera : Camera
            The window's camera.
        framebuffer : moderngl.Framebuffer
            Bottom-up, like GL's default framebuffer.
        options : RenderOptions or mapping, optional
            Render options.
        sample : int, optional
            None: one picture, what a moving camera shows (lens, shutter and area lights at
            their centres). k: add supersample k (0 starts over) and show the mean so far; after
            the last the picture equals ``render``'s.
        **kwargs
            Render options.

        Returns
        -------
        int
            The supersamples shown.
        """
        self._check_open()
        opts = self.options(scene, options, **kwargs)
        scene = staged(scene, opts)
        was, self._inside = self._inside, True
        try:
            return self._sequence(scene, camera, opts, Destination(framebuffer, sample))
        finally:
            self._inside = was

    @checked
    def samples(self, scene: Scene, camera: Camera, options=None, **kwargs) -> int:
        """How many supersamples the colour of this render sums.

        Parameters
        ----------
        scene : Scene
            The scene.
        camera : Camera
            The camera.
        options : RenderOptions or mapping, optional
            Render options.
        **kwargs
            Render options.

        Returns
        -------
        int
            The count (0: one picture).
        """
        opts = self.options(scene, options, **kwargs)
        scene = staged(scene, opts)
        with self.current():  # (an engine made on first use makes GL objects)
            engine = self._engine(opts.engine)
        aa = engine.sampling(engine.decided(opts), scene,
                             with_lens(camera, opts.aperture, opts.focus), False)
        return aa.samples if aa is not None else 0

    @contextlib.contextmanager
    def current(self) -> Iterator[Renderer]:
        """This renderer's context current for a block: what a front wraps its drawing in
        (``present`` is called inside one). Inside another such block it changes nothing:
        a ``with ctx:`` block nested in another leaves the outer one without a context
        when it ends (facet.gl.context), so methods that need the context (``samples``)
        enter it through here.

        Returns
        -------
        contextmanager of Renderer
            ``with renderer.current():`` holds the context for the block.
        """
        if self._inside:
            yield self
            return
        with self.ctx:
            self._inside = True
            try:
                yield self
            finally:
                self._inside = False

    # -- the pass sequence ---------------------------------------------------------------
    def _sequence(self, scene, camera, opts: RenderOptions, dest: Destination):
        self._settle()
        engine = self._engine(opts.engine)
        scene, state = prepare_frame(scene, camera, opts, dest.window is not None)  # 1
        self._warn(engine.unsupported(opts, scene))  # (what was given, before it decides)
        opts = engine.decided(opts)
        if opts.denoise:
            self._warn(denoise_lines(engine, dest))
        surf = self._surfaces_for(opts.size)
        aa = engine.sampling(opts, scene, state.camera, dest.preview)
        state = engine.prepare(scene, state, opts, aa)  # 2
        aux = dest.channels(opts)
        # Without MSAA or supersampling, colour and the exact channels come from one pass
        # (multiple render targets) where the engine can; otherwise they get their own.
        together = aux if (dest.wants_colour(opts) and aa is None and not opts.aa.msaa
                           and engine.draws_together(scene)) else ()
        channels = self._exact(engine, point_lights_for(scene), state, aux, surf) \
            if aux and not together else {}  # 3
        color, shown = self._colour(engine, scene, state, opts, aa, dest, surf, together) \
            if dest.wants_colour(opts) else (None, 0)  # 4, 5
        if together:
            channels = {name: self._reader(surf, name) for name in aux}
        self.cache.sweep()
        if dest.window is not None:
            return shown
        spp = None
        if "spp" in opts.outputs:
            spp = self._spp.astype(np.int32) if self._spp is not None else \
                np.full((opts.height, opts.width), shown, np.int32)
        frame = Frame(color, channels.get("depth"), channels.get("ids"), state.camera,
                      channels.get("normals"), channels.get("position"), channels.get("uv"),
                      opts.size, spp=spp)
        if frame.unread:
            self._unread = weakref.ref(frame)
        return frame

    # -- resources -----------------------------------------------------------------------
    def user_programs(self) -> UserShaderPrograms | None:
        """Users' mesh shaders' programs, of the engine that keeps them (nothing is made to
        ask: None while no such engine has drawn).

        Returns
        -------
        UserShaderPrograms or None
            Those of the first engine that has any (facet.render.engine.Engine.user_programs).
        """
        kept = (e.user_programs() for e in self._engines.values())
        return next((programs for programs in kept if programs is not None), None)

    def resize(self, width: int, height: int) -> None:
        """A new default size for later calls (a window was resized).

        Parameters
        ----------
        width, height : int
            Pixels.
        """
        self.defaults = ParsedLayer({**self.defaults, **parse_layer({"size": (width, height)})})

    def _check_open(self) -> None:
        if self._closed:
            raise InputError("this Renderer is closed")

    def close(self) -> None:
        """Release every GL object, and the context if this renderer made it. Safe to call
        twice."""
        if self._closed:
            return
        self._settle()
        self._closed = True
        with self.ctx:
            if self._surfaces is not None:
                self._surfaces.release()
            for part in (*self._engines.values(), self._finisher, self.cache):
                if part is not None:
                    part.release()
        if self._own_context:
            self.ctx.release()

    def gl_error(self) -> str:
        """The context's pending GL error.

        Returns
        -------
        str
            ``'GL_NO_ERROR'`` when all is well.
        """
        with self.current():
            return self.ctx.error

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

"""``Renderer``: owns a GL context and everything made in it, and runs the one pass sequence.

    with Renderer(640, 480) as r:
        frame = r.render(scene, camera, outputs=("color", "depth", "ids", "normals"))

``render`` (an offscreen target, read back to numpy; facet.render.frame) and ``present`` (a
window's framebuffer) are two destinations of the same sequence, ``_sequence``:

1. prepare: the options (facet.scene.options, resolved once per call), the camera and its
   lens, the lights that shine (the default rig when the scene has none), background and
   environment; the frame's shared state (facet.render.state);
2. shadow maps (facet.render.shadow), once per frame, or per sample for area lights;
3. the exact channels (depth, ids, normals, position, uv) at pixel centres: with the
   colour in one pass, or (MSAA, supersampling) in a pass of their own, drawn when
   first read (facet.render.frame says why);
4. colour: one picture (MSAA when asked: opaque objects with their mirrors and environment,
   the wireframe overlay, then transparent ones by OIT over the resolved colour), or the
   sum of supersamples carrying the distributed effects (facet.render.antialias): all of
   them offscreen, one more per call in a window, so a still view refines;
5. finishing (facet.render.finish): mean, straight alpha, sRGB, into the destination.

A call changes nothing the next one sees: targets are kept per size, sample count and
format, programs per variant, meshes per Mesh; options are never stored.
"""

from __future__ import annotations

import copy
import threading
import weakref
from dataclasses import replace

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..geometry.lens import with_lens
from ..geometry.sampling import pattern
from ..gl import context as glcontext
from ..gl.resources import ResourceCache
from ..gl.targets import clear_frame, writing
from ..scene.light import active_lights
from ..scene.options import (
    ParsedLayer,
    RenderOptions,
    clamp_msaa,
    options_for,
    parse_layer,
)
from ..scene.scene import Scene
from .antialias import (
    colour_sampling,
    distributed_sample,
    gloss_jitter,
    has_area_lights,
    jitter_matrix,
    point_lights_for,
)
from .destination import Destination, Surfaces
from .finish import Finisher, finish_for
from .forward import ForwardPass
from .frame import Frame
from .overlay import wireframe_overlay
from .shadow import ShadowMaps
from .state import FrameState
from .transparency import split_transparent

LIGHT_ORDER = ("DirectionalLight", "PointLight", "SpotLight", "AreaLight")


def frozen(scene: Scene) -> Scene:
    """A view of ``scene`` whose objects are copies with their own transforms and materials
    (what a deferred pass draws, whatever the caller changes afterwards)."""
    return scene.view(objects=[
        replace(o, transform=np.array(o.transform, dtype=np.float64),
                material=copy.copy(o.material)) for o in scene.objects])


class Renderer:
    """Renders scenes headlessly (``render``) or into a window (``present``).

    ``Renderer(width, height, msaa, **options)``: the options this renderer gives every call
    (facet.scene.options; e.g. ``shading="blinn"``, ``srgb=True``, ``float_color=True``),
    above a scene's own and below each call's keywords. ``context``: a window's GL context
    (used, not owned); otherwise a headless one is made (``device``: the EGL device index;
    ``backend``: auto / egl / osmesa, facet.gl.context). ``close()`` (or leaving a ``with``
    block) releases the context and every GL object.
    """

    def __init__(self, width: int | None = None, height: int | None = None,
                 msaa: int | None = None, *, context=None, device: int | None = None,
                 backend: str | None = None, **options):
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
        self.forward = ForwardPass(self.ctx, self.cache)
        self._parts: dict = {}  # shadow atlas, finishing pass, ray tracer: made on first use
        self._surfaces: Surfaces | None = None
        self._closed = False
        self._unread = None  # the last Frame with channels still on the GPU (weakly)
        self._inside = False  # the context is current (render, present): read directly
        with self.ctx:
            # What the MSAA policy needs to know (facet.scene.options.clamp_msaa).
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
        """The options a call with these arguments renders with: a ``RenderOptions``
        passed in is used as it is (a front resolved it), with ``kwargs`` on top; otherwise
        (facet.scene.options.options_for) the ``front``'s defaults < the scene's < this
        renderer's < ``options`` (a mapping) < ``kwargs``."""
        if isinstance(options, RenderOptions):
            opts = options.merged(kwargs)
        else:
            opts = options_for(scene, self.defaults, options, kwargs, front=front)
        aa = clamp_msaa(opts.aa, *self._limits)
        return opts if aa is opts.aa else replace(opts, aa=aa)

    def camera(self, scene: Scene, opts: RenderOptions) -> Camera:
        """The scene's camera the options name (else its first), else one framing it."""
        return scene.camera(opts.camera) or Camera.frame(scene.bounds, up=opts.up,
                                                         aspect=opts.width / opts.height)

    def render(self, scene: Scene, camera: Camera | None = None, options=None,
               **kwargs) -> Frame:
        """Render ``scene`` through ``camera`` (default: ``camera(scene, options)``) into
        numpy arrays. Keywords are render options (facet.scene.options.RenderOptions:
        ``outputs``, ``aa``, ``msaa``, ``shadows``, ``shading``, ``srgb``, ...)."""
        self._check_open()
        opts = self.options(scene, options, **kwargs)
        with self.ctx:  # several renderers (contexts) may live in one thread
            self._inside = True
            try:
                return self._sequence(scene, camera or self.camera(scene, opts), opts,
                                      Destination())
            finally:
                self._inside = False

    def present(self, scene: Scene, camera: Camera, framebuffer, options=None, *,
                sample: int | None = None, **kwargs) -> int:
        """Draw into a window's ``framebuffer`` (bottom-up, like GL) with the sequence of
        ``render``; call it with the window's context current (re-entering a current EGL
        context here would drop what was drawn). ``sample`` None: one picture, what a
        moving camera shows (no supersampling: lens, shutter and area lights at their
        centres). ``sample`` k: add supersample k (0 starts over) and show the mean so far;
        after the last the picture equals ``render``'s. Returns the samples shown."""
        self._check_open()
        opts = self.options(scene, options, **kwargs)
        self._inside = True
        try:
            return self._sequence(scene, camera, opts, Destination(framebuffer, sample))
        finally:
            self._inside = False

    def samples(self, scene: Scene, camera: Camera, options=None, **kwargs) -> int:
        """How many supersamples the colour of this render sums (0: one picture)."""
        opts = self.options(scene, options, **kwargs)
        aa = colour_sampling(opts, scene, with_lens(camera, opts.aperture, opts.focus))
        return aa.samples if aa is not None else 0

    # -- the pass sequence ---------------------------------------------------------------
    def _sequence(self, scene, camera, opts: RenderOptions, dest: Destination):
        self._settle()
        scene, state = self._prepare(scene, camera, opts, dest)  # 1
        surf = self._surfaces_for(opts.size)
        trace = opts.engine == "trace"
        aa = colour_sampling(opts, scene, state.camera, dest.preview)
        centre = point_lights_for(scene)  # an area light without supersamples: its centre
        if trace:  # the tracer casts shadow rays: its geometry instead of shadow maps
            self._part("tracer").prepare(scene, state)
        elif opts.shadows_on and not (aa is not None and has_area_lights(scene)):  # 2
            state = state.with_(shadows=self._part("shadows").draw(centre, opts.pcf))
        aux = dest.channels(opts)
        # Without MSAA, supersampling or users' shaders, colour and the exact channels come
        # from one pass (multiple render targets); otherwise the exact ones get their own.
        users = any(o.material.shader is not None for o in scene.objects)
        together = aux if (dest.wants_colour(opts) and aa is None and not opts.aa.msaa
                           and not users) else ()
        channels = self._exact(centre, state, aux, surf, trace) \
            if aux and not together else {}  # 3
        color, shown = self._colour(scene, state, opts, aa, dest, surf, together) \
            if dest.wants_colour(opts) else (None, 0)  # 4, 5
        if together:
            channels = {name: self._reader(surf, name) for name in aux}
        self.cache.sweep()
        if dest.window is not None:
            return shown
        frame = Frame(color, channels.get("depth"), channels.get("ids"), state.camera,
                      channels.get("normals"), channels.get("position"), channels.get("uv"),
                      opts.size)
        if frame.unread:
            self._unread = weakref.ref(frame)
        return frame

    def _reader(self, surf, name: str, draw=None):
        """Read channel ``name`` when the frame's user first asks for it (facet.render.frame:
        a caller that only wants colour moves nothing else), with this renderer's context
        current; ``draw``: the deferred pass that fills it (``_exact``), run first."""
        owner = threading.get_ident()

        def read():
            if threading.get_ident() != owner:  # a GL context belongs to one thread
                raise InputError(f"a frame's {name} is read back from the GPU in the thread "
                                 "that rendered it: call frame.settle() there before "
                                 "handing the frame to another thread or process")
            if self._inside:  # never enter a current context again (facet.gl.context)
                return self._read_aux(surf, name, draw)
            with self.ctx:
                return self._read_aux(surf, name, draw)
        return read

    @staticmethod
    def _read_aux(surf, name: str, draw):
        if draw is not None:
            draw()
        return surf.targets.read_aux(name)

    def _settle(self) -> None:
        """Read what the last frame has not read yet, if someone still holds it, before
        its targets are drawn over."""
        frame = self._unread() if self._unread is not None else None
        self._unread = None
        if frame is not None:
            frame.settle()

    def _prepare(self, scene, camera, opts: RenderOptions, dest: Destination):
        """The scene as this render sees it, and the frame's state (step 1)."""
        camera = with_lens(camera, opts.aperture, opts.focus)
        # Lights in a canonical order (by kind; the sum does not care): programs are
        # specialised on the kinds, so scenes that differ only in light order share one.
        lights = sorted(active_lights(scene.lights, camera.view, opts.lights),
                        key=lambda light: LIGHT_ORDER.index(type(light).__name__))
        view = scene.view(lights=lights)
        # options_for put the scene's own background and environment under the explicit
        # ones; None (a RenderOptions built without a scene) means the scene's.
        background = np.array(scene.background if opts.background is None else opts.background,
                              dtype=np.float64)
        if dest.window is not None:
            background[3] = 1.0  # a window shows colour only
        view.background = background
        if opts.environment is not None:
            view.environment = opts.environment
        state = FrameState(camera, opts.width, opts.height, dest.flip_y, opts.shading,
                           opts.srgb, tuple(point_lights_for(view).lights), view.ambient,
                           view.environment, time=opts.time, cull=opts.cull)
        return view, state

    def _colour(self, scene, state, opts, aa, dest, surf, together):
        """Steps 4 and 5: (colour read back or None, samples shown)."""
        alpha = float(scene.background[3])
        bg = np.array([*state.to_linear(scene.background[:3]).tolist(), alpha])
        clear = (*(bg[:3] * alpha).tolist(), alpha)  # premultiplied (finishing undoes it)
        if aa is None:
            finish = finish_for(bg, opts.srgb)
            dtype = "f4" if finish.needed or opts.float_color else "f1"
            fbo = self._picture(scene, state, opts, clear, surf, dtype, together,
                                None if finish.needed else dest.window)
            source = surf.targets.color_texture(dtype)
            return self._finish(source, fbo, finish, opts, dest, surf), 1
        samples = dest.samples(aa.samples)
        source = self._accumulate(scene, state, opts, aa, samples, bg, surf, dest.preview)
        finish = finish_for(bg, opts.srgb, samples.stop)
        return self._finish(source, None, finish, opts, dest, surf), samples.stop

    def _exact(self, scene, state: FrameState, aux, surf, trace: bool) -> dict:
        """The exact channels at pixel centres, from the opaque objects (step 3), in a
        single-sample pass of their own; read back when used (``_reader``).

        The rasterizer's pass is drawn when a channel is first read, not now: most callers
        of the default outputs look at colour only, and under MSAA this pass costs a second
        trip through every triangle. It draws a snapshot of the objects taken now (their
        transforms and materials copied), so a scene changed after ``render`` returns
        changes nothing; the renderer draws it before its targets are used again
        (``_settle``). The ray tracer's pass is drawn now (its geometry is this frame's)."""
        if trace:
            self._draw_exact(scene, state, aux, surf, trace)
            return {name: self._reader(surf, name) for name in aux}
        opaque = frozen(split_transparent(scene)[0])
        state = state.with_(shading="unlit", shadows=None, environment=None)
        drawn = []

        def draw():
            if not drawn:
                drawn.append(True)
                self._draw_exact(opaque, state, aux, surf, trace)
        return {name: self._reader(surf, name, draw) for name in aux}

    def _draw_exact(self, scene, state: FrameState, aux, surf, trace: bool) -> None:
        fbo = surf.targets.aux(aux)
        fbo.use()
        with writing(fbo, colour=False):  # no colour written (nor cleared) per fragment
            fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)  # the exact channels: "nothing"
            self.ctx.enable_only(self.ctx.DEPTH_TEST)
            if trace:
                self._part("tracer").draw_exact(scene, state, aux)
            else:
                self.forward.draw(split_transparent(scene)[0], state, aux=aux,
                                  colour_pass=False)

    def _picture(self, scene, state, opts, clear, surf, dtype, together, direct):
        """One picture (step 4): opaque objects (straight into the window ``direct`` when
        nothing needs compositing or finishing), the overlay, then transparent ones over the
        resolved colour. Returns the framebuffer holding it."""
        t = surf.targets
        opaque, transparent = split_transparent(scene)
        if opts.aa.msaa:
            target = t.multisample(opts.aa.msaa, dtype)
        elif direct is not None and transparent is None:
            target = direct
            target.viewport = (0, 0, *opts.size)
        else:
            target = t.color(dtype)
        if together:  # the same colour texture, with the exact channels' attachments
            target = t.aux(together, dtype)
        target.use()
        clear_frame(target, clear, exact=bool(together))
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        self.forward.draw(opaque, state, aux=together)
        if opts.wireframe:
            wireframe_overlay(self.forward, scene, state)
        if transparent is None and direct is not None:
            return target  # shown as it is (a multisampled one resolves as it is copied)
        zbuffer = target.depth_attachment if opts.aa.msaa else t.zbuffer
        result = t.resolve(target, dtype) if opts.aa.msaa else t.color(dtype)
        if transparent is not None:
            # Layers tested against the opaque depth (multisampled with MSAA: anti-aliased
            # edges), composited over the resolved opaque colour.
            oit = surf.oit.begin(zbuffer)
            self.forward.draw(transparent, state, oit=True)
            surf.oit.end(oit, result)
        return result

    def _accumulate(self, scene, state, opts, aa, samples: range, bg, surf, plain=False):
        """Add supersamples ``samples`` of ``aa`` (step 4): each with its pixel offset, lens
        point, shutter time, area-light points and gloss tilt (``plain``: the centre of
        each); returns the sum's texture."""
        acc = surf.accumulator
        clear = (*(bg[:3] * bg[3]), bg[3])
        if samples.start == 0:
            acc.clear()
        for k in samples:
            if plain:
                sample, scene_k = state, point_lights_for(scene)
            else:
                cam_k, scene_k = distributed_sample(state.camera, scene, k, aa)
                dx, dy = pattern(aa.pattern, aa.samples)[k]
                sample = state.with_(camera=cam_k, lights=tuple(scene_k.lights),
                                     jitter=jitter_matrix(dx, dy, opts.width, opts.height),
                                     gloss_jitter=gloss_jitter(k, aa.samples))
            trace = opts.engine == "trace"
            if opts.shadows_on and not trace and has_area_lights(scene) and not plain:
                # The maps follow the area lights' points.
                sample = sample.with_(shadows=self._part("shadows").draw(scene_k, opts.pcf, k))
            acc.begin_sample(clear)
            self.ctx.enable_only(self.ctx.DEPTH_TEST)
            if trace:
                self._part("tracer").draw(scene_k, sample, bg, opts.max_depth, opts.shadows_on)
                acc.add_sample()
                continue
            opaque, transparent = split_transparent(scene_k)
            self.forward.draw(opaque, sample)
            if opts.wireframe:
                wireframe_overlay(self.forward, scene_k, sample)
            if transparent is not None:
                oit = surf.oit.begin(acc.sample_depth)
                self.forward.draw(transparent, sample, oit=True)
                surf.oit.end(oit, acc.sample)
            acc.add_sample()
        return acc.accum_tex

    def _finish(self, source, source_fbo, finish, opts, dest, surf):
        """Step 5: finished colour read back (offscreen) or shown (window); a sum of
        samples (no ``source_fbo``) is always finished."""
        t = surf.targets
        out = "f4" if opts.float_color else "f1"
        needed = finish.needed or source_fbo is None
        if dest.window is not None:
            dest.window.viewport = (0, 0, *opts.size)
            if needed:
                self._part("finisher").draw(source, dest.window, finish)
            elif source_fbo is not dest.window:
                self.ctx.copy_framebuffer(dest.window, source_fbo)
            return None
        if not needed:
            return t.read_color(source_fbo, out)
        self._part("finisher").draw(source, t.output(out), finish)
        return t.read_color(t.output(out), out)

    # -- resources -----------------------------------------------------------------------
    def _part(self, name: str):
        """The shadow maps, the finishing pass or the ray tracer, made on first use."""
        if name not in self._parts:
            if name == "tracer":
                from .trace.engine import Tracer  # the tracer's modules load only if used

                self._parts[name] = Tracer(self.ctx, self.cache)
            else:
                self._parts[name] = ShadowMaps(self.ctx, self.cache) if name == "shadows" \
                    else Finisher(self.ctx)
        return self._parts[name]

    def _surfaces_for(self, size) -> Surfaces:
        """The size-dependent targets, made anew when the size changes."""
        if self._surfaces is None or self._surfaces.size != tuple(size):
            new = Surfaces(self.ctx, tuple(size))
            # moderngl re-binds the bound framebuffer after making one: bind a live one
            # before releasing the old (a released one there is GL_INVALID_OPERATION).
            new.targets.color().use()
            if self._surfaces is not None:
                self._surfaces.release()
            self._surfaces = new
        return self._surfaces

    def resize(self, width: int, height: int) -> None:
        """A new default size for later calls (a window was resized)."""
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
            for part in (*self._parts.values(), self.forward, self.cache):
                part.release()
        if self._own_context:
            self.ctx.release()

    def gl_error(self) -> str:
        """The context's pending GL error ('GL_NO_ERROR' when all is well)."""
        with self.ctx:
            return self.ctx.error

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

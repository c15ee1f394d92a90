"""``Renderer`` (owns a GL context and everything made in it) and ``Frame`` (its results).

    with Renderer(640, 480, msaa=4) as r:
        frame = r.render(scene, camera, outputs=("color", "depth", "ids", "normals"))
        frame.color       # (H, W, 4) uint8, row 0 at the top
        frame.depth       # (H, W) float32, linear depth along the camera axis, 0 = no hit
        frame.object_ids  # (H, W) int32, -1 = background
        frame.normals     # (H, W, 3) float32 world-space unit normals, 0 = no hit
        frame.position    # (H, W, 3) float32 world-space positions, 0 = no hit
        frame.uv          # (H, W, 2) float32 texture coordinates, 0 = no hit or no uvs

Only colour is anti-aliased: every other channel comes from a single-sample pass at pixel
centres whatever ``msaa`` is, so values are exact and labels never blend.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.camera import Camera
from ..geometry.sampling import pattern
from ..gl import context as glcontext
from ..gl.resources import ResourceCache
from ..gl.targets import Targets
from ..image.colorspace import linear_to_srgb, srgb_to_linear, unpremultiply
from ..scene.scene import Scene
from .antialias import (
    DISTRIBUTED_AA,
    distributed_sample,
    gloss_jitter,
    has_area_lights,
    jitter_matrix,
    needs_accumulation,
    parse_aa,
    point_lights_for,
)
from .forward import ForwardPass
from .present import WindowPresenter
from .shading import check_shading
from .transparency import split_transparent

OUTPUTS = ("color", "depth", "ids", "normals", "position", "uv")
DEFAULT_OUTPUTS = ("color", "depth", "ids")
# Output name -> the auxiliary render channel that holds it (facet.gl.targets.AUX_CHANNELS).
_CHANNEL = {"depth": "depth", "ids": "ids", "normals": "normals", "position": "position",
            "uv": "uv"}


@dataclass
class Frame:
    """One render's results (see the module docstring); outputs not asked for are None."""

    color: np.ndarray | None
    depth: np.ndarray | None
    object_ids: np.ndarray | None
    camera: Camera
    normals: np.ndarray | None = None
    position: np.ndarray | None = None
    uv: np.ndarray | None = None
    size: tuple[int, int] = (0, 0)  # (width, height)

    def camera_normals(self) -> np.ndarray:
        """Normals in camera space (OpenGL axes: x right, y up, z towards the viewer)."""
        if self.normals is None:
            raise InputError("this frame has no normals; render with outputs=(..., 'normals')")
        return (self.normals @ self.camera.view[:3, :3].T).astype(np.float32)

    def camera_info(self) -> dict:
        """The camera as plain data (see ``Camera.describe``) for this image size."""
        return self.camera.describe(*self.size)

    def save(self, path):
        """Write the colour image (PNG; RGBA if the background is transparent)."""
        from ..image.writers import save_image, to_uint8

        if self.color is None:
            raise InputError("this frame has no colour output to save")
        return save_image(path, to_uint8(self.color))


class Renderer(WindowPresenter):
    """Headless renderer of ``width`` x ``height`` images with optional MSAA (0, 2, 4, 8).

    ``float_color=True`` keeps colour as float32 in [0, 1] (``frame.color`` is float32) for
    16-bit output and dithering; by default it is RGBA8 (uint8). ``srgb=True`` treats input
    colours as sRGB, lights in linear space and returns sRGB-encoded float colour
    (facet.image.colorspace states both modes).

    ``close()`` (or leaving a ``with`` block) releases the context and every GL object.
    """

    def __init__(self, width: int = 800, height: int = 600, msaa: int = 0, *,
                 shading: str = "phong", float_color: bool = False, srgb: bool = False,
                 context=None):
        self.shading = check_shading(shading)
        self.srgb = bool(srgb)
        self.float_color = bool(float_color)
        # A window's context (facet.viewer) is used, not owned; otherwise a headless one.
        self._own_context = context is None
        self.ctx = glcontext.create_headless() if context is None else context
        try:
            # The sRGB mode lights in linear space, which needs more than 8 bits to keep
            # dark tones from banding before the encoding: it always uses a float target.
            self.targets = Targets(self.ctx, width, height, msaa,
                                   color_dtype="f4" if float_color or srgb else "f1")
        except BaseException:
            if self._own_context:
                self.ctx.release()
            raise
        self.width, self.height, self.msaa = width, height, msaa
        self.cache = ResourceCache(self.ctx)
        self.forward = ForwardPass(self.ctx, self.cache)
        self._accumulator = None  # supersampling targets, made on first use
        self._transparency = None  # OIT targets, made on first use
        self._shadow_maps = None  # shadow atlas, made on first use
        self._shadows = None  # this render call's shadow data
        self._shadows_on, self._pcf = False, 1  # what the supersampling render asked for
        self._closed = False

    @property
    def info(self) -> dict[str, object]:
        return glcontext.describe(self.ctx)

    def render(self, scene: Scene, camera: Camera | None = None, *, shading: str | None = None,
               outputs=DEFAULT_OUTPUTS, time: float = 0.0, aa: str | None = None,
               shadows: bool = False, pcf: int = 1) -> Frame:
        """Render ``scene`` through ``camera`` (default: ``Camera.frame`` of the scene).

        ``aa``: ``none``, ``msaa:N`` or ``ssaa:PATTERN:N`` (facet.render.antialias); default
        the renderer's ``msaa``. Supersampled colour comes back as float32 in [0, 1] unless
        the renderer keeps 8-bit colour, in which case it is rounded to uint8. ``shadows``:
        shadow maps for every light (facet.render.shadow), filtered by a PCF kernel of
        radius ``pcf`` texels (0, 1 or 2).
        """
        if self._closed:
            raise InputError("this Renderer is closed")
        unknown = set(outputs) - set(OUTPUTS)
        if unknown:
            raise InputError(f"unknown outputs {sorted(unknown)}; choose from {OUTPUTS}")
        shading = check_shading(shading or self.shading)
        if camera is None:
            camera = Camera.frame(scene.bounds, aspect=self.width / self.height)
        mode = parse_aa(aa) if aa is not None else None
        # Depth of field, motion blur, area lights and gloss ride on supersampling.
        if needs_accumulation(scene, camera, shadows) and (mode is None or mode.kind != "ssaa"):
            mode = parse_aa(DISTRIBUTED_AA)
        if mode is not None and mode.kind != "ssaa":
            wanted = mode.samples if mode.kind == "msaa" else 0
            if wanted != self.msaa:
                self.set_msaa(wanted)
        # Several renderers (contexts) may live in one thread: make ours current.
        with self.ctx:
            if mode is not None and mode.kind == "ssaa":
                self._pcf = pcf
                self._shadows_on = shadows
                return self._supersample(scene, camera, shading, outputs, time, mode)
            scene = point_lights_for(scene)  # an area light without samples: its centre
            self._shadows = self._draw_shadows(scene, pcf) if shadows else None
            return self._render(scene, camera, shading, outputs, time)

    def _draw_shadows(self, scene: Scene, pcf: int = 1, sample: int = 0):
        from .shadow import ShadowMaps

        if self._shadow_maps is None:
            self._shadow_maps = ShadowMaps(self.ctx, self.cache)
        return self._shadow_maps.draw(scene, pcf, sample)

    def _colour_draw(self, scene, camera, shading, **kw) -> None:
        """The colour pass, with the shadow maps of this render call if there are any."""
        self.forward.draw(scene, camera, self.width, self.height, shading,
                          shadows=self._shadows, shadow_maps=self._shadow_maps, **kw)

    def set_msaa(self, samples: int) -> None:
        """Switch the multisample count (new targets; programs and meshes stay)."""
        with self.ctx:
            self._replace_targets(Targets(self.ctx, self.width, self.height, samples,
                                          color_dtype=self.targets.color_dtype))
        self.msaa = samples

    def _replace_targets(self, targets: Targets) -> None:
        """Swap in new targets and release the old ones. The new ones are bound first:
        moderngl re-binds the previously bound framebuffer after making any framebuffer,
        and a released one there fails with GL_INVALID_OPERATION."""
        targets.color_only.use()
        if self._transparency is not None:
            self._transparency.forget_depth_buffers()  # they use the old depth buffer
        self.targets.release()
        self.targets = targets

    def _supersample(self, scene, camera, shading, outputs, time, mode) -> Frame:
        """Colour averaged over the pattern's sub-pixel offsets; other channels exact."""
        from .antialias import Accumulator

        w, h = self.width, self.height
        others = tuple(o for o in outputs if o != "color")
        centre = point_lights_for(scene)
        self._shadows = self._draw_shadows(centre, self._pcf) if self._shadows_on else None
        frame = self._render(centre, camera, shading, others, time) if others else \
            Frame(None, None, None, camera, size=(w, h))
        if "color" not in outputs:
            return frame
        if self._accumulator is None:
            self._accumulator = Accumulator(self.ctx, w, h)
        acc = self._accumulator
        bg = self._background(scene)
        acc.accum.use()
        acc.accum.clear(0.0, 0.0, 0.0, 0.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        for k in range(mode.samples):
            self._draw_sample(scene, camera, shading, mode, k, bg, time)
        color = self._finish_color(acc.result(mode.samples), scene)
        if not (self.float_color or self.srgb):
            color = np.rint(np.clip(color, 0, 1) * 255).astype(np.uint8)
        frame.color = color
        return frame

    def _draw_sample(self, scene, camera, shading, mode, k, background, time,
                     flip_y: bool = True) -> None:
        """Add sample ``k`` of ``mode`` to the accumulator: the pattern's sub-pixel offset,
        the lens point, shutter time and area-light points of that sample (facet.render.
        antialias.distributed_sample), opaque objects then transparent ones (OIT)."""
        acc = self._accumulator
        acc.begin_sample(background)
        cam_k, scene_k = distributed_sample(camera, scene, k, mode)
        if self._shadows_on and has_area_lights(scene):
            # Shadow maps are drawn once per render, except that area lights move their
            # point lights every sample.
            self._shadows = self._draw_shadows(scene_k, self._pcf, k)
            acc.begin_sample(background)  # the maps bound their own framebuffer
        dx, dy = pattern(mode.pattern, mode.samples)[k]
        jitter = jitter_matrix(dx, dy, self.width, self.height)
        opaque, transparent = split_transparent(scene_k)
        self._colour_draw(opaque, cam_k, shading, srgb=self.srgb, time=time, jitter=jitter,
                          gloss_jitter=gloss_jitter(k, mode.samples), flip_y=flip_y)
        if transparent is not None:
            oit = self._oit().begin(acc.sample_depth)
            self._colour_draw(transparent, cam_k, shading, srgb=self.srgb, time=time,
                              jitter=jitter, oit=True, flip_y=flip_y)
            self._transparency.end(oit, acc.sample)
        acc.add_sample()

    def _oit(self):
        """The order-independent transparency targets, made on first use."""
        from .transparency import Transparency

        if self._transparency is None:
            self._transparency = Transparency(self.ctx, self.width, self.height)
        return self._transparency

    def _background(self, scene, window: bool = False) -> tuple[float, ...]:
        """The clear colour: the scene's background, linear when colour-managed, and
        premultiplied by its alpha (see ``_finish_color``); opaque in a ``window``, which
        shows colour only."""
        bg = np.asarray(scene.background, dtype=np.float64)
        bg = np.append(bg[:3], 1.0 if window or bg.size == 3 else bg[3])
        if self.srgb:
            bg = np.append(srgb_to_linear(bg[:3]), bg[3])
        bg[:3] *= bg[3]
        return tuple(float(c) for c in bg)

    def _finish_color(self, color: np.ndarray, scene) -> np.ndarray:
        """Read-back colour as returned: straight alpha when the background is not opaque
        (drawn premultiplied, so edges and layers average right), sRGB-encoded when
        colour-managed."""
        if len(scene.background) == 4 and scene.background[3] < 1.0:
            # Empty pixels keep the background's colour (for anyone who drops alpha).
            bg = np.asarray(scene.background[:3], dtype=np.float64)
            unpremultiply(color, srgb_to_linear(bg) if self.srgb else bg)
        if self.srgb:
            color[..., :3] = linear_to_srgb(color[..., :3])
        return color

    def _render(self, scene: Scene, camera: Camera, shading: str, outputs,
                time: float = 0.0) -> Frame:
        opaque, transparent = split_transparent(scene)
        if transparent is None:
            return self._render_opaque(scene, camera, shading, outputs, time)
        frame = self._render_opaque(opaque, camera, shading,
                                    tuple(o for o in outputs if o != "color"), time,
                                    keep_color="color" in outputs)
        if "color" in outputs:
            t = self.targets
            # Layers tested against the opaque depth: multisampled with MSAA (anti-aliased
            # transparent edges), composited over the resolved opaque colour.
            zbuffer = t.ms_z if self.msaa else t.zbuffer
            self._transparent_pass(transparent, camera, shading, zbuffer, t.color_only, time)
            frame.color = self._finish_color(t.read_color(), scene)
        return frame

    def _transparent_pass(self, transparent, camera, shading, zbuffer, target, time):
        oit = self._oit().begin(zbuffer)
        self._colour_draw(transparent, camera, shading, srgb=self.srgb, time=time, oit=True)
        self._transparency.end(oit, target)

    def _render_opaque(self, scene: Scene, camera: Camera, shading: str, outputs,
                       time: float = 0.0, keep_color: bool = False) -> Frame:
        w, h, t = self.width, self.height, self.targets
        aux = tuple(_CHANNEL[o] for o in OUTPUTS if o in outputs and o in _CHANNEL)
        outputs = (*outputs, "color") if keep_color and "color" not in outputs else outputs
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        bg = self._background(scene)
        srgb = self.srgb
        user_shaders = any(o.material.shader is not None for o in scene.objects)
        if aux and (self.msaa or user_shaders):
            # Exact, unblended channels at pixel centres from the built-in shader, then the
            # colour on its own (multisampled, or through the users' shaders).
            t.begin_aux(aux, bg)
            self.forward.draw(scene, camera, w, h, "unlit", aux=aux, srgb=srgb,
                              colour_pass=False)
            aux_done = True
        else:
            aux_done = False
        if self.msaa:
            t.begin_multisample(bg)
            self._colour_draw(scene, camera, shading, srgb=srgb, time=time)
            t.resolve()
        elif aux_done or not aux:
            t.begin_color(bg)
            self._colour_draw(scene, camera, shading, srgb=srgb, time=time)
        else:
            t.begin_aux(aux, bg)
            self._colour_draw(scene, camera, shading, aux=aux, srgb=srgb)
        read = {name: t.read_aux(name) for name in aux}
        for name in ("normals", "position"):  # stored as RGBA32F: drop w
            if name in read:
                read[name] = np.ascontiguousarray(read[name][..., :3])
        color = self._finish_color(t.read_color(), scene) if "color" in outputs else None
        frame = Frame(color, read.get("depth"),
                      read.get("ids"), camera, read.get("normals"), read.get("position"),
                      read.get("uv"), (w, h))
        self.cache.sweep()
        return frame

    def resize(self, width: int, height: int) -> None:
        """New target size (a window was resized); programs and meshes stay."""
        if (width, height) == (self.width, self.height):
            return
        with self.ctx:
            if self._accumulator is not None:
                self._accumulator.release()
                self._accumulator = None
            if self._transparency is not None:
                self._transparency.release()
                self._transparency = None
            self._replace_targets(Targets(self.ctx, width, height, self.msaa,
                                          color_dtype=self.targets.color_dtype))
        self.width, self.height = width, height

    def close(self) -> None:
        """Release every GL object, and the context if this renderer made it. Safe to call
        twice."""
        if self._closed:
            return
        self._closed = True
        with self.ctx:
            if self._accumulator is not None:
                self._accumulator.release()
            if self._shadow_maps is not None:
                self._shadow_maps.release()
            if self._transparency is not None:
                self._transparency.release()
            self.forward.release()
            self.cache.release()
            self.targets.release()
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

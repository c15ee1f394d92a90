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
from ..geometry.lens import check_lens
from ..geometry.sampling import pattern
from ..gl import context as glcontext
from ..gl.resources import ResourceCache
from ..gl.targets import Targets
from ..image.colorspace import linear_to_srgb, srgb_to_linear
from ..scene.scene import Scene
from .antialias import distributed_sample, gloss_jitter, has_area_lights, parse_aa, point_lights_for
from .forward import ForwardPass
from .shading import check_shading

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


class Renderer:
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
        # Depth of field and motion blur are sums over samples too: they ride on
        # supersampling (16 jittered samples unless aa asks for another pattern or count).
        distributed = check_lens(camera) or any(o.transform_end is not None
                                                for o in scene.objects) or (
            shadows and has_area_lights(scene)) or (
            scene.environment is not None and any(o.material.gloss > 0 and
                                                  o.material.reflectivity > 0
                                                  for o in scene.objects))
        if distributed and (mode is None or mode.kind != "ssaa"):
            mode = parse_aa("ssaa:jittered:16")
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

    def _draw_shadows(self, scene: Scene, pcf: int = 1):
        from .shadow import ShadowMaps

        if self._shadow_maps is None:
            self._shadow_maps = ShadowMaps(self.ctx, self.cache)
        return self._shadow_maps.draw(scene, pcf)

    def _colour_draw(self, scene, camera, shading, **kw) -> None:
        """The colour pass, with the shadow maps of this render call if there are any."""
        self.forward.draw(scene, camera, self.width, self.height, shading,
                          shadows=self._shadows, shadow_maps=self._shadow_maps, **kw)

    def set_msaa(self, samples: int) -> None:
        """Switch the multisample count (new targets; programs and meshes stay)."""
        with self.ctx:
            targets = Targets(self.ctx, self.width, self.height, samples,
                              color_dtype=self.targets.color_dtype)
            self.targets.release()
        self.targets, self.msaa = targets, samples

    def _supersample(self, scene, camera, shading, outputs, time, mode) -> Frame:
        """Colour averaged over the pattern's sub-pixel offsets; other channels exact."""
        from .antialias import Accumulator, jitter_matrix

        w, h = self.width, self.height
        others = tuple(o for o in outputs if o != "color")
        centre = point_lights_for(scene)
        # Shadow maps once per render, unless area lights move their point lights per sample.
        per_sample_shadows = self._shadows_on and has_area_lights(scene)
        self._shadows = self._draw_shadows(centre, self._pcf) if self._shadows_on else None
        frame = self._render(centre, camera, shading, others, time) if others else \
            Frame(None, None, None, camera, size=(w, h))
        if "color" not in outputs:
            return frame
        if self._accumulator is None:
            self._accumulator = Accumulator(self.ctx, w, h)
        acc = self._accumulator
        bg = np.asarray(scene.background, dtype=np.float64)
        if self.srgb:
            bg = np.append(srgb_to_linear(bg[:3]), bg[3])
        acc.accum.use()
        acc.accum.clear(0.0, 0.0, 0.0, 0.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        for k, (dx, dy) in enumerate(pattern(mode.pattern, mode.samples)):
            acc.begin_sample(tuple(float(c) for c in bg))
            cam_k, scene_k = distributed_sample(camera, scene, k, mode)
            if per_sample_shadows:
                self._shadows = self._draw_shadows(scene_k, self._pcf)
                acc.begin_sample(tuple(float(c) for c in bg))  # the maps bound their own fbo
            opaque, transparent = split_transparent(scene_k)
            jitter = jitter_matrix(dx, dy, w, h)
            self._colour_draw(opaque, cam_k, shading, srgb=self.srgb, time=time, jitter=jitter,
                              gloss_jitter=gloss_jitter(k, mode.samples))
            if transparent is not None:
                from .transparency import Transparency

                if self._transparency is None:
                    self._transparency = Transparency(self.ctx, w, h)
                oit = self._transparency.begin(acc.sample_depth)
                self._colour_draw(transparent, cam_k, shading, srgb=self.srgb, time=time,
                                  jitter=jitter, oit=True)
                self._transparency.end(oit, acc.sample)
            acc.add_sample()
        color = acc.result(mode.samples)
        if self.srgb:
            color[..., :3] = linear_to_srgb(color[..., :3])
        if not (self.float_color or self.srgb):
            color = np.rint(np.clip(color, 0, 1) * 255).astype(np.uint8)
        frame.color = color
        return frame

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
            if self.msaa:  # the opaque depth, single-sampled, for the transparent pass
                t.depth_only.use()
                t.depth_only.clear(depth=1.0)
                self.forward.draw(opaque, camera, self.width, self.height, "unlit",
                                  colour_pass=False)
            self._transparent_pass(transparent, camera, shading, t.zbuffer, t.color_only,
                                   time)
            frame.color = t.read_color()
            if self.srgb:
                frame.color[..., :3] = linear_to_srgb(frame.color[..., :3])
        return frame

    def _transparent_pass(self, transparent, camera, shading, zbuffer, target, time):
        from .transparency import Transparency

        if self._transparency is None:
            self._transparency = Transparency(self.ctx, self.width, self.height)
        oit = self._transparency.begin(zbuffer)
        self._colour_draw(transparent, camera, shading, srgb=self.srgb, time=time, oit=True)
        self._transparency.end(oit, target)

    def _render_opaque(self, scene: Scene, camera: Camera, shading: str, outputs,
                       time: float = 0.0, keep_color: bool = False) -> Frame:
        w, h, t = self.width, self.height, self.targets
        aux = tuple(_CHANNEL[o] for o in OUTPUTS if o in outputs and o in _CHANNEL)
        outputs = (*outputs, "color") if keep_color and "color" not in outputs else outputs
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        bg = np.asarray(scene.background, dtype=np.float64)
        if self.srgb:
            bg = np.append(srgb_to_linear(bg[:3]), bg[3])
        bg = tuple(float(c) for c in bg)
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
        color = t.read_color() if "color" in outputs else None
        if color is not None and self.srgb:
            color[..., :3] = linear_to_srgb(color[..., :3])
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
            targets = Targets(self.ctx, width, height, self.msaa,
                              color_dtype=self.targets.color_dtype)
            self.targets.release()
        self.targets, self.width, self.height = targets, width, height

    def present(self, scene: Scene, camera: Camera, framebuffer, *, shading: str | None = None,
                wireframe: bool = False, time: float = 0.0, shadows: bool = False) -> None:
        """Draw ``scene`` into ``framebuffer`` (a window's, bottom-up like GL) with the same
        pass and shaders as ``render``; MSAA draws into the multisampled target and resolves
        into the window. ``wireframe`` overlays the triangle edges."""
        shading = check_shading(shading or self.shading)
        w, h, t = self.width, self.height, self.targets
        scene = point_lights_for(scene)
        self._shadows = self._draw_shadows(scene) if shadows else None  # own framebuffer
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        bg = tuple(float(c) for c in scene.background)
        target = t.begin_multisample(bg) if self.msaa else framebuffer
        if not self.msaa:
            framebuffer.use()
            framebuffer.clear(*bg, depth=1.0)
        self._colour_draw(scene, camera, shading, flip_y=False, time=time)
        if wireframe:
            self.ctx.depth_func = "<="
            self.ctx.wireframe = True
            self.forward.draw(_edges(scene), camera, w, h, "unlit", flip_y=False)
            self.ctx.wireframe = False
            self.ctx.depth_func = "<"
        if self.msaa:
            self.ctx.copy_framebuffer(framebuffer, target)
        self.cache.sweep()

    def present_progressive(self, scene: Scene, camera: Camera, framebuffer, aa: str,
                            index: int, *, shading: str | None = None,
                            time: float = 0.0, shadows: bool = False) -> int:
        """Supersampling in a window, one sample per call: add sample ``index`` of ``aa``'s
        pattern (0 starts over) and show the mean so far. Returns the samples shown; after
        the last one the picture equals the headless ``render(aa=...)``."""
        from .antialias import Accumulator, jitter_matrix

        mode = parse_aa(aa)
        if mode.kind != "ssaa":
            raise InputError(f"progressive rendering needs ssaa, got {aa!r}")
        scene = point_lights_for(scene)
        shading = check_shading(shading or self.shading)
        w, h = self.width, self.height
        if self._accumulator is None:
            self._accumulator = Accumulator(self.ctx, w, h)
        acc = self._accumulator
        index = min(index, mode.samples - 1)
        if index == 0:
            self._shadows = self._draw_shadows(scene) if shadows else None
        if index == 0:
            acc.accum.use()
            acc.accum.clear(0.0, 0.0, 0.0, 0.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        dx, dy = pattern(mode.pattern, mode.samples)[index]
        acc.begin_sample(tuple(float(c) for c in scene.background))
        # Upright (no flip): the window shows the accumulation as it is.
        self._colour_draw(scene, camera, shading, flip_y=False, time=time,
                          jitter=jitter_matrix(dx, dy, w, h))
        acc.add_sample()
        acc.show(framebuffer, index + 1)
        self.cache.sweep()
        return index + 1

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


EDGE_COLOR = (0.05, 0.05, 0.05)


def _edges(scene: Scene) -> Scene:
    """The same objects with a dark unlit material, for the wireframe overlay (no GL made)."""
    from ..scene.material import Material
    from ..scene.scene import SceneObject

    edges = Scene(background=scene.background)
    material = Material(color=EDGE_COLOR)
    edges.objects = [SceneObject(o.id, o.mesh, material, o.transform, o.name)
                     for o in scene.objects]
    return edges


def split_transparent(scene: Scene):
    """(opaque scene, transparent scene or None): views of ``scene`` by material opacity."""
    if all(o.material.opacity >= 1.0 for o in scene.objects):
        return scene, None
    return (scene.view(objects=[o for o in scene.objects if o.material.opacity >= 1.0]),
            scene.view(objects=[o for o in scene.objects if o.material.opacity < 1.0]))

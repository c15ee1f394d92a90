"""The forward Phong pass: one draw per scene object into the current target.

Shading models map to programs through ``facet.render.shading.SHADING_MODELS``;
programs are compiled on first use and reused. Per frame the pass writes the camera and
light uniforms (lights through one std140 uniform block, re-uploaded only when they change)
and per object its matrices and material.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..geometry import transforms as T
from ..geometry.camera import Camera
from ..gl.glsl_source import glsl_root
from ..gl.resources import ResourceCache
from ..gl.shaders import Program, compile_program
from ..gl.targets import FLIP_Y, aux_locations
from ..image.colorspace import srgb_to_linear
from ..scene.light import DirectionalLight, PointLight, SpotLight
from ..scene.scene import MAX_LIGHTS, Scene
from .mirror import MIRROR_UNIT, MirrorTargets, mirror_plane
from .shading import SHADING_MODELS, check_shading
from .user_shaders import UserPrograms

LIGHT_KIND = {DirectionalLight: 0, PointLight: 1, SpotLight: 2}  # LIGHT_* in lighting.glsl
LIGHTS_BINDING = 0
ENV_UNIT = 2  # texture unit of the environment cube (0: material texture, 1: shadow atlas)


def pack_lights(scene: Scene, to_linear=np.asarray) -> bytes:
    """The std140 ``Lights`` block of glsl/lib/lights.glsl: ambient, count, 4 vec4 per light."""
    block = np.zeros(2 * 4 + MAX_LIGHTS * 16, dtype=np.float32)
    block[0:3] = to_linear(scene.ambient)
    block[4:8] = np.array([len(scene.lights), 0, 0, 0], dtype=np.int32).view(np.float32)
    for i, light in enumerate(scene.lights):
        pos, direction, color, falloff = block[8 + 16 * i: 24 + 16 * i].reshape(4, 4)
        pos[3] = LIGHT_KIND[type(light)]
        color[:3] = to_linear(light.color) * light.intensity
        if hasattr(light, "position"):
            pos[:3] = light.position
            falloff[:3] = light.attenuation
        if hasattr(light, "direction"):
            direction[:3] = light.direction
        if isinstance(light, SpotLight):
            direction[3] = np.cos(np.radians(light.inner_angle))
            color[3] = np.cos(np.radians(light.outer_angle))
    return block.tobytes()


@dataclass(frozen=True)
class Variant:
    """Everything a program is specialised on (each becomes a define in glsl/mesh)."""

    shading: str
    light_kinds: tuple[int, ...] = ()  # LIGHT_* of each light, in order
    aux: tuple[str, ...] = ()  # auxiliary outputs (facet.gl.targets)
    orthographic: bool = False  # the view direction is a constant
    texture: bool = False
    vertex_colors: bool = False
    srgb: bool = False  # vertex colours are sRGB-encoded
    shadow_slots: tuple[int, ...] | None = None  # per light: its first shadow tile, or -1
    shadow_tiles: int = 0  # tiles in the shadow atlas
    shadow_pcf: int = 1  # PCF kernel radius in texels
    oit: bool = False  # the transparent pass (outputs to the OIT sums, facet.render.transparency)
    environment: bool = False  # reflects / refracts the scene's environment
    mirror: bool = False  # mixes in its planar reflection (facet.render.mirror)
    clip_plane: bool = False  # discards what is behind a mirror (its reflection pass)

    def defines(self) -> dict:
        spec = SHADING_MODELS[check_shading(self.shading)]
        d = {spec.define: None, "MAX_LIGHTS": MAX_LIGHTS, "LIGHT_COUNT": len(self.light_kinds)}
        if self.light_kinds:
            kinds = ", ".join(map(str, self.light_kinds))
            d["LIGHT_KIND_LIST"] = f"int[{len(self.light_kinds)}]({kinds})"
        for name, location in aux_locations(self.aux).items():
            d[f"OUT_{name.upper()}"] = location
        if self.shadow_slots is not None and self.light_kinds:
            d["SHADOWS"] = None
            slots = ", ".join(map(str, self.shadow_slots))
            d["LIGHT_SHADOW_LIST"] = f"int[{len(self.shadow_slots)}]({slots})"
            d["SHADOW_TILES"] = max(self.shadow_tiles, 1)
            d["SHADOW_PCF"] = self.shadow_pcf
        flags = {"VIEW_ORTHOGRAPHIC": self.orthographic, "HAS_TEXTURE": self.texture,
                 "HAS_VERTEX_COLORS": self.vertex_colors, "COLOR_SRGB": self.srgb,
                 "OIT": self.oit, "HAS_ENVIRONMENT": self.environment,
                 "HAS_MIRROR": self.mirror, "CLIP_PLANE": self.clip_plane}
        d.update({k: None for k, on in flags.items() if on})
        return d


class ForwardPass:
    """Draws a scene with one of the shading models; owns its programs and light buffer."""

    def __init__(self, ctx, cache: ResourceCache):
        self.ctx = ctx
        self.cache = cache
        self.programs: dict[Variant, Program] = {}
        self.user = UserPrograms(ctx, cache.forget_program)
        self._sky = None  # the environment background program, made on first use
        self.mirrors = MirrorTargets(ctx)  # planar reflection textures, made on first use
        self.lights_ubo = ctx.buffer(reserve=len(pack_lights(Scene())))
        self._lights_bytes = b""

    def program(self, variant: Variant) -> Program:
        """The compiled program for ``variant`` (compiled on first use, then reused)."""
        if variant not in self.programs:
            spec = SHADING_MODELS[check_shading(variant.shading)]
            root = glsl_root()
            prog = compile_program(self.ctx, root / spec.vertex, root / spec.fragment,
                                   variant.defines())
            if "Lights" in prog.gl:
                prog.gl["Lights"].binding = LIGHTS_BINDING
            self.programs[variant] = prog
        return self.programs[variant]

    def draw(self, scene: Scene, camera: Camera, width: int, height: int, shading: str,
             aux: tuple[str, ...] = (), flip_y: bool = True, srgb: bool = False,
             time: float = 0.0, jitter=None, shadows: dict | None = None,
             shadow_maps=None, oit: bool = False, colour_pass: bool = True,
             gloss_jitter=(0.0, 0.0), clip_plane=None) -> None:
        """Draw every object of ``scene`` into the bound framebuffer, which holds the ``aux``
        channels too. ``flip_y``: draw upside down for top-down readback. ``srgb``: inputs
        are sRGB-encoded and are linearised (facet.image.colorspace). Materials with their
        own shader use it for colour (``aux`` passes always use the built-in one); ``time``
        is their ``u_time``. ``jitter``: a clip-space shift (supersampling, antialias.py).
        ``shadows``: what ``ShadowMaps.draw`` returned (``shadow_maps``) for this scene.
        ``colour_pass``: False for passes that only fill depth or the exact channels (no
        background, no environment lookups, no mirrors). ``clip_plane``: world-space (n, d)
        of the mirror this pass draws the reflection for (facet.render.mirror)."""
        if colour_pass and not oit and clip_plane is None:
            reflections = self._draw_reflections(
                scene, camera, width, height, shading, flip_y=flip_y, srgb=srgb, time=time,
                jitter=jitter, shadows=shadows, shadow_maps=shadow_maps,
                gloss_jitter=gloss_jitter)
        else:
            reflections = {}
        to_linear = srgb_to_linear if srgb else np.asarray
        lights = pack_lights(scene, to_linear)
        if lights != self._lights_bytes:
            self.lights_ubo.write(lights)
            self._lights_bytes = lights
        self.lights_ubo.bind_to_uniform_block(LIGHTS_BINDING)
        projection = camera.projection(width, height)
        if jitter is not None:
            projection = jitter @ projection
        view_projection = (FLIP_Y @ projection if flip_y else projection) @ camera.view
        # Flipping y mirrors the image, so counter-clockwise front faces turn clockwise; so
        # does looking through a mirror.
        self.ctx.front_face = "cw" if flip_y != (clip_plane is not None) else "ccw"
        # Perspective: V = normalize(eye - p). Parallel projection: V is the same everywhere.
        eye = tuple(float(v) for v in (-camera.forward if camera.is_orthographic
                                       else camera.eye))
        env = scene.environment
        if env is not None and colour_pass and not oit:
            self._draw_sky(env, view_projection, width, height)
        base = Variant(shading, tuple(LIGHT_KIND[type(x)] for x in scene.lights),
                       tuple(aux_locations(aux)), camera.is_orthographic, srgb=srgb,
                       shadow_slots=shadows["slots"] if shadows else None,
                       shadow_tiles=shadows["tiles"] if shadows else 0,
                       shadow_pcf=shadows["pcf"] if shadows else 1, oit=oit,
                       clip_plane=clip_plane is not None)
        intensities = np.array([to_linear(x.color) * x.intensity
                                for x in scene.lights]).reshape(-1, 3)
        ambient = to_linear(scene.ambient)
        ready: set[int] = set()
        for obj in scene.objects:
            m = obj.material
            user = m.shader is not None and not aux
            if user:
                prog = self.user.program(m.shader, base.defines())
            else:
                mirror = id(obj) in reflections
                prog = self.program(replace(
                    base, texture=m.texture is not None,
                    vertex_colors=obj.mesh.colors is not None, mirror=mirror,
                    environment=env is not None and m.reflectivity > 0 and colour_pass
                    and not mirror))  # a mirror reflects the sky in its reflection
            strict = not user  # a user's shader need not declare every standard input
            if id(prog) not in ready:  # per-frame uniforms, once per program
                prog.set("u_view", camera.view, strict)
                prog.set("u_eye_world", eye, strict)
                if clip_plane is not None:  # users' shaders do not clip (they lack it)
                    prog.set("u_clip_plane", tuple(float(v) for v in clip_plane), strict)
                if user:
                    prog.set("u_projection", view_projection @ np.linalg.inv(camera.view),
                             strict)
                    prog.set("u_time", float(time), strict)
                    prog.set("u_resolution", (float(width), float(height)), strict)
                if shadows:
                    shadow_maps.bind(prog, shadows)
                ready.add(id(prog))
            color = to_linear(m.color)
            prog.set("u_model", obj.transform, strict)
            prog.set("u_mvp", view_projection @ obj.transform, strict)
            prog.set("u_normal_matrix", T.normal_matrix(obj.transform), strict)
            prog.set("u_color", tuple(float(c) for c in color), strict)
            # The material's products with each light (see glsl/lib/lights.glsl), computed
            # once per draw instead of once per fragment.
            prog.set("u_ambient_term", tuple(float(c) for c in ambient * m.ka * color), strict)
            prog.set_array("u_light_diffuse", intensities * (m.kd * color), strict)
            prog.set_array("u_light_specular", intensities * m.ks, strict)
            prog.set("u_shininess", m.shininess, strict)
            prog.set("u_object_id", obj.id + 1, strict)  # 0 is "nothing" in the id target
            if oit:
                prog.set("u_opacity", m.opacity, strict)
            if id(obj) in reflections and not user:
                reflections[id(obj)].use(location=MIRROR_UNIT)
                prog.set("u_mirror", MIRROR_UNIT)
                prog.set("u_mirror_weight", m.reflectivity)
            elif env is not None and m.reflectivity > 0 and colour_pass and not user:
                self.cache.cube(env).use(location=ENV_UNIT)
                prog.set("u_environment", ENV_UNIT)
                prog.set("u_reflectivity", m.reflectivity)
                prog.set("u_ior", m.ior)
                prog.set("u_gloss", m.gloss)
                prog.set("u_gloss_jitter", tuple(float(v) for v in gloss_jitter))
            if m.texture is not None:
                self.cache.texture(m.texture, srgb).use(location=0)
                prog.set("u_texture", 0)
            self.cache.buffers(obj.mesh).vao(self.ctx, prog.gl).render()

    def _draw_reflections(self, scene, camera, width, height, shading, **kw) -> dict:
        """Draw each mirror's reflection into its texture (facet.render.mirror), before the
        pass sets its own uniforms; {id(mirror object): texture}. Rebinds the framebuffer
        that was bound."""
        mirrors = [o for o in scene.objects if o.material.mirror and o.material.shader is None]
        if not mirrors:
            return {}
        bound = self.ctx.fbo
        bg = np.asarray(scene.background, dtype=np.float64)
        rgb = (srgb_to_linear(bg[:3]) if kw["srgb"] else bg[:3]) * bg[3]
        # The side of each mirror the camera sees (parallel projection: far behind it).
        eye = camera.eye - 1e6 * camera.forward if camera.is_orthographic else camera.eye
        out = {}
        for i, obj in enumerate(mirrors):
            plane = mirror_plane(obj, eye)
            tex, fbo = self.mirrors.get(i, width, height)
            fbo.use()
            fbo.clear(*(float(c) for c in rgb), float(bg[3]), depth=1.0)
            rest = scene.view(objects=[o for o in scene.objects if o is not obj])
            self.draw(rest, camera.with_view(camera.view @ T.reflection(plane)), width,
                      height, shading, clip_plane=plane, **kw)
            out[id(obj)] = tex
        bound.use()
        return out

    def _draw_sky(self, env, view_projection, width: int, height: int) -> None:
        """The environment behind everything: a full-screen pass, no depth test or write."""
        if self._sky is None:
            root = glsl_root()
            prog = compile_program(self.ctx, root / "shadertoy" / "fullscreen.vert",
                                   root / "post" / "sky.frag")
            self._sky = (prog, self.ctx.vertex_array(prog.gl, []))
        prog, vao = self._sky
        self.cache.cube(env).use(location=ENV_UNIT)
        prog.set("u_environment", ENV_UNIT)
        prog.set("u_inv_view_projection", np.linalg.inv(view_projection))
        prog.set("u_viewport", (float(width), float(height)))
        self.ctx.disable(self.ctx.DEPTH_TEST)
        vao.render(vertices=3)
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def release(self) -> None:
        self.mirrors.release()
        if self._sky is not None:
            self._sky[1].release()
            self._sky[0].release()
        self.user.release()
        for prog in self.programs.values():
            self.cache.forget_program(prog.gl)
            prog.release()
        self.programs.clear()
        self.lights_ubo.release()

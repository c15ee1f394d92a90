"""The forward pass: one draw per scene object into the bound target, or one instanced
draw for the objects that share a mesh and a material (facet.render.raster.instancing).

Shading models map to programs through ``facet.render.shading.SHADING_MODELS``; a program is
specialised on a ``Variant`` (the frame's light kinds, shadows, which outputs...), compiled
on first use and reused. Per frame the pass writes the camera and the light block (from the
``FrameState``; the uniform buffer is re-uploaded only when the lights change), per object
its matrices and material.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from ...geometry import transforms as T
from ...gl.bindings import BLOCKS, unit
from ...gl.fullscreen import FullScreenPass
from ...gl.glsl_source import glsl_root
from ...gl.resources import ResourceCache
from ...gl.shaders import Program, compile_program
from ...gl.targets import aux_locations, writing
from ...scene.pbr import as_phong
from ...scene.scene import MAX_LIGHTS, Scene
from ..material_record import record_defines
from ..materials import (
    as_pbr,
    model_for,
    phong_color,
    slot_defines,
)
from ..shading import SHADING_MODELS, check_shading
from ..state import FrameState, pack_lights
from .culling import Culling, det3
from .edl import EdlTarget
from .ibl import LUT_SIZE, PREFILTER_LEVELS, ImageLighting
from .instancing import INSTANCE_LAYOUT, batches, instance_rows
from .mirror import MirrorTargets, mirror_plane
from .skinning import POSE_DEFINES, JointRows, bind_pose, gpu_pose, pose_buffers
from .slots import SlotSamplers, set_pbr_material
from .sprites import set_sprite_uniforms, sprite_variant, uses_edl
from .transmission import TransmissionTarget, transmits
from .user_shaders import UserPrograms

MAX_PROGRAMS = 16  # compiled mesh programs kept per renderer (least recently used go)


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
    linear_out: bool = False  # float output: the pbr model writes linear light
    shadow_slots: tuple[int, ...] | None = None  # per light: its first shadow tile, or -1
    shadow_tiles: int = 0  # tiles in the shadow atlas
    shadow_pcf: int = 1  # PCF kernel radius in texels
    oit: bool = False  # the transparent pass (into the OIT sums, raster.transparency)
    environment: bool = False  # reflects / refracts the scene's environment
    mirror: bool = False  # mixes in its planar reflection (facet.render.raster.mirror)
    clip_plane: bool = False  # discards what is behind a mirror (its reflection pass)
    slots: tuple[str, ...] = ()  # the pbr model's TEX_* defines (materials.slot_defines)
    uv1: bool = False  # the mesh has a second texture coordinate set
    tangents: bool = False  # normal mapping: the mesh's tangent frames
    alpha_mask: bool = False  # glTF alphaMode MASK: discard below the cutoff
    exact_only: bool = False  # a pass for the exact channels alone: no colour computed
    grey: bool = False  # every material-light term is grey (see grey_terms)
    transmission: bool = False  # refracts the picture behind it (raster.transmission)
    instanced: bool = False  # matrices per instance (facet.render.raster.instancing)
    sprite: str = ""  # "points" or "lines": quads per point or segment (mesh/sprite.vert)
    edl: bool = False  # eye-dome lighting of an unlit cloud (facet.render.raster.edl)
    edl_depth: bool = False  # the cloud's depth pass for it
    skin: int = 0  # skinned in the vertex shader: 4 or 8 influences (raster.skinning)
    morph: bool = False  # morphed in the vertex shader (raster.skinning)

    @classmethod
    def of(cls, state: FrameState, aux=(), oit: bool = False) -> Variant:
        """The frame's base variant (each object's is made from it)."""
        s = state.shadows
        return _base_variant(state.shading, state.light_kinds, tuple(aux),
                             state.camera.is_orthographic, state.srgb,
                             s.slots if s else None, s.tiles if s else 0, s.pcf if s else 1,
                             oit, state.clip_plane is not None, state.linear_out)

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
        d.update({s: None for s in self.slots})
        if self.shading == "pbr":
            d["LUT_SIZE"] = float(LUT_SIZE)  # the split-sum table's (facet.render.raster.ibl)
            d.update(record_defines())  # the material record's layout
        flags = {"VIEW_ORTHOGRAPHIC": self.orthographic, "HAS_TEXTURE": self.texture,
                 "HAS_UV1": self.uv1, "HAS_TANGENTS": self.tangents,
                 "ALPHA_MASK": self.alpha_mask, "EXACT_ONLY": self.exact_only,
                 "HAS_VERTEX_COLORS": self.vertex_colors, "COLOR_SRGB": self.srgb,
                 "OIT": self.oit, "HAS_ENVIRONMENT": self.environment,
                 "HAS_MIRROR": self.mirror, "CLIP_PLANE": self.clip_plane,
                 "GREY_TERMS": self.grey, "LINEAR_OUT": self.linear_out,
                 "TRANSMISSION": self.transmission, "INSTANCED": self.instanced,
                 "SPRITE_POINTS": self.sprite == "points",
                 "SPRITE_LINES": self.sprite == "lines", "EDL": self.edl,
                 "EDL_DEPTH": self.edl_depth, "SKINNED": self.skin > 0,
                 "SKIN_8": self.skin > 4, "MORPHED": self.morph}
        d.update({k: None for k, on in flags.items() if on})
        if self.skin or self.morph:
            d.update(POSE_DEFINES)
        return d


LIT = ("phong", "blinn", "flat", "gouraud")  # the models that evaluate shade_scene


def phong_terms(m, state: FrameState, ambient, intensities) -> tuple:
    """C and the material's products with each light (glsl/lib/lights.glsl: I_a k_a C,
    I_i k_d C, I_i k_s), computed once per draw instead of once per fragment."""
    color = np.asarray(phong_color(m, state), dtype=np.float64)
    return color, ambient * m.ka * color, intensities * (m.kd * color), intensities * m.ks


def grey_terms(terms) -> bool:
    """Whether every product is grey (equal channels), as an untextured grey material
    under white lights gives: then the program reads one channel of each (GREY_TERMS),
    and the compiler computes one colour channel where it would compute three. The
    picture is the same; a software rasteriser shades ~5% faster."""
    _, *products = terms
    return all(r == r[:1] * 3 for t in products for r in np.reshape(t, (-1, 3)).tolist())


@lru_cache(maxsize=64)  # asked for on every draw; a handful of distinct ones in a run
def _base_variant(shading, light_kinds, aux, orthographic, srgb, slots, tiles, pcf, oit,
                  clip_plane, linear_out=False) -> Variant:
    # "auto" picks a model per material (facet.render.materials.model_for); the base
    # variant, which users' shaders see, is phong's.
    return Variant("phong" if shading == "auto" else shading, light_kinds,
                   tuple(aux_locations(aux)), orthographic, srgb=srgb, shadow_slots=slots,
                   shadow_tiles=tiles, shadow_pcf=pcf, oit=oit, clip_plane=clip_plane,
                   linear_out=linear_out)


class ForwardPass:
    """Draws a scene with one of the shading models; owns its programs and light buffer."""

    def __init__(self, ctx, cache: ResourceCache):
        self.ctx = ctx
        self.cache = cache
        # The most recently used programs (a long-lived renderer meets many light sets and
        # materials; each program holds a few MB of compiled code): MAX_PROGRAMS at most.
        self.programs: OrderedDict[Variant, Program] = OrderedDict()
        self.user = UserPrograms(ctx, cache.forget_program)
        self._sky = None  # the environment background program, made on first use
        self.mirrors = MirrorTargets(ctx)  # planar reflection textures, made on first use
        self.behind = TransmissionTarget(ctx)  # the picture transmission refracts
        self.lights_ubo = ctx.buffer(reserve=len(pack_lights((), np.zeros(3))))
        self._lights_bytes = b""
        self.ibl = ImageLighting(ctx, cache)  # the pbr model's ambient and environment light
        self.culling = Culling()
        self._front_face = None  # the winding set last (_front)
        self._variants: dict[tuple, Variant] = {}  # (base, flags) -> Variant (_phong_variant)
        self.samplers = SlotSamplers(ctx)
        self.edl = EdlTarget(ctx)  # eye-dome lighting's depth of unlit clouds
        self.joints = JointRows(ctx)  # skinned poses' joint matrices

    def program(self, variant: Variant) -> Program:
        """The compiled program for ``variant`` (compiled on first use, then reused; the
        least recently used beyond MAX_PROGRAMS is released)."""
        if variant in self.programs:
            self.programs.move_to_end(variant)
        else:
            spec = SHADING_MODELS[check_shading(variant.shading)]
            root = glsl_root()
            vertex = "mesh/sprite.vert" if variant.sprite else spec.vertex
            prog = compile_program(self.ctx, root / vertex, root / spec.fragment,
                                   variant.defines())
            self.programs[variant] = prog
            while len(self.programs) > MAX_PROGRAMS:
                _, old = self.programs.popitem(last=False)
                self.cache.forget_program(old.gl)
                old.release()
        return self.programs[variant]

    def draw(self, scene: Scene, state: FrameState, *, aux: tuple[str, ...] = (),
             oit: bool = False, colour_pass: bool = True) -> None:
        """Draw every object of ``scene`` into the bound framebuffer, which holds the ``aux``
        channels too. Materials with their own shader use it for colour (``aux`` passes use
        the built-in one). ``oit``: the transparent pass into the OIT sums.
        ``colour_pass``: False for passes that only fill the exact channels (no background,
        no environment lookups, no mirrors)."""
        shows_effects = colour_pass and not oit
        reflections = self._draw_reflections(scene, state) \
            if shows_effects and state.clip_plane is None else {}
        behind = self._draw_behind(scene, state) if shows_effects else None
        if state.lights_block != self._lights_bytes:
            self.lights_ubo.write(state.lights_block)
            self._lights_bytes = state.lights_block
        self.lights_ubo.bind_to_uniform_block(BLOCKS["Lights"])
        view_projection = state.view_projection()
        # Flipping y mirrors the image, so counter-clockwise front faces turn clockwise; so
        # does looking through a mirror, and so does an object whose transform mirrors
        # (det < 0): the winding that faces front is set per draw (_front), which culling
        # and the shaders' gl_FrontFacing (two-sided lighting) both follow.
        mirrored_view = state.flip_y != (state.clip_plane is not None)
        camera = state.camera
        # Perspective: V = normalize(eye - p). Parallel projection: V is the same everywhere.
        eye = tuple((-camera.forward if camera.is_orthographic else camera.eye).tolist())
        env = state.environment
        if env is not None and shows_effects:
            self._draw_sky(env, view_projection, state.width, state.height)
        base = Variant.of(state, aux, oit)
        to_linear = state.to_linear
        intensities = np.array([to_linear(x.color) * x.intensity
                                for x in state.lights]).reshape(-1, 3)
        ambient = to_linear(state.ambient)
        ready: set[int] = set()
        if colour_pass and any(model_for(state.shading, o.material) == "pbr"
                               for o in scene.objects):
            # Made (once) before any draw: they are passes of their own.
            self.ibl.lut()
            if env is not None:
                self.ibl.maps(env)
        def alone(o) -> bool:  # drawn by itself: a user's shader, a mirror, transmission,
            return o.mesh.kind != "mesh" or hasattr(o.mesh, "skin") or (  # points, lines,
                o.material.shader is not None and not aux) or id(o) in reflections or (
                behind is not None and model_for(state.shading, o.material) == "pbr"
                and transmits(as_pbr(o.material)))

        for item in batches(scene.objects, alone):
            group = item if isinstance(item, list) else None  # one mesh, one material
            obj = item[0] if group is not None else item
            if obj.mesh.kind != "mesh":  # points and lines (facet.render.raster.sprites)
                self._draw_sprites(obj, base, state, view_projection, eye, ambient,
                                   intensities, bool(aux) and not colour_pass, ready)
                continue
            m = obj.material
            user = m.shader is not None and not aux
            mirror = id(obj) in reflections
            model = model_for(state.shading, m)
            reflects = (env is not None and m.reflectivity > 0 and colour_pass and not mirror
                        and not user)
            if user:
                prog = self.user.program(m.shader, base.defines())
            elif model == "pbr":
                pbr = as_pbr(m)
                mesh = obj.mesh
                prog = self.program(replace(
                    base, shading="pbr", slots=slot_defines(pbr),
                    vertex_colors=mesh.colors is not None, uv1=mesh.uvs1 is not None,
                    # (a deformed pose's tangents are its rest mesh's, moved on the GPU)
                    tangents=pbr.normal_mapped and (
                        mesh.rest if any(gpu_pose(mesh)) else mesh).tangents is not None,
                    alpha_mask=pbr.alpha_mode == "MASK",
                    environment=env is not None and colour_pass,
                    transmission=behind is not None and transmits(pbr),
                    instanced=group is not None,
                    **({} if user else dict(zip(("skin", "morph"), gpu_pose(mesh),
                                                strict=True)))))
            else:  # a mirror reflects the sky in its reflection
                exact_only = bool(aux) and not colour_pass
                terms = phong_terms(m, state, ambient, intensities)
                prog = self.program(self._phong_variant(
                    base, model, m.texture is not None, mirror, reflects,
                    obj.mesh.colors is not None, getattr(m, "alpha_mode", "") == "MASK",
                    exact_only, not exact_only and model in LIT and grey_terms(terms),
                    group is not None, *((0, False) if user else gpu_pose(obj.mesh))))
            strict = not user  # a user's shader need not declare every standard input
            if id(prog) not in ready:  # per-frame uniforms, once per program
                self._frame_uniforms(prog, state, view_projection, eye, user)
                ready.add(id(prog))
            place = (item, view_projection, state, mirrored_view)
            if model == "pbr" and not user:
                self._draw_pbr(prog, obj, pbr, state, view_projection, env, colour_pass,
                               behind if transmits(pbr) else None, place)
                continue
            if user:
                terms = phong_terms(m, state, ambient, intensities)
            color, ambient_term, diffuse, specular = terms
            if group is None:
                prog.set("u_model", obj.transform, strict)
                prog.set("u_mvp", view_projection @ obj.transform, strict)
                prog.set("u_normal_matrix", T.normal_matrix(obj.transform), strict)
                prog.set("u_object_id", obj.id + 1, strict)  # 0: "nothing" in the id target
            prog.set("u_color", tuple(color.tolist()), strict)
            prog.set("u_ambient_term", tuple(ambient_term.tolist()), strict)
            prog.set_array("u_light_diffuse", diffuse, strict)
            prog.set_array("u_light_specular", specular, strict)
            prog.set("u_shininess", m.shininess, strict)
            if oit:
                prog.set("u_opacity", m.opacity, strict)
            if mirror:
                reflections[id(obj)].use(location=unit("u_mirror"))
                prog.set("u_mirror_weight", m.reflectivity)
            elif reflects:
                self.cache.cube(env).use(location=unit("u_environment"))
                prog.set("u_reflectivity", m.reflectivity)
                prog.set("u_ior", m.ior)
                prog.set("u_gloss", m.gloss)
                prog.set("u_gloss_jitter", tuple(float(v) for v in state.gloss_jitter))
            if m.texture is not None:
                self.cache.texture(m.texture, state.srgb).use(location=unit("u_texture"))
                slot = getattr(m, "base_color_texture", None)
                prog.set("u_uv_transform", np.eye(3) if slot is None else slot.transform,
                         strict=False)
            if getattr(m, "alpha_mode", "") == "MASK":
                prog.set("u_base_alpha", float(m.base_color[3]), strict=False)
                prog.set("u_alpha_cutoff", m.alpha_cutoff, strict=False)
            self._render(prog, *place)
        self._cull(False)
        self._front(False)

    def _draw_sprites(self, obj, base, state, view_projection, eye, ambient, intensities,
                      exact_only: bool, ready: set) -> None:
        terms = phong_terms(as_phong(obj.material), state, ambient, intensities)
        variant = sprite_variant(base, obj, state.shading, exact_only)
        buffers = self.cache.buffers(obj.mesh)
        self._cull(False)

        def draw(v) -> object:
            prog = self.program(v)
            if id(prog) not in ready:
                self._frame_uniforms(prog, state, view_projection, eye, False)
                ready.add(id(prog))
            set_sprite_uniforms(prog, obj, state, view_projection, terms)
            return prog

        if uses_edl(obj, variant):  # its depth first, read around each fragment after
            depth = replace(variant, aux=(), oit=False, edl_depth=True, shadow_slots=None,
                            light_kinds=())
            shade = self.edl.draw_shade(
                state.width, state.height,
                lambda: buffers.draw_sprites(self.ctx, draw(depth).gl))
            variant = replace(variant, edl=True)
            prog = draw(variant)
            shade.use(location=unit("u_edl_shade"))
            buffers.draw_sprites(self.ctx, prog.gl)
            return
        buffers.draw_sprites(self.ctx, draw(variant).gl)

    def _render(self, prog, item, view_projection, state: FrameState,
                mirrored_view: bool) -> None:
        """Draw ``item`` (an object, or a batch of objects sharing mesh and material: one
        instanced draw per winding and culling state) with ``prog``, whose material is
        set; each with its front winding and culling (facet.render.raster.culling)."""
        camera = state.camera
        if not isinstance(item, list):
            det = det3(item.transform)
            self._front(mirrored_view != (det < 0))
            # Back faces nobody can see are not drawn (facet.render.raster.culling).
            self._cull(self.culling.cull(item, state.cull, camera.view, camera.near, det))
            if any(gpu_pose(item.mesh)) and "in_position" in prog.gl and (
                    "u_joints" in prog.gl or "u_targets" in prog.gl):  # deformed on the GPU
                buffers = pose_buffers(self.cache, item.mesh, self.ctx)
                bind_pose(prog, item.mesh, buffers, self.joints)
            else:
                buffers = self.cache.buffers(item.mesh)
            buffers.vao(self.ctx, prog.gl).render()
            return
        rows, det = instance_rows(item, view_projection)
        cull = self.culling.cull_many(item, np.stack([o.transform for o in item]), state.cull,
                                      camera.view, camera.near, det)
        buffers = self.cache.buffers(item[0].mesh)
        for mirrored in (False, True):
            for culled in (False, True):
                chosen = ((det < 0) == mirrored) & (cull == culled)
                if chosen.any():
                    self._front(mirrored_view != mirrored)
                    self._cull(culled)
                    buffers.draw_instances(self.ctx, prog.gl, rows[chosen], INSTANCE_LAYOUT)

    def _phong_variant(self, base: Variant, *flags) -> Variant:
        """``base`` for one object drawn by a Phong model (``flags``: shading, texture,
        mirror, environment, vertex_colors, alpha_mask, exact_only, grey, instanced), kept:
        it is
        asked for per object per frame, and building a Variant costs more than finding
        one."""
        key = (base, *flags)
        found = self._variants.get(key)
        if found is None:
            if len(self._variants) >= 4 * MAX_PROGRAMS:
                self._variants.clear()
            names = ("shading", "texture", "mirror", "environment", "vertex_colors",
                     "alpha_mask", "exact_only", "grey", "instanced", "skin", "morph")
            found = self._variants[key] = replace(base, **dict(zip(names, flags, strict=True)))
        return found

    def _front(self, clockwise: bool) -> None:
        face = "cw" if clockwise else "ccw"
        if self._front_face != face:
            self.ctx.front_face = face
            self._front_face = face

    def _cull(self, on: bool) -> None:
        if on:
            self.ctx.enable(self.ctx.CULL_FACE)
        else:
            self.ctx.disable(self.ctx.CULL_FACE)

    def _draw_pbr(self, prog, obj, m, state: FrameState, view_projection, env,
                  colour_pass: bool, behind, place) -> None:
        """One object or batch (``place``: what ``_render`` draws) by the pbr model
        (glsl/mesh/pbr.frag); ``behind``: the picture its transmission refracts
        (facet.render.raster.transmission)."""
        if not isinstance(place[0], list):
            prog.set("u_model", obj.transform)
            prog.set("u_mvp", view_projection @ obj.transform)
            prog.set("u_normal_matrix", T.normal_matrix(obj.transform))
            prog.set("u_handedness", -1.0 if det3(obj.transform) < 0 else 1.0, strict=False)
            prog.set("u_object_id", obj.id + 1)
        bound = set_pbr_material(prog, m, self.cache, self.samplers)
        if colour_pass:
            self.ibl.lut().use(location=unit("u_ibl_lut"))
        if env is not None and colour_pass:
            irradiance, prefiltered = self.ibl.maps(env)
            irradiance.use(location=unit("u_irradiance"))
            prefiltered.use(location=unit("u_prefiltered"))
            prog.set("u_prefiltered_levels", float(PREFILTER_LEVELS), strict=False)
        if behind is not None:
            behind.use(location=unit("u_behind"))
            prog.set("u_behind_width", float(behind.width))
            prog.set("u_view_projection", view_projection)
        self._render(prog, *place)
        for at in bound:  # sampler objects outlive the draw otherwise
            self.ctx.clear_samplers(at, at + 1)

    def _frame_uniforms(self, prog: Program, state: FrameState, view_projection, eye,
                        user: bool) -> None:
        strict = not user
        prog.set("u_view", state.camera.view, strict)
        prog.set("u_eye_world", eye, strict)
        if state.clip_plane is not None:  # users' shaders do not clip (they lack it)
            prog.set("u_clip_plane", tuple(float(v) for v in state.clip_plane), strict)
        if user:
            prog.set("u_projection", view_projection @ np.linalg.inv(state.camera.view),
                     strict)
            prog.set("u_time", float(state.time), strict)
            prog.set("u_resolution", (float(state.width), float(state.height)), strict)
        if state.shadows:
            state.shadows.bind(prog)

    def _draw_reflections(self, scene: Scene, state: FrameState) -> dict:
        """Draw each mirror's reflection into its texture (facet.render.raster.mirror), before the
        pass sets its own uniforms; {id(mirror object): texture}. Rebinds the framebuffer
        that was bound."""
        mirrors = [o for o in scene.objects if o.material.mirror and o.material.shader is None]
        if not mirrors:
            return {}
        bound = self.ctx.fbo
        bg = np.asarray(scene.background, dtype=np.float64)
        rgb = state.to_linear(bg[:3]) * bg[3]
        camera = state.camera
        # The side of each mirror the camera sees (parallel projection: far behind it).
        eye = camera.eye - 1e6 * camera.forward if camera.is_orthographic else camera.eye
        out = {}
        for i, obj in enumerate(mirrors):
            plane = mirror_plane(obj, eye)
            tex, fbo = self.mirrors.get(i, state.width, state.height)
            fbo.use()
            fbo.clear(*(float(c) for c in rgb), float(bg[3]), depth=1.0)
            rest = scene.view(objects=[o for o in scene.objects if o is not obj])
            self.draw(rest, state.with_(camera=camera.with_view(
                camera.view @ T.reflection(plane)), clip_plane=tuple(plane)))
            out[id(obj)] = tex
        bound.use()
        return out

    def _draw_behind(self, scene: Scene, state: FrameState):
        """The picture of ``scene`` without its transmitting objects (those the pbr model
        draws), mipmapped, for them to refract (facet.render.raster.transmission); None
        when none transmits. Rebinds the framebuffer that was bound."""
        through = [o for o in scene.objects if o.material.shader is None and
                   model_for(state.shading, o.material) == "pbr" and transmits(o.material)]
        if not through:
            return None
        bound = self.ctx.fbo
        tex, fbo = self.behind.get(state.width, state.height)
        fbo.use()
        bg = np.asarray(scene.background, dtype=np.float64)
        fbo.clear(*(float(c) for c in state.to_linear(bg[:3]) * bg[3]), float(bg[3]),
                  depth=1.0)
        skip = {id(o) for o in through}
        self.draw(scene.view(objects=[o for o in scene.objects if id(o) not in skip]), state)
        tex.build_mipmaps()
        bound.use()
        return tex

    def _draw_sky(self, env, view_projection, width: int, height: int) -> None:
        """The environment behind everything: a full-screen pass, no depth test or write."""
        if self._sky is None:
            self._sky = FullScreenPass(self.ctx, "post/sky.frag")
        self.ctx.disable(self.ctx.DEPTH_TEST)
        with writing(self.ctx.fbo, exact=False):  # the exact channels keep their "nothing"
            self._sky.draw({"u_environment": self.cache.cube(env)},
                           u_inv_view_projection=np.linalg.inv(view_projection),
                           u_viewport=(float(width), float(height)))
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def release(self) -> None:
        self.culling.release()
        self.ibl.release()
        self.samplers.release()
        self.mirrors.release()
        self.behind.release()
        self.edl.release()
        self.joints.release()
        if self._sky is not None:
            self._sky.release()
        self.user.release()
        for prog in self.programs.values():
            self.cache.forget_program(prog.gl)
            prog.release()
        self.programs.clear()
        self.lights_ubo.release()

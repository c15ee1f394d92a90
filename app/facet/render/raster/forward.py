"""The forward pass: one draw per scene object into the bound target, or one instanced
draw for the objects that share a mesh and a material (facet.render.raster.instancing).

Each object's draw comes from a table keyed by its geometry kind and material model
(facet.render.raster.draws). Shading models map to programs through
``facet.render.shading.SHADING_MODELS``; a program is specialised on a ``Variant``
(facet.render.raster.variant: the frame's light kinds, shadows, which outputs...), compiled
on first use and reused. Per frame the pass writes the camera and the light block (from the
``FrameState``; the uniform buffer is re-uploaded only when the lights change), per object
its matrices and material.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace

import numpy as np

from ...geometry.planes import reflection
from ...gl.bindings import BLOCKS
from ...gl.fullscreen import FullScreenPass
from ...gl.glsl_source import glsl_root
from ...gl.resources import ResourceCache
from ...gl.shaders import Program, compile_program
from ...gl.targets import writing
from ...scene.scene import Scene
from ..materials import as_pbr, model_for
from ..shading import SHADING_MODELS, check_shading
from ..state import FrameState, pack_lights
from .culling import Culling, det3
from .draws import DRAWERS, FramePass, material_model
from .edl import EdlTarget
from .ibl import ImageLighting
from .instancing import INSTANCE_LAYOUT, batches, instance_rows
from .mirror import MirrorTargets, mirror_plane
from .skinning import JointRows, bind_pose, gpu_pose, pose_buffers
from .slots import SlotSamplers
from .transmission import TransmissionTarget, transmits
from .user_shaders import UserPrograms
from .variant import Variant

MAX_PROGRAMS = 16  # compiled mesh programs kept per renderer (least recently used go)


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
        self._variants: dict[tuple, Variant] = {}  # (base, flags) -> Variant (phong_variant)
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
        to_linear = state.to_linear
        intensities = np.array([to_linear(x.color) * x.intensity
                                for x in state.lights]).reshape(-1, 3)
        fp = FramePass(state, Variant.of(state, aux, oit), view_projection, eye,
                       to_linear(state.ambient), intensities, aux, oit, colour_pass,
                       reflections, behind, mirrored_view)
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
            obj = item[0] if isinstance(item, list) else item  # one mesh, one material
            DRAWERS[obj.mesh.kind, material_model(obj, fp)](self, fp, item, obj)
        self.cull(False)
        self._front(False)

    def render(self, prog, item, fp: FramePass) -> None:
        """Draw ``item`` (an object, or a batch of objects sharing mesh and material: one
        instanced draw per winding and culling state) with ``prog``, whose material is
        set; each with its front winding and culling (facet.render.raster.culling)."""
        state, mirrored_view = fp.state, fp.mirrored_view
        camera = state.camera
        if not isinstance(item, list):
            det = det3(item.transform)
            self._front(mirrored_view != (det < 0))
            # Back faces nobody can see are not drawn (facet.render.raster.culling).
            self.cull(self.culling.cull(item, state.cull, camera.view, camera.near, det))
            if any(gpu_pose(item.mesh)) and "in_position" in prog.gl and (
                    "u_joints" in prog.gl or "u_targets" in prog.gl):  # deformed on the GPU
                buffers = pose_buffers(self.cache, item.mesh, self.ctx)
                bind_pose(prog, item.mesh, buffers, self.joints)
            else:
                buffers = self.cache.buffers(item.mesh)
            buffers.vao(self.ctx, prog.gl).render()
            return
        rows, det = instance_rows(item, fp.view_projection)
        cull = self.culling.cull_many(item, np.stack([o.transform for o in item]), state.cull,
                                      camera.view, camera.near, det)
        buffers = self.cache.buffers(item[0].mesh)
        for mirrored in (False, True):
            for culled in (False, True):
                chosen = ((det < 0) == mirrored) & (cull == culled)
                if chosen.any():
                    self._front(mirrored_view != mirrored)
                    self.cull(culled)
                    buffers.draw_instances(self.ctx, prog.gl, rows[chosen], INSTANCE_LAYOUT)

    def phong_variant(self, base: Variant, *flags) -> Variant:
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

    def cull(self, on: bool) -> None:
        if on:
            self.ctx.enable(self.ctx.CULL_FACE)
        else:
            self.ctx.disable(self.ctx.CULL_FACE)

    def frame_uniforms(self, prog: Program, fp: FramePass, user: bool) -> None:
        """The pass's uniforms of ``prog`` (camera, clip plane, shadows; a user's shader's
        projection, time and resolution), once per program and pass."""
        if id(prog) in fp.ready:
            return
        fp.ready.add(id(prog))
        state, strict = fp.state, not user
        prog.set("u_view", state.camera.view, strict)
        prog.set("u_eye_world", fp.eye, strict)
        if state.clip_plane is not None:  # users' shaders do not clip (they lack it)
            prog.set("u_clip_plane", tuple(float(v) for v in state.clip_plane), strict)
        if user:
            prog.set("u_projection", fp.view_projection @ np.linalg.inv(state.camera.view),
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
                camera.view @ reflection(plane)), clip_plane=tuple(plane)))
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

"""The ray scene on the GPU, shared by the Whitted tracer and the path tracer (siblings that
each own one): the meshes' triangles and hierarchies, the placed instances and their top
level, the materials' images as layers of one texture array, and the lights' block, uploaded
from what facet.render.rays.pack lays out; and the full-screen programs of glsl/trace/ that
read them, compiled once per set of defines.

Meshes are packed once per Mesh (kept while it lives) and the geometry textures are uploaded
again only when the set of meshes changes; instances and the top level are packed per call
(per supersample when objects move, for motion blur): a turntable or a moving camera never
rebuilds a mesh's hierarchy.
"""

from __future__ import annotations

import weakref

import numpy as np

from ...gl.bindings import BLOCKS, IMAGES, image_defines, unit
from ...gl.fullscreen import FullScreenPass
from ...gl.glsl_source import glsl_root
from ...gl.shaders import compile_program
from ...gl.targets import aux_locations
from ...scene.scene import MAX_LIGHTS
from ..materials import as_pbr, phong_color
from ..shading import SHADING_MODELS
from ..state import FrameState, pack_lights
from . import pack
from .layers import texture_array
from .sprites import sprite_lines, sprite_radii


def ray_scene_lines(scene, noun: str) -> list[str]:
    """What the ray scene draws otherwise than the rasterizer, said by the tracer ``noun``:
    points and lines as spheres and capsules, glass volumes on open surfaces as thin."""
    return sprite_lines(scene, noun) + pack.open_volume_lines(scene, noun)


def pixel_cone(state: FrameState) -> tuple[float, float]:
    """A pixel's ray cone (glsl/trace/surface.glsl's u_cone): its width at distance t is
    a + b t; (pixel width, 0) for a parallel projection, (0, pixel angle) for a perspective
    or intrinsics one (from the projection's vertical scale)."""
    p = state.camera.projection(state.width, state.height)
    size = 2.0 / (float(p[1, 1]) * state.height)
    return (size, 0.0) if p[3, 3] == 1.0 else (0.0, size)


def scene_rect(box, views, width: int, height: int):
    """The pixels that rays through the scene's world ``box`` (2, 3) can come from, for the
    view-projections ``views`` (one per sample drawn): (x, y, w, h) in GL's window
    coordinates, a pixel wider all round than the box's corners fall (a pixel's rays
    leave from anywhere in it), empty when the box is; None when every pixel may see the
    scene (an unbounded object, a corner at or behind the eye, a box over the picture)."""
    if box is None:
        return None
    box = np.asarray(box, np.float64)
    if not np.all(box[0] <= box[1]):
        return (0, 0, 0, 0)  # nothing there to see
    corners = np.array([[box[i, 0], box[j, 1], box[k, 2], 1.0]
                        for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    lo, hi = np.array([np.inf, np.inf]), np.array([-np.inf, -np.inf])
    for view in views:
        clip = corners @ np.asarray(view, np.float64).T
        if not np.all(clip[:, 3] > 1e-9 * np.abs(clip[:, :3]).max(initial=1.0)):
            return None
        ndc = clip[:, :2] / clip[:, 3:]
        lo, hi = np.minimum(lo, ndc.min(axis=0)), np.maximum(hi, ndc.max(axis=0))
    size = np.array([width, height], np.float64)
    x0, y0 = np.clip(np.floor((lo + 1.0) / 2.0 * size) - 1.0, 0, size).astype(int)
    x1, y1 = np.clip(np.ceil((hi + 1.0) / 2.0 * size) + 1.0, 0, size).astype(int)
    if x0 == 0 and y0 == 0 and x1 == width and y1 == height:
        return None  # (the whole picture)
    return (int(x0), int(y0), max(int(x1 - x0), 0), max(int(y1 - y0), 0))


def _overlap(a, b):
    """The overlap of rectangles (x, y, w, h), or None."""
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[0] + a[2], b[0] + b[2]), min(a[1] + a[3], b[1] + b[3])
    return (x0, y0, x1 - x0, y1 - y0) if x1 > x0 and y1 > y0 else None


def _set_uniforms(program: FullScreenPass, values: dict) -> None:
    for name, value in values.items():
        if isinstance(value, bytes):  # an array, as GL lays it out
            member = program.program.gl.get(name, None)
            if member is not None:
                member.write(value)
        else:
            program.program.set(name, value, strict=False)


def scene_defines(scene) -> tuple:
    """The kinds of object ``scene`` lacks, as defines that leave their code out of the
    tracers' programs: NO_SPRITES (no points or lines: no sphere or capsule in a triangle
    test), NO_SHAPES (no analytic shapes), NO_MESHES (shapes only: no mesh traversal),
    NO_KIND_<KIND> (no shape of that kind: its intersection left out). llvmpipe runs every
    line of a shader's branches whether or not a lane takes them (only loops end early), so
    code a scene cannot reach still costs it time: in a traversal's inner loop, most of it
    (the Cornell box of shapes: every candidate paid for the cylinder's and cone's test)."""
    objects = scene.objects
    kinds = {o.shape.kind for o in objects if o.shape is not None}
    return (("NO_SPRITES",) if all(o.shape is not None or o.mesh.kind == "mesh"
                                   for o in objects) else ()) + \
        (("NO_SHAPES",) if not kinds else ()) + \
        (("NO_MESHES",) if objects and all(o.shape is not None for o in objects) else ()) + \
        tuple(f"NO_KIND_{kind.upper()}" for kind in pack.KINDS
              if kind != "mesh" and kind not in kinds)


def constant_sky(state: FrameState):
    """The frame's environment's one colour (Environment.uniform_color) or None: the
    programs read it as a value (SKY_CONSTANT: glsl/trace/sky.glsl, trace.frag)."""
    return None if state.environment is None else state.environment.uniform_color


def reads_images(ctx) -> bool:
    """Whether programs on ``ctx`` can read the scene's arrays as images (glsl/trace/data.glsl
    SCENE_IMAGES): its GLSL 3.30 programs require image load and store and layout bindings
    as extensions (core in GL 4.2, whose contexts list them: Mesa's, NVIDIA's, AMD's)."""
    return {"GL_ARB_shader_image_load_store",
            "GL_ARB_shading_language_420pack"} <= set(ctx.extensions)


class RayScene:
    """One engine's ray scene (module docstring). ``programs``: compiled passes by stage
    and defines."""

    use_blocks = True  # a small scene's rows from uniform blocks (False: textures only)
    use_rects = True  # escaped pixels by the escaped program (False: one program for all)
    use_images = True  # the scene's arrays as images where the context can (reads_images)

    def __init__(self, ctx, cache):
        self.ctx, self.cache = ctx, cache
        self.programs: dict[tuple, FullScreenPass] = {}
        self._defines: dict[FullScreenPass, tuple] = {}  # a program's stage and defines
        self.world_box = None  # the bound objects' (2, 3) world box; None: unbounded
        self.meshes = weakref.WeakKeyDictionary()  # Mesh -> pack.MeshData
        self._sprite_sizes: dict[int, int | None] = {}  # id(points) -> its radii's hash
        self._geometry_key: tuple | None = None
        self._geometry_refs: list = []  # the meshes of the uploaded geometry (alive)
        self.roots: dict[int, int] = {}
        self.deepest = 1  # the uploaded hierarchies' most levels (pack.stack_defines)
        self._stacks: dict = {}  # the prepared scene's stack depths (pack.stack_defines)
        self.first_tri: dict[int, int] = {}
        self.textures: dict[str, object] = {}
        self._layers_key: tuple | None = None
        self.layers: dict = {}
        self.lights_ubo = ctx.buffer(reserve=len(pack_lights((), np.zeros(3))))
        limit = int(ctx.info["GL_MAX_TEXTURE_SIZE"])
        self.max_texels = pack.TEX_WIDTH * limit
        # Without images (reads_images), small scenes' instance rows and top level are read
        # from uniform blocks: on llvmpipe a uniform is much cheaper than a texel fetch (the
        # Cornell box: 610 -> 414 ms a sample at 256 x 256); larger ones stay in their
        # textures. An image is cheaper than both (the Cornell box at 128 x 128: 24.9 ms a
        # sample from blocks, 18.7 from images). (Storage buffers, GL 4.3, were measured
        # slower than blocks and texel fetches: 906 ms.)
        self.block_texels = min(int(ctx.info["GL_MAX_UNIFORM_BLOCK_SIZE"]) // 16, 4096)
        self.blocks = {name: ctx.buffer(reserve=self.block_texels * 16)
                       for name in ("Instances", "Tlas")}
        self._in_blocks = False  # the prepared scene's rows fit them (``prepare``)
        self._images = reads_images(ctx)
        self._scene_defines: tuple = ()  # the prepared scene's (scene_defines)

    # -- uploads ---------------------------------------------------------------------------
    def upload(self, name: str, rows: np.ndarray, dtype: str = "f4") -> None:
        """Rows of texels as the scene texture ``name`` (replacing the last one)."""
        image = pack.to_texels(rows)
        old = self.textures.pop(name, None)
        if old is not None:
            old.release()
        tex = self.ctx.texture((pack.TEX_WIDTH, image.shape[0]), 4, image.tobytes(),
                               dtype=dtype)
        tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
        self.textures[name] = tex

    def prepare(self, scene, state: FrameState, requests: list) -> None:
        """Geometry for ``scene`` and its images ``requests`` ((texture, mode) pairs,
        facet.render.rays.layers), each uploaded only when it changed."""
        self._geometry(scene, state)
        self._texture_layers(requests, state.srgb)
        # What the scene holds decides what the programs hold (scene_defines).
        self._scene_defines = scene_defines(scene)
        self._stacks = pack.stack_defines(self.deepest, len(scene.objects))
        n = len(scene.objects)  # (a top level has fewer than 2 n nodes)
        self._in_blocks = RayScene.use_blocks and not self.images and max(
            n * pack.INSTANCE_TEXELS, (2 * n + 1) * pack.NODE_TEXELS) <= self.block_texels

    @property
    def images(self) -> bool:
        """Whether the programs read the scene's arrays as images (reads_images)."""
        return self._images and RayScene.use_images

    def _geometry(self, scene, state) -> None:
        """Every mesh's triangles and hierarchy, uploaded when the set of meshes changed (or,
        for points and lines sized in pixels, their radii: facet.render.rays.sprites)."""
        meshes = list({id(o.mesh): o.mesh for o in scene.objects if o.shape is None}.values())
        framed = {id(o.mesh) for o in scene.objects
                  if o.shape is None and as_pbr(o.material).normal_mapped}
        radii = {id(o.mesh): sprite_radii(o, state.camera, state.width, state.height)
                 for o in scene.objects if o.mesh.kind != "mesh"}
        sized = {k: hash(r.tobytes()) for k, r in radii.items()}
        key = tuple((id(m), id(m) in framed, sized.get(id(m))) for m in meshes)
        if key == self._geometry_key and "tris" in self.textures:
            return
        data = []
        twin = pack.same_geometry(meshes, framed)  # (uploaded once)
        for k, mesh in enumerate(meshes):
            if twin[k] != k:
                self.meshes[mesh] = self.meshes[meshes[twin[k]]]
                continue
            cached = self.meshes.get(mesh)
            if cached is None or (id(mesh) in framed and not cached.has_tangents) or \
                    self._sprite_sizes.get(id(mesh)) != sized.get(id(mesh)):
                self.meshes[mesh] = pack.mesh_data(mesh, id(mesh) in framed,
                                                   radii.get(id(mesh)))
                self._sprite_sizes[id(mesh)] = sized.get(id(mesh))
            data.append(self.meshes[mesh])
        if not data:  # shapes only: one dummy triangle keeps every sampler valid
            from ...scene.mesh import Mesh

            data = [pack.mesh_data(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))]
        geo = pack.pack_geometry(data, self.max_texels)
        own = [twin[k] == k for k in range(len(meshes))]
        slot = np.cumsum(own) - 1  # each mesh's place in ``data``: its twin's
        self.upload("tris", geo["tris"])
        self.upload("tri_index", geo["index"], "i4")
        self.upload("vertices", geo["vertices"])
        self.upload("nodes", geo["nodes"], "u4")
        self.deepest = max(d.depth for d in data)
        self.roots = {id(m): int(geo["root"][slot[twin[k]]]) for k, m in enumerate(meshes)}
        self.first_tri = {id(m): int(geo["first_tri"][slot[twin[k]]])
                          for k, m in enumerate(meshes)}
        self._geometry_key, self._geometry_refs = key, meshes

    def _texture_layers(self, requests: list, srgb: bool) -> None:
        """The requested images as layers of one texture array, keyed (id(texture), mode)
        (facet.render.rays.layers)."""
        requests = list({(id(t), c): (t, c) for t, c in requests}.values())
        key = (tuple((id(t), c) for t, c in requests), srgb)
        if key == self._layers_key:
            return
        old = self.textures.pop("textures", None)
        if old is not None:
            old.release()
        self.textures["textures"] = texture_array(self.ctx, requests, srgb,
                                                  self.cache.ray_layers)
        self.layers = {(id(t), c): i for i, (t, c) in enumerate(requests)}
        self._layers_key = key

    def instances(self, scene, state: FrameState, more_rows=None) -> tuple[int, bool, int]:
        """Upload the placed objects (``more_rows(rows, ordered)`` may add to their rows):
        (unbounded count, has a top level, the single bounded instance without one or
        -1)."""
        boxes = {id(o.mesh): self.meshes[o.mesh].bounds for o in scene.objects
                 if o.mesh.kind != "mesh" and o.shape is None}
        top = self._stacks.get("TOP_STACK")  # (the top level fits the programs' stack)
        rows, tlas, unbounded, ordered = pack.pack_instances(
            scene.objects, self.roots, lambda m: phong_color(m, state), self.layers, boxes,
            None if top is None else top - 1)
        if more_rows is not None:
            more_rows(rows, ordered)
        tlas_rows = tlas.reshape(-1, 4) if tlas is not None else np.zeros((4, 4), np.float32)
        self.upload("instances", rows.reshape(-1, 4))
        self.upload("tlas", tlas_rows)
        if self._in_blocks:
            for name, data in (("Instances", rows.reshape(-1, 4)), ("Tlas", tlas_rows)):
                if len(data) > self.block_texels:  # (prepare saw the same objects)
                    raise RuntimeError(f"{name} outgrew its uniform block")
                self.blocks[name].write(np.ascontiguousarray(data, np.float32).tobytes())
                self.blocks[name].bind_to_uniform_block(BLOCKS[name])
        single = unbounded if tlas is None and len(rows) > unbounded else -1
        self.world_box = pack.bounded_box(scene.objects, tlas, unbounded, boxes)
        return unbounded, tlas is not None, single

    # -- programs and draws ----------------------------------------------------------------
    def program(self, stage: str, state: FrameState, shadows: bool, aux=(),
                secondary: bool = False, extra=()) -> FullScreenPass:
        """glsl/trace/<stage>.frag with the frame's defines and ``extra`` ones. The lights
        are looped over at run time (u_light_count), not unrolled per light set as the
        rasterizer's are: each unrolled light would inline a whole shadow ray's traversal,
        and one program serves every light set."""
        model = "phong" if state.shading in ("auto", "pbr") else state.shading
        defines = {SHADING_MODELS[model].define: None, "MAX_LIGHTS": MAX_LIGHTS,
                   **pack.layout_defines(), **self._stacks}
        if self._in_blocks:
            defines["SCENE_BLOCKS"] = self.block_texels
        if self.images:
            defines.update(SCENE_IMAGES=None, **image_defines())
        defines.update(dict.fromkeys(self._scene_defines))
        flags = {"SHADOWS": shadows and stage == "trace", "COLOR_SRGB": state.srgb,
                 "LINEAR_OUT": state.linear_out,
                 "SECONDARY": secondary and stage == "trace",
                 "HAS_ENVIRONMENT": state.environment is not None and stage != "primary",
                 "SKY_CONSTANT": constant_sky(state) is not None and stage != "primary"}
        defines.update({k: None for k, on in flags.items() if on})
        defines.update(dict(k if isinstance(k, tuple) else (k, None) for k in extra))
        for name, location in aux_locations(aux).items():
            defines[f"OUT_{name.upper()}"] = location
        return self._compiled(stage, defines)

    def _compiled(self, stage: str, defines: dict) -> FullScreenPass:
        key = (stage, tuple(sorted(defines.items())))
        if key not in self.programs:
            root = glsl_root()
            prog = compile_program(self.ctx, root / "post" / "fullscreen.vert",
                                   root / "trace" / f"{stage}.frag", defines)
            self.programs[key] = FullScreenPass(self.ctx, None, program=prog)
            self._defines[self.programs[key]] = (stage, defines)
        return self.programs[key]

    def escaped(self, program: FullScreenPass) -> FullScreenPass:
        """``program`` compiled for pixels whose eye rays miss the scene (ESCAPED:
        glsl/trace/scene.glsl): their sky, without a traversal."""
        stage, defines = self._defines[program]
        return self._compiled(stage, {**defines, "ESCAPED": None})

    def bind(self, scene, state: FrameState, program: FullScreenPass, more_rows=None) -> None:
        """The scene's textures, instances and lights for ``program``, and the camera."""
        self._placed = self.instances(scene, state, more_rows)
        self.lights_ubo.write(state.lights_block)
        self.lights_ubo.bind_to_uniform_block(BLOCKS["Lights"])
        self._bind_program(state, program)

    def _bind_program(self, state: FrameState, program: FullScreenPass) -> None:
        unbounded, has_tlas, single = self._placed
        prog = program.program
        images = self.images  # (as ``program`` compiled it)
        for name in ("tris", "tri_index", "vertices", "nodes", "instances", "tlas",
                     "textures"):
            if images and f"u_{name}" in IMAGES:
                self.textures[name].bind_to_image(IMAGES[f"u_{name}"], read=True,
                                                  write=False)
            else:
                self.textures[name].use(location=unit(f"u_{name}"))
        prog.set("u_unbounded", unbounded, strict=False)
        prog.set("u_has_tlas", has_tlas, strict=False)
        prog.set("u_single", single, strict=False)
        prog.set("u_inv_view_projection", np.linalg.inv(state.view_projection()), strict=False)
        prog.set("u_cone", pixel_cone(state), strict=False)
        prog.set("u_viewport", (float(state.width), float(state.height)))

    def draw_colour(self, scene, state: FrameState, program: FullScreenPass, textures=None,
                    more_rows=None, views=None, **uniforms) -> None:
        """Draw a colour ``program`` over the scene into the bound target, with the
        environment, ``textures`` ({sampler: texture, or the name of one of the scene's
        textures, made while binding}) and ``uniforms`` (those it lacks skipped; a callable
        is asked for its value after binding, when ``more_rows`` has made it). ``views``:
        the view-projection matrices of the samples stacked in the target (default:
        ``state``'s alone).

        Pixels whose eye rays all miss the scene's bounds are drawn by the program's
        escaped variant (``escaped``), the program itself only over the rectangle
        (``scene_rect``) that holds the rest: llvmpipe runs every line of a program in all
        8 lanes of a group whichever way their branches go, so a pixel of sky beside an
        object paid for the object's whole traversal and shading."""
        self.bind(scene, state, program, more_rows)
        textures = {k: self.textures[v] if isinstance(v, str) else v
                    for k, v in (textures or {}).items()}
        values = {}
        for name, value in uniforms.items():
            value = value() if callable(value) else value
            if value is None:
                continue
            if not isinstance(value, (int, bytes)):  # a vector: ints stay ints (ivec)
                value = tuple(v if isinstance(v, int) else float(v) for v in value)
            values[name] = value
        one_colour = constant_sky(state)
        if one_colour is not None:
            values["u_sky_color"] = tuple(float(c) for c in one_colour)
        elif state.environment is not None:
            textures["u_environment"] = self.cache.cube(state.environment)
        rect = scene_rect(self.world_box, views or [state.view_projection()],
                          state.width, state.height) if RayScene.use_rects else None
        self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND)
        if rect is None:
            _set_uniforms(program, values)
            program.draw(textures)
        else:
            sky = self.escaped(program)
            self._bind_program(state, sky)
            _set_uniforms(sky, values)
            sky.draw(textures)
            if rect[2] > 0 and rect[3] > 0:
                _set_uniforms(program, values)
                self._scissored(program, textures, rect, state.height)
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def _scissored(self, program: FullScreenPass, textures, rect, height: int) -> None:
        """``program`` over ``rect`` (x, y, w, h) of each picture stacked in the viewport
        (samples drawn in parts of ``height`` rows: glsl/trace/path.frag), within the
        scissor already set (a strip of a sample: facet.render.sequence), which is kept."""
        fbo = self.ctx.fbo
        vx, vy, _, vh = fbo.viewport
        before = self.ctx.scissor
        x, y, w, h = rect
        for part in range(max(1, vh // height)):
            box = _overlap((vx + x, vy + part * height + y, w, h), before)
            if box is not None:
                self.ctx.scissor = box
                program.draw(textures)
        self.ctx.scissor = None if tuple(before) == (0, 0, *fbo.size) else before

    def draw_exact(self, scene, state: FrameState, aux, defines=(), more_rows=None) -> None:
        """The exact channels ``aux`` at pixel centres into the bound target (cleared), by
        glsl/trace/primary.frag with the materials read as ``defines`` say."""
        program = self.program("primary", state, False, aux, extra=defines)
        self.bind(scene, state, program, more_rows)
        prog = program.program
        camera = state.camera
        prog.set("u_eye_world", tuple(float(v) for v in camera.eye), strict=False)
        prog.set("u_forward", tuple(float(v) for v in camera.forward), strict=False)
        self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND)
        # (pixels whose rays miss the scene's bounds stay cleared: nothing hit)
        rect = scene_rect(self.world_box, [state.view_projection()], state.width,
                          state.height) if RayScene.use_rects else None
        if rect is None:
            program.draw()
        elif rect[2] > 0 and rect[3] > 0:
            self._scissored(program, None, rect, state.height)
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def release(self) -> None:
        for program in self.programs.values():
            program.release()
        self.programs.clear()
        self._defines.clear()
        for tex in self.textures.values():
            tex.release()
        self.textures.clear()
        self.lights_ubo.release()
        for block in self.blocks.values():
            block.release()

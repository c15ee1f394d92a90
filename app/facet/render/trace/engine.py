"""The ray tracer as an engine (facet.render.engine) on the GPU: uploads what
facet.render.trace.pack lays out, and draws one supersample of traced colour
(glsl/trace/trace.frag) or the exact channels (glsl/trace/primary.frag) as full-screen
passes, on any GL 3.3 context (llvmpipe and the viewer's window included). Its colour is
always a sum of samples (msaa:N becomes N rays per pixel); what it does not honour it names
(``unsupported``).

Meshes are packed once per Mesh (kept while it lives) and the scene's geometry textures are
uploaded again only when the set of meshes changes; instances and the top level are packed
per call (per supersample when objects move, for motion blur): a turntable or a moving
camera never rebuilds a mesh's hierarchy.
"""

from __future__ import annotations

import weakref

import numpy as np

from ...gl.bindings import BLOCKS, unit
from ...gl.fullscreen import FullScreenPass
from ...gl.glsl_source import glsl_root
from ...gl.shaders import compile_program
from ...gl.targets import aux_locations
from ...scene.option_values import DISTRIBUTED_AA
from ...scene.options import RenderOptions, parse_aa
from ...scene.pbr import PbrMaterial
from ...scene.scene import MAX_LIGHTS
from ..antialias import accumulation
from ..engine import Engine, grid_or_jittered
from ..materials import as_pbr, feature_lines, phong_color
from ..shading import SHADING_MODELS
from ..state import FrameState, pack_lights
from . import pack
from .sprites import sprite_lines, sprite_radii

# Below this roughness a glTF material reflects the scene (glsl/trace/shade.glsl's).
TRACED_ROUGHNESS = 0.6

MAX_TEXTURE_LAYER = 2048  # materials' images are resized to at most this square


class TraceEngine(Engine):
    """The ray tracer of one renderer: programs, the scene's textures, and the draws."""

    name = "trace"

    def __init__(self, ctx, cache):
        super().__init__(ctx, cache)
        self.programs: dict[tuple, FullScreenPass] = {}
        self._meshes = weakref.WeakKeyDictionary()  # Mesh -> pack.MeshData
        self._sprite_sizes: dict[int, int | None] = {}  # id(points) -> its radii's hash
        self._geometry_key: tuple | None = None
        self._geometry_refs: list = []  # the meshes of the uploaded geometry (alive)
        self._roots: dict[int, int] = {}
        self._first_tri: dict[int, int] = {}
        self._textures: dict[str, object] = {}
        self._layers_key: tuple | None = None
        self._layers: dict[int, int] = {}
        self.lights_ubo = ctx.buffer(reserve=len(pack_lights((), np.zeros(3))))
        limit = int(ctx.info["GL_MAX_TEXTURE_SIZE"])
        self.max_texels = pack.TEX_WIDTH * limit

    # -- scene data ----------------------------------------------------------------------
    def _upload(self, name: str, rows: np.ndarray, dtype: str = "f4") -> None:
        image = pack.to_texels(rows)
        old = self._textures.pop(name, None)
        if old is not None:
            old.release()
        tex = self.ctx.texture((pack.TEX_WIDTH, image.shape[0]), 4, image.tobytes(),
                               dtype=dtype)
        tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
        self._textures[name] = tex

    def _geometry(self, scene, state) -> None:
        """Upload every mesh's triangles and hierarchy when the set of meshes changed (or,
        for points and lines sized in pixels, their radii: facet.render.trace.sprites)."""
        meshes = list({id(o.mesh): o.mesh for o in scene.objects if o.shape is None}.values())
        framed = {id(o.mesh) for o in scene.objects if o.shape is None and self._tangents(o)}
        radii = {id(o.mesh): sprite_radii(o, state.camera, state.width, state.height)
                 for o in scene.objects if o.mesh.kind != "mesh"}
        sized = {k: hash(r.tobytes()) for k, r in radii.items()}
        key = tuple((id(m), id(m) in framed, sized.get(id(m))) for m in meshes)
        if key == self._geometry_key and "tris" in self._textures:
            return
        data = []
        for mesh in meshes:
            cached = self._meshes.get(mesh)
            if cached is None or (id(mesh) in framed and not cached.has_tangents) or \
                    self._sprite_sizes.get(id(mesh)) != sized.get(id(mesh)):
                self._meshes[mesh] = pack.mesh_data(mesh, id(mesh) in framed,
                                                    radii.get(id(mesh)))
                self._sprite_sizes[id(mesh)] = sized.get(id(mesh))
            data.append(self._meshes[mesh])
        if not data:  # shapes only: one dummy triangle keeps every sampler valid
            from ...scene.mesh import Mesh

            data = [pack.mesh_data(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))]
        geo = pack.pack_geometry(data, self.max_texels)
        self._upload("tris", geo["tris"])
        self._upload("tri_index", geo["index"], "i4")
        self._upload("vertices", geo["vertices"])
        self._upload("nodes", geo["nodes"])
        self._roots = {id(m): int(r) for m, r in zip(meshes, geo["root"], strict=False)}
        self._first_tri = {id(m): int(f) for m, f in zip(meshes, geo["first_tri"],
                                                         strict=False)}
        self._geometry_key, self._geometry_refs = key, meshes

    def _tangents(self, obj) -> bool:
        """Whether ``obj``'s mesh needs tangent frames here: for a normal map."""
        m = obj.material
        return isinstance(m, PbrMaterial) and m.normal_mapped

    def _layer_requests(self, scene, pbr_shading: bool) -> list:
        """(texture, mode) for each image the tracer samples (modes: facet.render.trace
        .pack): a Phong material's image as given, a metallic-roughness material's slots
        (colour decoded to linear, data as stored) when it is shaded by that model
        (``pbr_shading``), else its base colour image as its Phong stand-in's."""
        out = []
        for obj in scene.objects:
            m = obj.material
            if isinstance(m, PbrMaterial) and pbr_shading:
                out += [(slot.texture, pack.slot_mode(name, slot)) for name, slot in m.slots.items()
                        if name in pack.PATH_SLOTS]
            elif m.texture is not None:
                out.append((m.texture, pack.AS_GIVEN))
        return out

    def _texture_layers(self, scene, srgb: bool, pbr_shading: bool = True) -> None:
        """The materials' images as layers of one texture array (resized to one size),
        keyed (id(texture), mode): decoded to linear for LINEAR, and for AS_GIVEN in the
        sRGB colour mode; DATA as stored."""
        requests = list({(id(t), c): (t, c)
                         for t, c in self._layer_requests(scene, pbr_shading)}.values())
        key = (tuple((id(t), c) for t, c in requests), srgb)
        if key == self._layers_key:
            return
        old = self._textures.pop("textures", None)
        if old is not None:
            old.release()
        modes = [c.removesuffix(pack.NEAREST) for _, c in requests]
        colour = [c == pack.LINEAR or (c == pack.AS_GIVEN and srgb) for c in modes]
        if requests:
            side = min(max(max(t.pixels.shape[:2]) for t, _ in requests), MAX_TEXTURE_LAYER)
            layers = [_layer(t.pixels, side, decode, c.endswith(pack.NEAREST))
                      for (t, c), decode in zip(requests, colour, strict=True)]
            if any(x.dtype == np.float16 for x in layers):  # one array, one type
                layers = [x if x.dtype == np.float16 else (x / 255.0).astype(np.float16)
                          for x in layers]
            # Rows flipped: GL's first row is v = 0, the image's bottom (as gl.resources).
            data = np.ascontiguousarray(np.stack(layers)[:, ::-1])
            dtype = "f2" if data.dtype == np.float16 else "f1"
        else:
            side, data, dtype = 1, np.full((1, 1, 1, 4), 255, np.uint8), "f1"
        tex = self.ctx.texture_array((side, side, len(data)), 4, data.tobytes(), dtype=dtype)
        tex.build_mipmaps()
        tex.filter = (self.ctx.LINEAR_MIPMAP_LINEAR, self.ctx.LINEAR)
        self._textures["textures"] = tex
        self._layers = {(id(t), c): i for i, (t, c) in enumerate(requests)}
        self._layers_key = key

    # -- the engine interface (facet.render.engine) ----------------------------------------
    def sampling(self, opts, scene, camera, preview: bool):
        """Always a sum: msaa:N is N rays per pixel (none: one through the centre); a
        window's moving view one ray through each pixel's centre."""
        if preview:
            return parse_aa("ssaa:grid:1")
        aa = accumulation(opts.aa, scene, camera, opts.shadows_on)
        if aa is None and self.name == "trace" and self.glossy_reflections(scene, opts.shading):
            aa = parse_aa(DISTRIBUTED_AA)  # the reflections' tilts are a sum over samples
        return aa if aa is not None else grid_or_jittered(opts.aa.msaa or 1)

    @staticmethod
    def glossy_reflections(scene, shading: str) -> bool:
        """Whether a glTF material traces a blurred reflection of the scene
        (glsl/trace/trace.frag: roughness below TRACED_ROUGHNESS, above 0)."""
        return shading in ("auto", "pbr") and any(
            isinstance(o.material, PbrMaterial) and 0 < o.material.roughness < TRACED_ROUGHNESS
            and not o.material.unlit for o in scene.objects)

    def prepare(self, scene, state: FrameState, opts=None, aa=None) -> FrameState:
        """Geometry and textures for this scene (uploaded only when they changed)."""
        self._geometry(scene, state)
        self._texture_layers(scene, state.srgb, _pbr_shading(state))
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        self.draw(scene, state, background, opts.max_depth, opts.shadows_on)

    def unsupported(self, opts, scene) -> list[str]:
        """What the tracer does not draw as asked (each a warning line)."""
        lines = []
        if opts.wireframe:
            lines.append("the ray tracer draws no wireframe overlay")
        if opts.shading == "gouraud":
            lines.append("the ray tracer shades gouraud as phong (per pixel)")
        if opts.cull == "on":
            lines.append("the ray tracer culls no back faces for cull = on (only "
                         "single-sided glTF materials lose theirs)")
        if opts.pcf != RenderOptions.pcf:  # given: the default filters nothing here
            lines.append("pcf filters shadow maps; the ray tracer's shadow rays are exact")
        if opts.environment is not None and opts.shading in ("auto", "pbr") and any(
                isinstance(o.material, PbrMaterial) for o in scene.objects):
            lines.append("the ray tracer lights metallic-roughness materials by the ambient "
                         "term, not by the environment (the rasterizer and the path tracer "
                         "do)")
        return lines + sprite_lines(scene, "the ray tracer") + feature_lines(scene, _dropped,
                                                                      "the ray tracer")

    def _instances(self, scene, state: FrameState) -> tuple[int, bool, int]:
        """Upload the placed objects: (unbounded count, has a top level, the single
        bounded instance without one or -1)."""
        boxes = {id(o.mesh): self._meshes[o.mesh].bounds for o in scene.objects
                 if o.mesh.kind != "mesh" and o.shape is None}
        rows, tlas, unbounded, ordered = pack.pack_instances(
            scene.objects, self._roots, lambda m: phong_color(m, state), self._layers, boxes)
        self._more_rows(rows, ordered)
        self._upload("instances", rows.reshape(-1, 4))
        self._upload("tlas", tlas.reshape(-1, 4) if tlas is not None else
                     np.zeros((4, 4), np.float32))
        single = unbounded if tlas is None and len(rows) > unbounded else -1
        return unbounded, tlas is not None, single

    def _material_defines(self, scene, state) -> tuple:
        """Defines of how materials are read: PBR_SLOTS when some are metallic-roughness
        and shaded by that model (glsl/trace/shade.glsl's shade_pbr; shading "auto" or
        "pbr"; by their Phong stand-ins otherwise)."""
        pbr = _pbr_shading(state) and any(isinstance(o.material, PbrMaterial)
                                          for o in scene.objects)
        if not pbr:
            return ()
        # shadow rays through BLEND coverage and MASK cut-outs, texel by texel
        alpha = any(as_pbr(o.material).alpha_mode != "OPAQUE" for o in scene.objects)
        return ("PBR_SLOTS",) + (("ALPHA_SHADOWS",) if alpha else ())

    def _more_rows(self, rows: np.ndarray, ordered: list) -> None:
        """Add to the instance ``rows`` of the ``ordered`` objects (the tracer: nothing)."""

    def _more_textures(self) -> dict:
        """Scene textures of a colour program beyond _bind's: name -> (texture, unit)."""
        return {}

    # -- drawing -------------------------------------------------------------------------
    def _program(self, stage: str, state: FrameState, shadows: bool, aux=(),
                 secondary: bool = False, extra=()) -> FullScreenPass:
        # The lights are looped over at run time (u_light_count), not unrolled per light
        # set as the rasterizer's are: each unrolled light would inline a whole shadow
        # ray's traversal, and one program serves every light set.
        # The tracer shades every material by the Phong equation (a PbrMaterial through
        # its Phong stand-ins, facet.scene.pbr).
        model = "phong" if state.shading in ("auto", "pbr") else state.shading
        defines = {SHADING_MODELS[model].define: None, "MAX_LIGHTS": MAX_LIGHTS,
                   **pack.layout_defines()}
        flags = {"SHADOWS": shadows and stage == "trace", "COLOR_SRGB": state.srgb,
                 "LINEAR_OUT": state.linear_out,
                 "SECONDARY": secondary and stage == "trace",
                 "HAS_ENVIRONMENT": state.environment is not None and stage != "primary"}
        defines.update({k: None for k, on in flags.items() if on})
        defines.update({k: None for k in extra})
        for name, location in aux_locations(aux).items():
            defines[f"OUT_{name.upper()}"] = location
        key = (stage, tuple(sorted(defines.items())))
        if key not in self.programs:
            root = glsl_root()
            prog = compile_program(self.ctx, root / "post" / "fullscreen.vert",
                                   root / "trace" / f"{stage}.frag", defines)
            self.programs[key] = FullScreenPass(self.ctx, None, program=prog)
        return self.programs[key]

    def _bind(self, scene, state: FrameState, program: FullScreenPass) -> None:
        unbounded, has_tlas, single = self._instances(scene, state)
        self.lights_ubo.write(state.lights_block)
        self.lights_ubo.bind_to_uniform_block(BLOCKS["Lights"])
        prog = program.program
        for name in ("tris", "tri_index", "vertices", "nodes", "instances", "tlas",
                     "textures"):
            self._textures[name].use(location=unit(f"u_{name}"))
        prog.set("u_unbounded", unbounded, strict=False)
        prog.set("u_has_tlas", has_tlas, strict=False)
        prog.set("u_single", single, strict=False)
        inv = np.linalg.inv(state.view_projection())
        prog.set("u_inv_view_projection", inv)
        prog.set("u_viewport", (float(state.width), float(state.height)))

    def draw(self, scene, state: FrameState, background, max_depth: int,
             shadows: bool) -> None:
        """Trace one supersample (``state``'s camera, jitter, lights, gloss tilt) into the
        bound target: premultiplied colour and coverage."""
        # Reflection, refraction and transparency need the ray stack; without them a
        # simpler program runs (glsl/trace/trace.frag, SECONDARY).
        secondary = any(o.material.reflectivity > 0 or o.material.opacity < 1 or
                        getattr(o.material, "alpha_mode", "") in ("MASK", "BLEND") or
                        getattr(o.material, "transmission", 0.0) > 0 or
                        getattr(o.material, "roughness", 1.0) < TRACED_ROUGHNESS
                        for o in scene.objects)
        program = self._program("trace", state, shadows, secondary=secondary,
                                extra=self._material_defines(scene, state))
        self.draw_colour(scene, state, program, u_background=background,
                         u_max_depth=int(max_depth), u_gloss_jitter=state.gloss_jitter)

    def draw_colour(self, scene, state: FrameState, program: FullScreenPass,
                    **uniforms) -> None:
        """Draw a colour ``program`` (the tracer's, the path tracer's) over the scene into
        the bound target, with the environment and ``uniforms`` (those it lacks skipped)."""
        self._bind(scene, state, program)
        for name, value in uniforms.items():
            if not isinstance(value, int):  # a vector: ints stay ints (ivec uniforms)
                value = tuple(v if isinstance(v, int) else float(v) for v in value)
            program.program.set(name, value, strict=False)
        textures = self._more_textures()
        if state.environment is not None:
            textures["u_environment"] = self.cache.cube(state.environment)
        self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND)
        program.draw(textures)
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def draw_exact(self, scene, state: FrameState, aux, albedo: bool = False) -> None:
        """The exact channels ``aux`` at pixel centres into the bound target (cleared);
        ``albedo``: the first hit's albedo into its colour too (the denoiser's guide)."""
        program = self._program("primary", state, False, aux,
                                extra=self._material_defines(scene, state) +
                                (("ALBEDO",) if albedo else ()))
        self._bind(scene, state, program)
        prog = program.program
        camera = state.camera
        prog.set("u_eye_world", tuple(float(v) for v in camera.eye), strict=False)
        prog.set("u_forward", tuple(float(v) for v in camera.forward), strict=False)
        self.ctx.disable(self.ctx.DEPTH_TEST | self.ctx.BLEND)
        program.draw()
        self.ctx.enable(self.ctx.DEPTH_TEST)

    def release(self) -> None:
        for program in self.programs.values():
            program.release()
        self.programs.clear()
        for tex in self._textures.values():
            tex.release()
        self._textures.clear()
        self.lights_ubo.release()


def _layer(pixels: np.ndarray, side: int, decode: bool, nearest: bool = False) -> np.ndarray:
    """(side, side, 4) one layer of the texture array: uint8 as stored, or, for an image
    decoded to linear, float16 decoded *before* it is resized (filtering sRGB-encoded bytes
    would darken fine patterns: glTF's TextureLinearInterpolationTest). ``nearest``:
    resized by repeating texels (a nearest-filtered image: glsl/trace/material.glsl reads
    its texels' centres)."""
    from PIL import Image

    from ...image.colorspace import srgb_to_linear

    resample = Image.Resampling.NEAREST if nearest else Image.Resampling.LANCZOS
    if not decode:
        if pixels.shape[:2] == (side, side):
            return pixels
        return np.asarray(Image.fromarray(pixels).resize((side, side), resample))
    values = (np.arange(256) / 255.0).astype(np.float32)[pixels]
    values[..., :3] = srgb_to_linear(np.arange(256) / 255.0).astype(np.float32)[
        pixels[..., :3]]
    if pixels.shape[:2] != (side, side):
        values = np.stack([np.asarray(Image.fromarray(values[..., k], "F").resize(
            (side, side), resample)) for k in range(4)], -1)
    return np.clip(values, 0.0, None).astype(np.float16)


def _pbr_shading(state) -> bool:
    """Whether metallic-roughness materials are shaded by their model (else by their
    Phong stand-ins, as the rasterizer's phong model draws them)."""
    return state.shading in ("auto", "pbr")


def _dropped(m) -> list[str]:
    """The material features of ``m`` the tracer does not draw (a glTF material is shaded
    by the rasterizer's BRDF with its texture slots, glsl/trace/shade.glsl's shade_pbr; its
    surroundings reach it only as the ambient term and shadows)."""
    out = []
    if m.shader is not None:
        out.append("users' mesh shaders (the material's Phong terms are traced)")
    if not isinstance(m, PbrMaterial):
        return out
    return out

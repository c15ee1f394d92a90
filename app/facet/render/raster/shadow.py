"""Shadow maps for all three light kinds, in one depth atlas of square tiles.

* directional: one orthographic tile along the light, fitted to the scene's bounding
  sphere, so the whole scene casts and receives;
* spot: one perspective tile from the light along its axis, as wide as the outer cone;
* point: a cube map as six perspective tiles (+x, -x, +y, -y, +z, -z), each a little wider
  than 90 degrees so the filter has texels across the seams; the shader picks the face by
  the major axis of the light-to-point vector.

The maps are drawn once per ``render`` call (supersampling and the colour passes reuse them).
Transparent objects cast partial shadows: a dither mask keeps ``opacity`` of their texels in
the map (glsl/shadow/depth.frag), which the PCF filter turns into shadow of that strength;
clear glass (KHR_materials_transmission) casts what it does not let through
(facet.render.materials.shadow_opacity).
The lighting side (bias, normal offset, PCF) is glsl/lib/shadows.glsl.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...geometry import transforms as T
from ...gl.bindings import unit
from ...gl.glsl_source import glsl_root
from ...gl.shaders import compile_program
from ...options.render import PCF_CHOICES
from ...scene.light import DirectionalLight, PointLight, SpotLight
from ...scene.scene import Scene
from ..material_record import record_defines
from .instancing import batches
from .skinning import POSE_DEFINES, JointRows, bind_pose, gpu_pose, pose_buffers
from .slots import record_of

TILE = 1024  # shadow map resolution per tile
ATLAS_COLUMNS = 8  # tiles per atlas row (TILE x 8 = 8192 px wide, within GL limits)
SHADOW_KINDS = (DirectionalLight, SpotLight, PointLight)
CUBE_FOV = 95.0  # degrees per cube face (90 plus a margin for PCF at the seams)
# Cube faces: looking direction and up vector, in the order the shader indexes them.
CUBE_FACES = (((1, 0, 0), (0, -1, 0)), ((-1, 0, 0), (0, -1, 0)), ((0, 1, 0), (0, 0, 1)),
              ((0, -1, 0), (0, 0, -1)), ((0, 0, 1), (0, -1, 0)), ((0, 0, -1), (0, -1, 0)))
# [-1, 1] clip space -> [0, 1] texture space.
TO_UNIT = T.compose(T.scale(0.5), T.translate((0.5, 0.5, 0.5)))


def casts_shadow(light) -> bool:
    return isinstance(light, SHADOW_KINDS) and getattr(light, "cast_shadows", True)


def light_view_projections(light, bounds) -> list[tuple[np.ndarray, tuple[float, float]]]:
    """Per tile: (4x4 world -> light clip space, (texel size at distance 0, growth per unit
    distance)); one tile, or six for a point light's cube."""
    if isinstance(light, PointLight):
        return [_point_face(light, forward, up, bounds) for forward, up in CUBE_FACES]
    return [_single(light, bounds)]


def _point_face(light, forward, up, bounds):
    eye = np.asarray(light.position, dtype=np.float64)
    view = T.look_at(eye, eye + np.asarray(forward, dtype=np.float64), up)
    b = np.asarray(bounds, dtype=np.float64)
    corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
    far = max(float(np.max(np.linalg.norm(corners - eye, axis=1))), 1e-3) * 1.05
    proj = T.perspective(CUBE_FOV, 1.0, far / 100.0, far)
    return proj @ view, (0.0, 2.0 * np.tan(np.radians(CUBE_FOV) / 2.0) / TILE)


def _single(light, bounds):
    b = np.asarray(bounds, dtype=np.float64)
    center = b.mean(axis=0)
    radius = max(float(np.linalg.norm(b[1] - b[0])) / 2.0, 1e-6)
    d = np.asarray(light.direction, dtype=np.float64)
    up = (0.0, 1.0, 0.0) if abs(d[1]) < 0.99 else (1.0, 0.0, 0.0)
    corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
    if isinstance(light, DirectionalLight):
        # The tightest box around the scene's corners as the light sees them, so every
        # shadow texel falls on the scene.
        view = T.look_at(center - d * 2.0 * radius, center, up)
        local = corners @ view[:3, :3].T + view[:3, 3]
        lo, hi = local.min(axis=0), local.max(axis=0)
        pad = 0.01 * radius
        proj = T.orthographic(lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad,
                              max(-hi[2] - pad, 1e-4), -lo[2] + pad)
        extent = max(hi[0] - lo[0], hi[1] - lo[1]) + 2 * pad
        return proj @ view, (extent / TILE, 0.0)
    eye = np.asarray(light.position, dtype=np.float64)
    view = T.look_at(eye, eye + d, up)
    depth = -(corners @ view[:3, :3].T + view[:3, 3])[:, 2]  # along the spot's axis
    far = max(float(depth.max()), 1e-3) * 1.05
    # A near plane close to the light wastes the depth buffer's precision (perspective depth
    # is ~1/z): start at the nearest corner in front of the light, at least far / 20.
    ahead = depth[depth > 0]
    near = max(float(ahead.min()) * 0.9 if ahead.size else 0.0, far / 20.0)
    fov = min(2.0 * light.outer_angle + 2.0, 170.0)
    proj = T.perspective(fov, 1.0, near, far)
    return proj @ view, (0.0, 2.0 * np.tan(np.radians(fov) / 2.0) / TILE)


@dataclass(frozen=True, eq=False)
class ShadowData:
    """One frame's shadow maps as the lighting programs read them."""

    atlas: object  # the depth atlas texture (compare mode: sampler2DShadow)
    slots: tuple[int, ...]  # per light: its first tile (= matrix index), or -1
    matrices: np.ndarray  # (tiles, 4, 4) float32: world -> atlas texture space
    texels: np.ndarray  # (lights, 4) float32: texel size at distance 0, growth per unit
    tiles: int
    pcf: int  # filter kernel radius in texels

    def bind(self, prog) -> None:
        """Point a lighting program at the atlas and the lights' shadow matrices."""
        self.atlas.use(location=unit("u_shadow_atlas"))
        if "u_shadow_matrix" in prog._active:
            member = prog.gl["u_shadow_matrix"]
            # The linker may trim the array to the tiles the program can reach.
            matrices = self.matrices[:member.array_length]
            member.write(np.ascontiguousarray(matrices.transpose(0, 2, 1)).tobytes())
        prog.set_array("u_shadow_texel", self.texels)


class ShadowMaps:
    """The depth atlas of one renderer and the program that fills it."""

    def __init__(self, ctx, cache):
        self.ctx, self.cache = ctx, cache
        # (MASK cut-outs, instanced, skinned, 8 influences) -> the depth program, each
        # made on first use.
        self._programs: dict[tuple, object] = {}
        self.joints = JointRows(ctx)
        self.atlas = None
        self.fbo = None
        self.tiles = 0

    def _grid(self) -> tuple[int, int]:
        cols = min(self.tiles, ATLAS_COLUMNS)
        return cols, -(-self.tiles // cols)

    def _ensure(self, tiles: int) -> None:
        if tiles <= self.tiles:
            return
        self._release_atlas()
        self.tiles = tiles
        cols, rows = self._grid()
        self.atlas = self.ctx.depth_texture((TILE * cols, TILE * rows))
        self.atlas.compare_func = "<="  # sampler2DShadow: lit where the map is not nearer
        self.atlas.filter = (self.ctx.LINEAR, self.ctx.LINEAR)  # 2x2 PCF in hardware
        self.atlas.repeat_x = self.atlas.repeat_y = False
        self.fbo = self.ctx.framebuffer(depth_attachment=self.atlas)

    def draw(self, scene: Scene, pcf: int = 1, sample: int = 0) -> ShadowData | None:
        """Fill the atlas for the scene's lights; the uniforms and defines for lighting.
        ``pcf``: the filter's kernel radius in texels (``PCF_CHOICES``). ``sample``: which
        shift of the transparent casters' dither mask (glsl/shadow/depth.frag) to use."""
        if pcf not in PCF_CHOICES:
            raise InputError(f"pcf must be one of {PCF_CHOICES} (kernel radius), got {pcf!r}")
        casters = [i for i, light in enumerate(scene.lights) if casts_shadow(light)]
        if not casters or not scene.objects:
            return None
        bounds = _caster_bounds(scene)
        faces = {i: light_view_projections(scene.lights[i], bounds) for i in casters}
        self._ensure(sum(len(f) for f in faces.values()))
        slots = [-1] * len(scene.lights)  # per light: its first tile (= matrix index)
        matrices = np.tile(np.eye(4, dtype=np.float32), (max(self.tiles, 1), 1, 1))
        texels = np.zeros((len(scene.lights), 4), np.float32)
        shift = (sample % 4, sample // 4 % 4)
        for prog in self._programs.values():
            prog.set("u_dither_shift", shift)
        # Points and lines cast no shadow maps (RasterEngine.unsupported says so).
        items = batches([o for o in scene.objects if o.mesh.kind == "mesh"], lambda o: False)
        records: dict[int, np.ndarray] = {}  # per material: its record, packed once a pass

        def record(m):
            if id(m) not in records:
                records[id(m)] = record_of(m)
            return records[id(m)]

        self.fbo.use()
        self.fbo.clear(depth=1.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        tile = 0
        cols, rows = self._grid()
        for i in casters:
            slots[i] = tile
            for vp, (texel0, growth) in faces[i]:
                col, row = tile % cols, tile // cols
                self.fbo.viewport = (col * TILE, row * TILE, TILE, TILE)
                for item in items:  # objects sharing mesh and material: one draw
                    group = item if isinstance(item, list) else None
                    obj = item if group is None else item[0]
                    pose = (0, False) if group is not None else gpu_pose(obj.mesh)
                    prog = self._program_for(obj, group is not None, shift, *pose)
                    prog.set_array("u_material", record(obj.material))
                    if any(pose):  # deformed on the GPU, from the rest mesh
                        buffers = pose_buffers(self.cache, obj.mesh, self.ctx)
                        bind_pose(prog, obj.mesh, buffers, self.joints)
                    else:
                        buffers = self.cache.buffers(obj.mesh)
                    if group is None:
                        prog.set("u_light_mvp", vp @ obj.transform)
                        buffers.vao(self.ctx, prog.gl).render()
                        continue
                    mvp = vp @ np.stack([o.transform for o in group])
                    per_instance = mvp.transpose(0, 2, 1).reshape(-1, 16).astype(np.float32)
                    buffers.draw_instances(self.ctx, prog.gl, per_instance,
                                           ("16f /i", "in_light_mvp"))
                # World -> this tile of the atlas: clip [-1, 1] -> [0, 1] -> (col, row).
                to_tile = T.compose(TO_UNIT, T.scale((1.0 / cols, 1.0 / rows, 1.0)),
                                    T.translate((col / cols, row / rows, 0.0)))
                matrices[tile] = (to_tile @ vp).astype(np.float32)
                texels[i] = (texel0, growth, 0.0, 0.0)
                tile += 1
        self.fbo.viewport = (0, 0, TILE * cols, TILE * rows)
        return ShadowData(self.atlas, tuple(slots), matrices, texels, self.tiles, pcf)

    def _release_atlas(self) -> None:
        if self.fbo is not None:
            self.fbo.release()
            self.atlas.release()
        self.fbo = self.atlas = None
        self.tiles = 0

    def _program_for(self, obj, instanced: bool, shift, skin: int = 0, morph: bool = False):
        """The depth program for ``obj`` (drawn alone or instanced; skinned with ``skin``
        influences, morphed), its cut-out image bound (MASK materials)."""
        key = (_masked(obj), instanced, skin > 0, skin > 4, morph)
        prog = self._programs.get(key)
        if prog is None:
            root = glsl_root()
            names = ("ALPHA_MASK", "INSTANCED", "SKINNED", "SKIN_8", "MORPHED")
            defines = {name: None for name, on in zip(names, key, strict=True) if on}
            defines.update(record_defines())  # (glsl/mesh/record.glsl)
            if skin or morph:
                defines.update(POSE_DEFINES)
            prog = self._programs[key] = compile_program(
                self.ctx, root / "shadow" / "depth.vert", root / "shadow" / "depth.frag",
                defines)
            prog.set("u_dither_shift", shift)
        if not key[0]:
            return prog
        slot = obj.material.base_color_texture
        self.cache.texture(slot.texture, False).use(location=unit("u_texture"))
        return prog

    def release(self) -> None:
        self._release_atlas()
        for prog in self._programs.values():
            self.cache.forget_program(prog.gl)
            prog.release()
        self._programs.clear()
        self.joints.release()


def _masked(obj) -> bool:
    """A glTF MASK material whose cut-outs come from an image (and a mesh with uvs)."""
    m = obj.material
    return (getattr(m, "alpha_mode", "") == "MASK" and m.base_color_texture is not None
            and obj.mesh.uvs is not None)


def _caster_bounds(scene) -> np.ndarray:
    """The scene's bounds as the shadow maps fit them: a skinned pose's loose box
    (facet.scene.skinned), so shadows do not skin its vertices on the CPU."""
    if not any(hasattr(o.mesh, "loose_bounds") for o in scene.objects):
        return scene.bounds
    boxes = []
    for o in scene.objects:
        if o.infinite and len(scene.objects) > 1:
            continue
        b = getattr(o.mesh, "loose_bounds", None)
        b = o.mesh.bounds if b is None else b
        corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
        w = corners @ o.transform[:3, :3].T + o.transform[:3, 3]
        boxes.append((w.min(axis=0), w.max(axis=0)))
    lo, hi = zip(*boxes, strict=True)
    return np.stack([np.min(lo, axis=0), np.max(hi, axis=0)])


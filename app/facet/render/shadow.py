"""Shadow maps for directional and spot lights, in one depth atlas (one tile per light).

* directional: an orthographic frustum along the light, fitted to the scene's bounding
  sphere, so the whole scene casts and receives;
* spot: a perspective frustum from the light along its axis, as wide as the outer cone.

The maps are drawn once per ``render`` call (supersampling and the colour passes reuse them).
The lighting side (bias, normal offset, PCF) is glsl/lib/shadows.glsl.
"""

from __future__ import annotations

import numpy as np

from ..geometry import transforms as T
from ..gl.glsl_source import glsl_root
from ..gl.shaders import compile_program
from ..scene.light import DirectionalLight, SpotLight
from ..scene.scene import Scene

TILE = 2048  # shadow map resolution per light
SHADOW_KINDS = (DirectionalLight, SpotLight)
# [-1, 1] clip space -> [0, 1] texture space.
TO_UNIT = T.compose(T.scale(0.5), T.translate((0.5, 0.5, 0.5)))


def casts_shadow(light) -> bool:
    return isinstance(light, SHADOW_KINDS) and getattr(light, "cast_shadows", True)


def light_view_projection(light, bounds) -> tuple[np.ndarray, tuple[float, float]]:
    """(4x4 world -> light clip space, (texel size at distance 0, growth per distance))."""
    b = np.asarray(bounds, dtype=np.float64)
    center = b.mean(axis=0)
    radius = max(float(np.linalg.norm(b[1] - b[0])) / 2.0, 1e-6)
    d = np.asarray(light.direction, dtype=np.float64)
    up = (0.0, 1.0, 0.0) if abs(d[1]) < 0.99 else (1.0, 0.0, 0.0)
    if isinstance(light, DirectionalLight):
        eye = center - d * 2.0 * radius
        view = T.look_at(eye, center, up)
        proj = T.orthographic(-radius, radius, -radius, radius, radius * 0.5, radius * 3.5)
        return proj @ view, (2.0 * radius / TILE, 0.0)
    eye = np.asarray(light.position, dtype=np.float64)
    view = T.look_at(eye, eye + d, up)
    corners = np.array([[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]])
    depth = -(corners @ view[:3, :3].T + view[:3, 3])[:, 2]  # along the spot's axis
    far = max(float(depth.max()), 1e-3) * 1.05
    # A near plane close to the light wastes the depth buffer's precision (perspective depth
    # is ~1/z): start at the nearest corner in front of the light, at least far / 20.
    ahead = depth[depth > 0]
    near = max(float(ahead.min()) * 0.9 if ahead.size else 0.0, far / 20.0)
    fov = min(2.0 * light.outer_angle + 2.0, 170.0)
    proj = T.perspective(fov, 1.0, near, far)
    return proj @ view, (0.0, 2.0 * np.tan(np.radians(fov) / 2.0) / TILE)


class ShadowMaps:
    """The depth atlas of one renderer and the program that fills it."""

    def __init__(self, ctx, cache):
        self.ctx, self.cache = ctx, cache
        root = glsl_root()
        self.program = compile_program(ctx, root / "shadow" / "depth.vert",
                                       root / "shadow" / "depth.frag")
        self.atlas = None
        self.fbo = None
        self.tiles = 0

    def _ensure(self, tiles: int) -> None:
        if tiles <= self.tiles:
            return
        self._release_atlas()
        self.atlas = self.ctx.depth_texture((TILE * tiles, TILE))
        self.atlas.compare_func = "<="  # sampler2DShadow: lit where the map is not nearer
        self.atlas.filter = (self.ctx.LINEAR, self.ctx.LINEAR)  # 2x2 PCF in hardware
        self.atlas.repeat_x = self.atlas.repeat_y = False
        self.fbo = self.ctx.framebuffer(depth_attachment=self.atlas)
        self.tiles = tiles

    def draw(self, scene: Scene) -> dict | None:
        """Fill the atlas for the scene's lights; the uniforms and defines for lighting."""
        slots = [-1] * len(scene.lights)
        casters = [i for i, light in enumerate(scene.lights) if casts_shadow(light)]
        if not casters or not scene.objects:
            return None
        self._ensure(len(casters))
        n = len(scene.lights)
        matrices = np.tile(np.eye(4, dtype=np.float32), (n, 1, 1))
        texels = np.zeros((n, 4), np.float32)
        self.fbo.use()
        self.fbo.clear(depth=1.0)
        self.ctx.enable_only(self.ctx.DEPTH_TEST)
        bounds = scene.bounds
        for slot, i in enumerate(casters):
            slots[i] = slot
            vp, (texel0, growth) = light_view_projection(scene.lights[i], bounds)
            self.fbo.viewport = (slot * TILE, 0, TILE, TILE)
            for obj in scene.objects:
                self.program.set("u_light_mvp", vp @ obj.transform)
                self.cache.buffers(obj.mesh).vao(self.ctx, self.program.gl).render()
            # World -> this tile of the atlas: [-1, 1] -> [0, 1], then into column `slot`.
            tile = T.compose(TO_UNIT, T.scale((1.0 / self.tiles, 1.0, 1.0)),
                             T.translate((slot / self.tiles, 0.0, 0.0)))
            matrices[i] = (tile @ vp).astype(np.float32)
            texels[i] = (texel0, growth, 1.0 / self.tiles, 0.0)
        self.fbo.viewport = (0, 0, TILE * self.tiles, TILE)
        return {"slots": tuple(slots), "matrices": matrices, "texels": texels}

    def bind(self, prog, shadows: dict, unit: int = 1) -> None:
        """Point a lighting program at the atlas and the lights' shadow matrices."""
        self.atlas.use(location=unit)
        prog.set("u_shadow_atlas", unit, strict=False)
        if "u_shadow_matrix" in prog._active or "u_shadow_matrix[0]" in prog._active:
            prog.gl["u_shadow_matrix"].write(np.ascontiguousarray(
                shadows["matrices"].transpose(0, 2, 1)).tobytes())  # column-major for GLSL
        prog.set_array("u_shadow_texel", shadows["texels"], strict=False)

    def _release_atlas(self) -> None:
        if self.fbo is not None:
            self.fbo.release()
            self.atlas.release()
        self.fbo = self.atlas = None
        self.tiles = 0

    def release(self) -> None:
        self._release_atlas()
        self.cache.forget_program(self.program.gl)
        self.program.release()

"""The rasterizer's Gaussian splats (facet.scene.splats), drawn after the opaque and the
transparent objects, as the reference forward pass of 3D Gaussian Splatting composites them.

Under MSAA the splats are tested against the resolved (one-sample) depth of the opaque
scene: a splat's edge is smooth already, a mesh's silhouette over splats is not
anti-aliased (four times fewer blended samples: benchmarks/splats.py).

Per view, in numpy: every cloud's splats in world space (means, covariances A Sigma A^T of
the cloud's transform, kept while the cloud and its transform stay), their colours from the
SH along the direction from the camera to each mean (in the cloud's own frame), and one
order of all of them by depth along the camera axis, front to back (re-sorted and
re-coloured only when the view has moved: ``RESORT_ANGLE``, ``RESORT_MOVE``; numpy sorts a
million depths in 0.11 s on 2 cores, a GPU bitonic sort on llvmpipe in 1.1 s:
benchmarks/splats.py).
On the GPU, one instanced quad per splat (glsl/splats/splat.vert: EWA projection),
each pixel's Gaussian composited front to back by the blending into a float sum tested
against the opaque scene's depth (glsl/splats/splat.frag), then that sum over the picture
(C + T x what lies behind: meshes, the background). The reference's differences: its
transmittance stop at 1e-4 (here the last splats still add, each under 1e-4 of the
pixel); the pixels a splat reaches are its 3-sigma box (the reference tests every pixel of
the 16-pixel tiles that box touches); a splat behind the camera's near plane is left out
(the reference's: 0.2 units in front of it).
Exact channels: where the splats cover at least half a pixel and are nearer than the opaque
scene, depth is their expected depth (sum of T alpha depth / sum of T alpha) and ids their
cloud's id (with several clouds over one pixel, the weighted mean of their ids: said in a
warning line when ids are asked of a scene of several clouds).
"""

from __future__ import annotations

import numpy as np

from ...gl.fullscreen import FullScreenPass, fullscreen_vertex
from ...gl.glsl_source import glsl_root
from ...gl.shaders import compile_program

RESORT_ANGLE = 1e-3  # radians the view may turn before the splats are sorted again
RESORT_MOVE = 1e-4  # the eye's move, in units of the clouds' size, before the same
STRIDE = 14  # floats per splat: mean 3, covariance 6, colour 3 + opacity, id + 1


def scene_splats(scene) -> list:
    """The clouds placed in ``scene`` (none for a scene made before splats existed)."""
    return list(getattr(scene, "splats", ()) or ())


class _World:
    """One cloud's splats in world space, for one transform."""

    def __init__(self, obj):
        s, m = obj.splats, np.asarray(obj.transform, np.float64)
        self.key = (id(s), m.tobytes())
        linear = m[:3, :3]
        self.means = (s.means.astype(np.float64) @ linear.T + m[:3, 3]).astype(np.float32)
        cov = s.covariances(linear)
        self.cov = cov[:, [0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]].astype(np.float32)
        self.to_local = np.linalg.inv(linear)  # directions into the cloud's own frame
        self.splats, self.id = s, obj.id


class SplatPass:
    """The splats' programs, instance buffer, sums and the per-view numpy work."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._programs: dict[tuple, object] = {}
        self._vaos: dict[tuple, object] = {}
        corners = np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32)
        self._quad = ctx.buffer(corners.tobytes())
        self._instances = None
        self._capacity = 0
        self._world: dict[int, _World] = {}  # id(SplatObject) -> its world arrays
        self._order_key = None  # (clouds, view, eye) of the data in the buffer
        self._count = 0
        self._sums = None  # (size, samples, accum, aux, clear framebuffer, ms buffers)
        self._targets: dict[int, tuple] = {}  # zbuffer glo -> (zbuffer, framebuffer)
        self.composite = FullScreenPass(ctx, "splats/composite.frag")
        self._exact: dict[tuple, FullScreenPass] = {}
        # What the sums hold: the frame's state (the same object for a frame's colour and
        # its exact channels, drawn now or later; a new one for every frame and sample)
        # and what was drawn with it.
        self._drawn: tuple | None = None

    # -- per view, in numpy ----------------------------------------------------------------
    def _worlds(self, clouds) -> list[_World]:
        out = []
        for obj in clouds:
            w = self._world.get(id(obj))
            if w is None or w.key != (id(obj.splats), np.asarray(obj.transform).tobytes()):
                w = self._world[id(obj)] = _World(obj)
            out.append(w)
        live = {id(o) for o in clouds}
        for k in [k for k in self._world if k not in live]:
            del self._world[k]
        return out

    def _stale(self, clouds, view: np.ndarray) -> bool:
        """Whether the buffer's order and colours are too old for ``view``."""
        key = self._order_key
        if key is None or key[0] != tuple((id(o), o.splats.count) for o in clouds):
            return True
        old = key[1]
        turn = np.abs(view[:3, :3] - old[:3, :3]).max()
        eye, old_eye = np.linalg.inv(view)[:3, 3], np.linalg.inv(old)[:3, 3]
        return bool(turn > RESORT_ANGLE or
                    np.linalg.norm(eye - old_eye) > RESORT_MOVE * key[2])

    def upload(self, clouds, view: np.ndarray) -> int:
        """Sort and colour every cloud's splats for ``view`` (world -> view, OpenGL axes)
        and upload them in that order; returns how many there are."""
        if not self._stale(clouds, view):
            return self._count
        worlds = self._worlds(clouds)
        eye = np.linalg.inv(view)[:3, 3]
        axis = view[2, :3]  # view z: depth along the camera axis is -(axis . p + t)
        rows, depths = [], []
        for w in worlds:
            dirs = (w.means.astype(np.float64) - eye) @ w.to_local.T
            dirs /= np.maximum(np.linalg.norm(dirs, axis=1, keepdims=True), 1e-30)
            colors = w.splats.colors(dirs)
            block = np.empty((w.splats.count, STRIDE), np.float32)
            block[:, 0:3], block[:, 3:9] = w.means, w.cov
            block[:, 9:12], block[:, 12] = colors, w.splats.opacities
            block[:, 13] = w.id + 1
            rows.append(block)
            depths.append(-(w.means @ axis.astype(np.float32) + np.float32(view[2, 3])))
        data = np.concatenate(rows) if rows else np.zeros((0, STRIDE), np.float32)
        depth = np.concatenate(depths) if depths else np.zeros(0, np.float32)
        data = data[np.argsort(depth, kind="stable")]
        size = float(max((np.ptp(w.means, axis=0).max() if w.splats.count else 0.0)
                         for w in worlds) if worlds else 1.0) or 1.0
        if data.nbytes > self._capacity:
            if self._instances is not None:
                self._instances.release()
            self._capacity = max(data.nbytes, 1024)
            self._instances = self.ctx.buffer(reserve=self._capacity, dynamic=True)
            for vao in self._vaos.values():
                vao.release()
            self._vaos.clear()
        if data.nbytes:
            self._instances.write(data.tobytes())
        self._count = len(data)
        self._order_key = (tuple((id(o), o.splats.count) for o in clouds), view.copy(), size)
        return self._count

    # -- on the GPU ------------------------------------------------------------------------
    def _vao(self, state):
        key = (bool(state.srgb), bool(state.linear_out))
        if key not in self._vaos:
            if key not in self._programs:
                defines = {"COLOR_SRGB": None} if key[0] else {}
                if key[1]:
                    defines["LINEAR_OUT"] = None
                root = glsl_root() / "splats"
                self._programs[key] = compile_program(self.ctx, root / "splat.vert",
                                                      root / "splat.frag", defines)
            prog = self._programs[key].gl
            self._vaos[key] = self.ctx.vertex_array(prog, [
                (self._quad, "2f", "a_corner"),
                (self._instances, "3f 3f 3f 4f 1f/i", "a_mean", "a_cov_a", "a_cov_b",
                 "a_color", "a_id")], skip_errors=True)
        return self._programs[key], self._vaos[key]

    def _sums_for(self, zbuffer):
        """The sums (textures; multisampled buffers first when the opaque depth is) bound
        with the opaque scene's depth, cleared."""
        ctx, size, samples = self.ctx, zbuffer.size, zbuffer.samples
        if self._sums is None or self._sums[:2] != (size, samples):
            self._release_sums()
            accum = ctx.texture(size, 4, dtype="f4")
            aux = ctx.texture(size, 4, dtype="f4")
            resolved = ctx.framebuffer([accum, aux])
            ms = [ctx.renderbuffer(size, 4, samples=samples, dtype="f4") for _ in range(2)] \
                if samples else []
            self._sums = (size, samples, accum, aux, resolved, ms)
        _, _, accum, aux, resolved, ms = self._sums
        key = zbuffer.glo
        if key in self._targets and self._targets[key][0] is not zbuffer:
            self._targets.pop(key)[1].release()
        if key not in self._targets:
            self._targets[key] = (zbuffer, ctx.framebuffer(ms or [accum, aux], zbuffer))
        fbo = self._targets[key][1]
        fbo.use()
        fbo.depth_mask = False  # (the clear and the draw leave the opaque depth alone)
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        return fbo

    def accumulate(self, scene, state, zbuffer) -> bool:
        """Draw the splats into the sums; False when the scene has none in view."""
        clouds = scene_splats(scene)
        if not clouds:
            return False
        view = np.asarray(state.camera.view, np.float64)
        count = self.upload(clouds, view)
        if not count:
            return False
        ctx = self.ctx
        projection = state.view_projection() @ np.linalg.inv(state.camera.view)
        drawn = (state, zbuffer.glo, id(self._order_key), count)
        if self._drawn is not None and self._drawn[0] is state and \
                self._drawn[1:] == drawn[1:]:  # (the exact channels' and the colour's)
            return True
        fbo = self._sums_for(zbuffer)
        prog, vao = self._vao(state)
        prog.set("u_view", view)
        prog.set("u_projection", projection)
        prog.set("u_viewport", (float(state.width), float(state.height)))
        ctx.enable(ctx.DEPTH_TEST | ctx.BLEND)
        ctx.disable(ctx.CULL_FACE)
        ctx.blend_func = ctx.ONE_MINUS_DST_ALPHA, ctx.ONE
        vao.render(mode=ctx.TRIANGLE_STRIP, vertices=4, instances=count)
        fbo.depth_mask = True
        if self._sums[5]:  # resolve the multisampled sums into the textures
            for k in range(2):
                src = ctx.framebuffer([self._sums[5][k]])
                dst = ctx.framebuffer([self._sums[2 + k]])
                ctx.copy_framebuffer(dst, src)
                src.release()
                dst.release()
        ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA
        ctx.disable(ctx.BLEND)
        self._drawn = drawn
        return True

    def draw(self, scene, state, zbuffer, target) -> None:
        """The splats over ``target``'s picture, tested against ``zbuffer``."""
        if not self.accumulate(scene, state, zbuffer):
            return
        ctx = self.ctx
        target.use()
        ctx.disable(ctx.DEPTH_TEST)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE_MINUS_SRC_ALPHA
        self.composite.draw({"u_accum": self._sums[2]})
        ctx.blend_func = ctx.SRC_ALPHA, ctx.ONE_MINUS_SRC_ALPHA
        ctx.disable(ctx.BLEND)
        ctx.enable(ctx.DEPTH_TEST)

    def draw_exact(self, scene, state, fbo, locations: dict) -> None:
        """Depth and ids where the splats cover at least half a pixel in front of the
        opaque scene, into ``fbo`` (the exact channels' target, its depth the opaque
        scene's)."""
        if "depth_ids" not in locations or not self.accumulate(scene, state,
                                                                fbo.depth_attachment):
            return
        key = tuple(sorted(locations.items()))
        if key not in self._exact:
            defines = {f"OUT_{n.upper()}": k for n, k in locations.items()}
            prog = compile_program(self.ctx, fullscreen_vertex(),
                                   glsl_root() / "splats" / "exact.frag", defines)
            self._exact[key] = FullScreenPass(self.ctx, "splats/exact.frag", program=prog)
        ctx = self.ctx
        fbo.use()
        ctx.enable(ctx.DEPTH_TEST)
        ctx.disable(ctx.BLEND)
        mask, on, off = fbo.color_mask, locations["depth_ids"], (False,) * 4
        fbo.color_mask = tuple(m if k == on else off for k, m in enumerate(mask))
        fbo.depth_mask = False  # (tested against the opaque depth, which stays theirs)
        try:  # (depth_ids alone: the other attachments keep the opaque scene's)
            projection = state.view_projection() @ np.linalg.inv(state.camera.view)
            self._exact[key].draw({"u_splat_aux": self._sums[3]}, u_projection=projection)
        finally:
            fbo.color_mask = mask
            fbo.depth_mask = True

    def _release_sums(self) -> None:
        for _, fbo in self._targets.values():
            fbo.release()
        self._targets.clear()
        if self._sums is not None:
            for obj in (self._sums[4], self._sums[2], self._sums[3], *self._sums[5]):
                obj.release()
        self._sums = None

    def release(self) -> None:
        self._release_sums()
        for vao in self._vaos.values():
            vao.release()
        for prog in self._programs.values():
            prog.release()
        for p in self._exact.values():
            p.release()
        self.composite.release()
        self._quad.release()
        if self._instances is not None:
            self._instances.release()


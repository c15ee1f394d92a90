"""The steps of facet.render.renderer's pass sequence after the frame is prepared: the exact
channels (drawn now, or when first read), colour (one picture, or a sum of supersamples with
their distributed effects, denoised when asked), finishing into the destination, and the
reads back to numpy; and what the sequence makes on first use (engines, the finisher, the
targets of a size). ``PassSequence`` is the Renderer's base: it holds no state of its own
(the Renderer's context, engines, surfaces and finisher)."""

from __future__ import annotations

import threading
import time
import warnings
import weakref

import numpy as np

from ..errors import FacetWarning, InputError
from ..geometry.sampling import pattern
from ..gl.targets import writing
from .antialias import distributed_sample, gloss_jitter, jitter_matrix, point_lights_for
from .budget import SampleBudget
from .destination import Surfaces
from .engine import engine_for
from .finish import Finisher, finish_for
from .prepare import frozen
from .state import FrameState


class PassSequence:
    """Steps 3 to 5 of the Renderer's sequence (facet.render.renderer's docstring)."""

    _unread: weakref.ref | None  # the last Frame with channels still on the GPU
    _warned: set[str]  # what the engines cannot honour, said once
    _inside: bool  # the context is current
    progress = None  # progress(done, total, seconds) -> False to stop: after each sample
    _spp = None  # the last sum's paths per pixel (facet.render.budget)
    _engines: dict  # name -> engine (facet.render.engine), made on first use
    _finisher: Finisher | None  # the finishing pass, made on first use
    _surfaces: Surfaces | None  # the targets of the last size
    _view_budget: SampleBudget | None = None  # a still view's noise watch (_view_watch)
    view_settled = False  # a still view's noise is below the options' (it may stop)

    # -- what the sequence makes on first use and keeps ---------------------------------
    def _engine(self, name: str):
        """The engine called ``name`` (facet.render.engine), made on first use."""
        if name not in self._engines:
            self._engines[name] = engine_for(name)(self.ctx, self.cache)
        return self._engines[name]

    @property
    def finisher(self) -> Finisher:
        if self._finisher is None:
            self._finisher = Finisher(self.ctx)
        return self._finisher

    def _surfaces_for(self, size) -> Surfaces:
        """The size-dependent targets, made anew when the size changes."""
        if self._surfaces is None or self._surfaces.size != tuple(size):
            new = Surfaces(self.ctx, tuple(size))
            # moderngl re-binds the bound framebuffer after making one: bind a live one
            # before releasing the old (a released one there is GL_INVALID_OPERATION).
            new.targets.color().use()
            if self._surfaces is not None:
                self._surfaces.release()
            self._surfaces = new
        return self._surfaces

    def _warn(self, lines) -> None:
        """What an engine cannot honour: each line once per renderer (facet.render.engine)."""
        for line in lines:
            if line not in self._warned:
                self._warned.add(line)
                warnings.warn(line, FacetWarning, stacklevel=4)

    def _reader(self, surf, name: str, draw=None):
        """Read channel ``name`` when the frame's user first asks for it (facet.render.frame:
        a caller that only wants colour moves nothing else), with this renderer's context
        current; ``draw``: the deferred pass that fills it (``_exact``), run first."""
        owner = threading.get_ident()

        def read():
            if threading.get_ident() != owner:  # a GL context belongs to one thread
                raise InputError(f"a frame's {name} is read back from the GPU in the thread "
                                 "that rendered it: call frame.settle() there before "
                                 "handing the frame to another thread or process")
            if self._inside:  # never enter a current context again (facet.gl.context)
                return self._read_aux(surf, name, draw)
            with self.ctx:
                return self._read_aux(surf, name, draw)
        return read

    @staticmethod
    def _read_aux(surf, name: str, draw):
        if draw is not None:
            draw()
        return surf.targets.read_aux(name)

    def _settle(self) -> None:
        """Read what the last frame has not read yet, if someone still holds it, before
        its targets are drawn over."""
        frame = self._unread() if self._unread is not None else None
        self._unread = None
        if frame is not None:
            frame.settle()

    def _colour(self, engine, scene, state, opts, aa, dest, surf, together):
        """Steps 4 and 5: (colour read back or None, samples shown); the paths per pixel
        in ``_spp`` (None: the same everywhere)."""
        self._spp = None
        alpha = float(scene.background[3])
        bg = np.array([*state.to_linear(scene.background[:3]).tolist(), alpha])
        clear = (*(bg[:3] * alpha).tolist(), alpha)  # premultiplied (finishing undoes it)
        if aa is None:
            if opts.time_limit is not None:
                self._warn([f"time_limit stops sums of samples; {engine.capabilities.noun} "
                            "draws this picture in one pass (give spp to sum samples)"])
            # (float colour is linear light: encoded for 8-bit output and windows only)
            finish = finish_for(bg, opts.srgb and (not opts.float_color or
                                                  dest.window is not None))
            dtype = "f4" if finish.needed or opts.float_color else "f1"
            fbo = engine.draw_picture(scene, state, opts, surf, clear, dtype, together,
                                      None if finish.needed else dest.window)
            source = surf.targets.color_texture(dtype)
            return self._finish(source, fbo, finish, opts, dest, surf), 1
        samples = dest.samples(aa.samples)
        if dest.window is not None and opts.time_limit is not None:
            self._warn(["a window refines its picture a sample per frame: time_limit stops "
                        "the sums of pictures rendered offscreen"])
        budget = SampleBudget(self.ctx, opts.size, opts.noise if engine.adaptive else None,
                              opts.time_limit, self.progress) if dest.window is None else None
        watch = self._view_watch(engine, opts, dest)
        try:
            began = time.monotonic()
            source, done = self._accumulate(engine, scene, state, opts, aa, samples, bg, surf,
                                            dest.preview, budget)
            if watch is not None and len(samples) and \
                    not watch.added(aa.samples, time.monotonic() - began, source):
                self.view_settled = True
            if budget is not None:
                budget.even_out(source)
                self._spp = budget.counts()
        finally:
            engine.active = None
            if budget is not None:
                budget.release()
        if opts.denoise and engine.radiance and dest.window is None:
            self._denoise(engine, scene, state, surf, source, done)
        # An engine whose colour is linear radiance (the path tracer) is encoded for 8-bit
        # output (a window is 8-bit) and left linear in float colour, whatever srgb says.
        eight_bit = not opts.float_color or dest.window is not None
        # Float colour is linear light in every engine: encoding is for 8-bit output only.
        encode = eight_bit if engine.radiance else opts.srgb and eight_bit
        # Float output is linear light kept as it is, in every engine and every kind of
        # anti-aliasing: unclamped (and untonemapped), as a single-sample raster writes it.
        finish = finish_for(bg, encode, max(done, 1), clamp=eight_bit)
        return self._finish(source, None, finish, opts, dest, surf), done

    def _view_watch(self, engine, opts, dest) -> SampleBudget | None:
        """A still view's noise (``noise`` given to an adaptive engine): a budget that
        skips no pixel (the sum is shown as it grows), made at the view's first sample and
        kept while it refines; ``view_settled`` turns True once no pixel's error is above
        the noise (facet.render.budget's rule)."""
        if dest.window is None:
            return None
        if dest.sample is None or dest.sample == 0 or opts.noise is None or \
                not engine.adaptive or self._view_budget is None or \
                self._view_budget.size != tuple(opts.size) or \
                self._view_budget.noise != opts.noise:
            self.view_settled = False
            self._view_budget = None
            if dest.sample == 0 and opts.noise is not None and engine.adaptive:
                self._view_budget = SampleBudget(self.ctx, tuple(opts.size), opts.noise,
                                                 masked=False)
                self._view_budget.begin()
        return self._view_budget

    def _exact(self, engine, scene, state: FrameState, aux, surf) -> dict:
        """The exact channels at pixel centres (step 3), in a single-sample pass of their
        own; read back when used (``_reader``).

        An engine with ``deferred_exact`` (the rasterizer) draws this pass when a channel
        is first read, not now: most callers of the default outputs look at colour only,
        and under MSAA this pass costs a second trip through every triangle. It draws a
        snapshot of the objects taken now (their transforms and materials copied), so a
        scene changed after ``render`` returns changes nothing; the renderer draws it before
        its targets are used again (``_settle``). Otherwise (the ray tracer, whose geometry
        is this frame's) the pass is drawn now."""
        scene = engine.exact_scene(scene)
        if not engine.deferred_exact:
            self._draw_exact(engine, scene, state, aux, surf)
            return {name: self._reader(surf, name) for name in aux}
        snapshot = frozen(scene)
        drawn: list = []

        def draw():
            if not drawn:
                drawn.append(True)
                self._draw_exact(engine, snapshot, state, aux, surf)
        return {name: self._reader(surf, name, draw) for name in aux}

    def _draw_exact(self, engine, scene, state: FrameState, aux, surf) -> None:
        fbo = surf.targets.aux(aux)
        fbo.use()
        with writing(fbo, colour=False):  # no colour written (nor cleared) per fragment
            fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)  # the exact channels: "nothing"
            self.ctx.enable_only(self.ctx.DEPTH_TEST)
            engine.draw_exact(scene, state, aux)

    def _accumulate(self, engine, scene, state, opts, aa, samples: range, bg, surf,
                    plain=False, budget: SampleBudget | None = None):
        """Add supersamples ``samples`` of ``aa`` (step 4): each with its pixel offset, lens
        point, shutter time, area-light points and gloss tilt (``plain``: the centre of
        each), until ``budget`` says stop (facet.render.budget; a sample it stops halfway
        is dropped); returns (the sum's texture, the samples in it)."""
        acc = surf.accumulator
        clear = (*(bg[:3] * bg[3]), bg[3])
        if samples.start == 0:
            acc.clear()
        offsets = pattern(aa.pattern, aa.samples, opts.seed) if not plain else None
        if budget is not None and budget.synced and offsets is not None:
            # any first part of a pattern stopped early covers the whole pixel
            offsets = offsets[np.random.default_rng(opts.seed).permutation(len(offsets))]
        if budget is not None:
            budget.begin()
            engine.active = budget.mask
        done, k = samples.start, samples.start
        parts, per = _mosaic_parts(engine, scene, opts, plain, budget)
        while k < samples.stop:
            n = min(parts * per, samples.stop - k)
            drawn = [self._sample_state(engine, scene, state, opts, aa, offsets, j, plain)
                     for j in range(k, k + n)]
            began = time.monotonic()
            if n > 1:  # several samples at once (_mosaic_parts): parts first (tiles)
                each = -(-n // min(parts, n))
                stacked = -(-n // each)
                target = acc.mosaic(stacked)
                target.use()
                target.clear(*clear)
                self.ctx.enable_only(self.ctx.DEPTH_TEST)
                engine.draw_mosaic(drawn[0][0], [d[1] for d in drawn], k, opts, surf, bg,
                                   each)
                acc.add_sample(stacked)
            else:
                scene_k, sample = drawn[0]
                acc.begin_sample((0.0,) * 4 if engine.active is not None else clear)
                if not self._draw_strips(engine, scene_k, sample, opts, surf, bg, budget,
                                         len(samples)):
                    break
                acc.add_sample()
            done = k = k + n
            if budget is not None:
                if budget.synced:
                    self.ctx.finish()
                if not budget.added(len(samples), time.monotonic() - began, acc.accum_tex,
                                    n):
                    break
        return acc.accum_tex, done

    @staticmethod
    def _sample_state(engine, scene, state, opts, aa, offsets, k: int, plain: bool):
        """Sample k's (scene, state): its pixel offset, lens point, shutter time, area-light
        points and gloss tilt (``plain``: the centre of each)."""
        if plain:
            sample, scene_k = state, point_lights_for(scene)
        else:
            cam_k, scene_k = distributed_sample(state.camera, scene, k, aa)
            dx, dy = offsets[k]
            sample = state.with_(camera=cam_k, lights=tuple(scene_k.lights),
                                 jitter=jitter_matrix(dx, dy, opts.width, opts.height),
                                 gloss_jitter=gloss_jitter(k, aa.samples))
        return scene_k, engine.sample_state(scene, scene_k, sample, opts, k, plain)

    def _draw_strips(self, engine, scene_k, sample, opts, surf, bg, budget, total) -> bool:
        """One sample, in strips when one takes long (a stop is heard between them);
        False when the budget stopped it halfway."""
        n = budget.strips() if budget is not None else 1
        height = opts.height
        try:
            for i in range(n):
                if n > 1:
                    y0, y1 = i * height // n, (i + 1) * height // n
                    self.ctx.scissor = (0, y0, opts.width, y1 - y0)
                self.ctx.enable_only(self.ctx.DEPTH_TEST)
                engine.draw_sample(scene_k, sample, opts, surf, bg)
                if n > 1:
                    self.ctx.finish()
                    if i < n - 1 and not budget.go_on(total):
                        return False
        finally:
            if n > 1:
                self.ctx.scissor = None
        return True

    def _denoise(self, engine, scene, state, surf, source, samples: int) -> None:
        """The sum of ``samples`` pictures in ``source`` replaced by its denoised mean times
        ``samples`` (facet.render.denoise), guided by the engine's albedo and normals
        (drawn into the colour and normals attachments; the exact channels drawn there are
        the same normals, and depth and ids are left alone)."""
        from .denoise import denoise

        w, h = source.size
        total = np.frombuffer(source.read(), np.float32).reshape(h, w, 4).copy()
        fbo = surf.targets.aux(("normals",), "f4")
        fbo.use()
        with writing(fbo):
            fbo.clear(0.0, 0.0, 0.0, 0.0)
            engine.draw_exact(engine.exact_scene(scene), state, ("normals",), albedo=True)
        albedo = surf.targets.read_color(fbo, "f4")[..., :3]
        normal = surf.targets.read_aux("normals")
        total[..., :3] = denoise(total[..., :3] / samples, albedo, normal) * samples
        source.write(total.tobytes())

    def _finish(self, source, source_fbo, finish, opts, dest, surf):
        """Step 5: finished colour read back (offscreen) or shown (window); a sum of
        samples (no ``source_fbo``) is always finished."""
        t = surf.targets
        out = "f4" if opts.float_color else "f1"
        needed = finish.needed or source_fbo is None
        if dest.window is not None:
            dest.window.viewport = (0, 0, *opts.size)
            if needed:
                self.finisher.draw(source, dest.window, finish)
            elif source_fbo is not dest.window:
                self.ctx.copy_framebuffer(dest.window, source_fbo)
            return None
        if not needed:
            return t.read_color(source_fbo, out)
        self.finisher.draw(source, t.output(out), finish)
        return t.read_color(t.output(out), out)


TILE_PIXELS = 64 * 64  # llvmpipe's tile, the unit of work one of its threads takes
TILES_PER_THREAD = 8  # a draw's tiles a rasterizer thread gets (mosaic_pixels)
MAX_MOSAIC = 16


def rasterizer_threads() -> int:
    """The threads llvmpipe shades with: LP_NUM_THREADS where set (0: the caller's own,
    one), else this process's cores (its default)."""
    import os

    given = os.environ.get("LP_NUM_THREADS", "").strip()
    if given.isdigit():
        return max(1, int(given))
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        os.cpu_count() or 1


def mosaic_pixels() -> int:
    """The picture a draw should fill: TILES_PER_THREAD tiles for each rasterizer thread
    (65536 pixels, 256 x 256, on two cores)."""
    return TILE_PIXELS * TILES_PER_THREAD * rasterizer_threads()


def _mosaic_parts(engine, scene, opts, plain: bool, budget) -> tuple[int, int]:
    """How many samples to draw at once: (parts stacked one above the other, samples each
    fragment of a part draws one after the other; their product at most MAX_MOSAIC).

    llvmpipe's threads each take a 64 x 64 tile of a draw at a time, and a draw ends when
    its slowest tile does: a picture of few tiles leaves cores idle (64 x 64: one of two;
    the Cornell box drew 48k paths a second there against 89k at 256 x 256), and tiles of
    unequal cost (sky beside a mesh) leave one waiting at the end of each draw (128 x 128,
    four tiles: 1.7 of 2 cores busy on the glass and glTF-spheres scenes of
    benchmarks/pathtrace.py). So the path tracer draws several of its samples as one
    taller picture of at least ``mosaic_pixels()`` (128 x 128: four parts, 17% faster on
    those two scenes, 1.9 cores busy); and a fragment draws the engine's ``per_fragment``
    paths in one loop (more parts and fewer paths a fragment were slower: 16 x 1 and 8 x 2
    against 4 x 4 at 128 x 128). Only where samples differ in camera and shift alone (no
    motion blur), and where no budget watches sample by sample (a time limit, noise, a
    progress callback: each counts, and may stop, single samples)."""
    pixels = opts.width * opts.height
    if not engine.mosaic or plain or (budget is not None and budget.synced) or \
            getattr(scene, "moving", None) is not None or \
            any(o.transform_end is not None for o in scene.objects):
        return 1, 1
    fill = mosaic_pixels()
    parts = min(MAX_MOSAIC, fill // pixels) if pixels * 2 <= fill else 1
    return parts, max(1, min(engine.per_fragment, MAX_MOSAIC // parts))

"""The engines behind one door: the rasterizer, the Whitted ray tracer and the path tracer
draw one scene, with the same lights and materials, behind one interface; they are siblings
(the tracers share the ray scene of facet.render.rays, neither derives from the other). The
``engine`` option picks one per render call (facet.render.renderer asks ``engine_for`` once
and calls nothing else engine-specific).

An engine, given the frame's shared state (facet.render.state.FrameState):

    sampling(opts, scene, camera, preview)   the supersamples its colour sums, or None for
                                             one picture (``draw_picture``)
    prepare(scene, state, opts, aa)          what every sample of the frame shares (shadow
                                             maps, uploaded geometry); returns the state
    draw_picture(...)                        one picture, when ``sampling`` gave None
    sample_state(scene, scene_k, state, opts, k, plain)
                                             supersample k's own state (area-light maps)
    draw_sample(scene, state, opts, surf, background)
                                             one supersample into the bound sample target
    exact_scene(scene), draw_exact(scene, state, aux)
                                             the exact channels at pixel centres into the
                                             bound target (``deferred_exact``: may be drawn
                                             later, from a snapshot of ``exact_scene``)
    unsupported(opts, scene)                 what it cannot honour: one line each, which the
                                             renderer warns once (never silently dropped),
                                             from its row of facet.render.capabilities
    decided(opts)                            the options with what was not given decided
                                             by it (its defaults: the same table)

``ENGINE_CLASSES`` maps each name of facet.options.render.ENGINES to its class, loaded on
first use; a new engine is a new module and a row here.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any, Protocol

from ..options.render import AntiAliasing, parse_aa
from .antialias import accumulation
from .capabilities import CAPABILITIES, Capabilities

ENGINE_CLASSES = {
    "raster": ("facet.render.raster.engine", "RasterEngine"),
    "trace": ("facet.render.trace.engine", "TraceEngine"),
    "path": ("facet.render.path.engine", "PathEngine"),
}


class UserShaderPrograms(Protocol):
    """What a front asks of the users' mesh shaders' programs an engine keeps
    (facet.render.raster.user_shaders.UserPrograms is one): whether a file changed,
    reloading them (a ReloadResult), and whether one reads ``u_time``."""

    def changed(self) -> bool: ...

    def reload(self) -> Any: ...

    def reads_time(self) -> bool: ...


def engine_for(name: str):
    """The class of engine ``name`` (its module is imported now)."""
    module, cls = ENGINE_CLASSES[name]
    return getattr(import_module(module), cls)


class Engine:
    """The interface (module docstring); the defaults are a rasterizer's."""

    name = ""
    deferred_exact = False  # the exact channels may be drawn after the call returns
    radiance = False  # colour is linear radiance: sRGB-encoded only for 8-bit output
    adaptive = False  # skips the pixels ``active`` marks stopped (facet.render.budget)
    active = None  # the mask texture of the sum being drawn (R8, 0: stopped), or None
    mosaic = False  # draws several samples at once, stacked (draw_mosaic)
    per_fragment = 1  # in a mosaic, samples one fragment draws one after the other

    def __init__(self, ctx, cache):
        self.ctx, self.cache = ctx, cache

    @property
    def capabilities(self) -> Capabilities:
        """This engine's row of facet.render.capabilities."""
        return CAPABILITIES[self.name]

    def decided(self, opts):
        """``opts`` with what was not given decided by this engine (the renderer calls the
        methods below with these)."""
        return self.capabilities.decided(opts)

    def sampling(self, opts, scene, camera, preview: bool) -> AntiAliasing | None:
        """The supersampling the colour needs: the options' (or the distributed effects'),
        None for one picture; a window's moving view (``preview``) gets one picture."""
        return None if preview else accumulation(opts.aa, scene, camera, opts.shadows)

    def draws_together(self, scene) -> bool:
        """Whether colour and the exact channels may come from one pass."""
        return False

    def prepare(self, scene, state, opts, aa):
        return state

    def draw_picture(self, scene, state, opts, surf, clear, dtype, together, direct):
        raise NotImplementedError(f"the {self.name} engine always sums samples")

    def sample_state(self, scene, scene_k, state, opts, k: int, plain: bool):
        return state

    def draw_sample(self, scene, state, opts, surf, background) -> None:
        raise NotImplementedError

    def exact_scene(self, scene):
        return scene

    def draw_exact(self, scene, state, aux) -> None:
        raise NotImplementedError

    def unsupported(self, opts, scene) -> list[str]:
        """What this engine cannot honour, a line each: its table's options (given in
        ``opts``, before ``decided``) and material features, then ``more_lines``."""
        caps = self.capabilities
        return caps.option_lines(opts) + self.more_lines(opts, scene) + \
            caps.feature_lines(scene)

    def more_lines(self, opts, scene) -> list[str]:
        """Lines of what this engine does not honour beyond its table's (scene-dependent)."""
        return []

    def user_programs(self) -> UserShaderPrograms | None:
        """Users' mesh shaders' programs this engine keeps, or None (the tracers draw no
        user shader)."""
        return None

    def release(self) -> None:
        pass


def grid_or_jittered(n: int) -> AntiAliasing:
    """N samples per pixel: a grid when N is square, else jittered."""
    return parse_aa(f"ssaa:{'grid' if round(n ** 0.5) ** 2 == n else 'jittered'}:{n}")

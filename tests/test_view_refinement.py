"""How far a still view refines (issue 49, item 10): every front (the window, the widget,
the page) draws through a Session's pass sequence, so these run headless. The path tracer's
still view refines to its own view count (facet.render.capabilities.VIEW_PATHS) when the
options name no sample count, to the count they name otherwise, and with ``noise`` stops
once no pixel is noisier than that, as ``facet render --noise`` does. (Old code: every
engine stopped at the default msaa:4's four samples, fireflies left, and a view given
noise warned that it ignores it.)"""

from __future__ import annotations

import numpy as np

import facet
from facet.render.capabilities import VIEW_PATHS
from facet.scene import primitives
from facet.viewing.session import Session


def _frames(session, limit: int) -> int:
    """Frames drawn until the session is idle (at most ``limit``)."""
    for n in range(limit):
        if session.frame() is None:
            return n
    return limit


def _sphere():
    scene = facet.Scene()
    scene.add(primitives.sphere(0.5), facet.Material(color=(0.8, 0.5, 0.3)))
    scene.add_camera("front", facet.Camera.look_at((0, 0, 2.2), (0, 0, 0), fov_y=45))
    return scene


def test_a_still_path_traced_view_refines_past_the_default_four_samples():
    with Session(facet.paths.default_model(), size=(40, 30),
                 options={"engine": "path"}) as s:
        assert _frames(s, 13) == 13  # a sample a frame from the first: still refining
        state = s.state()
        assert (state["samples"], state["of"]) == (13, VIEW_PATHS), state
        assert f"13/{VIEW_PATHS} samples" in s.status() and s.refining
        # what a screenshot at another scale or a turntable renders by is the options as
        # given (the view count is the still view's alone)
        assert s.options().aa.kind == "msaa" and s.view_options().aa.samples == VIEW_PATHS


def test_a_view_given_a_sample_count_refines_to_it_and_stops():
    for engine, options in (("path", {"spp": 6}), ("trace", {})):
        with Session(facet.paths.default_model(), size=(40, 30),
                     options={"engine": engine, **options}) as s:
            # the Whitted tracer: its msaa:4, four rays a pixel after a first plain picture
            want, frames = (6, 6) if options else (4, 5)
            assert _frames(s, 40) == frames
            assert (s.state()["samples"], s.state()["of"]) == (want, want)
            assert not s.refining and not s.state()["settled"]


def test_a_view_given_noise_stops_once_no_pixel_is_noisier():
    noise = 0.25
    scene = _sphere()
    with Session(scene, size=(32, 32), options={"engine": "path", "noise": noise}) as s:
        n = _frames(s, 400)
        state = s.state()
        assert n < 400 and state["settled"] and not s.refining, state
        assert 16 <= state["samples"] < state["of"], state
        assert f"noise {noise:g} reached" in s.status()
        shown = s.grab().astype(float)
        camera = s.camera()
        with facet.Renderer(32, 32) as r:
            reference = r.render(scene, camera, engine="path", spp=256,
                                 outputs=("color",)).color[..., :3].astype(float)
    lit = reference.mean(axis=2) > 20
    # the picture it stopped at is the converged one within its noise, pixel by pixel on
    # average (a 4-sample picture of this sphere is off by far more)
    error = np.abs(shown - reference)[lit].mean() / reference[lit].mean()
    assert error < noise, error
    # moving the view starts over
    with Session(scene, size=(32, 32), options={"engine": "path", "noise": noise}) as s:
        _frames(s, 400)
        s.handle({"type": "wheel", "x": 16, "y": 16, "dy": 100})
        s.frame()
        assert not s.state()["settled"] and s.refining

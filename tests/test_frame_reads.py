"""When a frame's exact channels are drawn and read (facet.render.frame, renderer step 3).

Without MSAA they come from the colour pass and are read back when first used; with MSAA or
supersampling their own single-sample pass is drawn when first used. Either way a frame's
arrays are those of the scene and camera it was rendered with, whatever happens after.
"""

import threading

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, Scene

from conftest import quad_mesh, sphere_mesh

SIZE = 48
AA = [{"msaa": 0}, {"msaa": 4}, {"aa": "ssaa:grid:4"}]
CHANNELS = ("color", "depth", "ids", "normals", "position")


def _scene():
    scene = Scene()
    scene.add(sphere_mesh(), Material(color=(0.8, 0.3, 0.2)))
    scene.add(quad_mesh(4.0), Material(), transform=T.translate((0, 0, -1.5)))
    scene.add_light(DirectionalLight((-0.3, -0.4, -1)))
    return scene


CAMERAS = [Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=40, near=1, far=20),
           Camera.look_at((2, 1, 4), (0, 0, 0), fov_y=40, near=1, far=20)]


def _arrays(frame) -> dict:
    return {"depth": frame.depth, "ids": frame.object_ids, "normals": frame.normals,
            "position": frame.position}


def _reference(aa: dict, camera) -> dict:
    """Each channel as a renderer of its own gives it, read at once."""
    with Renderer(SIZE, SIZE) as r:
        return _arrays(r.render(_scene(), camera, outputs=CHANNELS, **aa))


def _assert_same(got: dict, want: dict) -> None:
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)
    assert (got["ids"] == 1).any() and (got["ids"] == 0).any()  # both objects seen


@pytest.mark.parametrize("aa", AA, ids=["none", "msaa4", "ssaa4"])
def test_a_scene_changed_after_render_changes_nothing(aa):
    """Move, recolour and swap the objects after ``render``: the channels read afterwards
    are those of the scene as rendered (the deferred pass draws a snapshot)."""
    want = _reference(aa, CAMERAS[0])
    scene = _scene()
    with Renderer(SIZE, SIZE) as r:
        frame = r.render(scene, CAMERAS[0], outputs=CHANNELS, **aa)
        scene.objects[0].transform[:3, 3] = (0.7, 0.0, 0.0)  # in place
        scene.objects[1].transform = T.translate((0, 0, -0.5))
        scene.objects[1].material.opacity = 0.5  # would drop it from the exact pass
        scene.objects.reverse()
        _assert_same(_arrays(frame), want)


@pytest.mark.parametrize("aa", AA, ids=["none", "msaa4", "ssaa4"])
def test_a_held_frame_keeps_its_channels_across_renders(aa):
    """Frame 1 is read after frame 2 was rendered (through another camera) into the same
    targets, and after the renderer is closed: each has its own camera's channels."""
    want = [_reference(aa, c) for c in CAMERAS]
    with Renderer(SIZE, SIZE) as r:
        first = r.render(_scene(), CAMERAS[0], outputs=CHANNELS, **aa)
        second = r.render(_scene(), CAMERAS[1], outputs=CHANNELS, **aa)
        _assert_same(_arrays(second), want[1])
        _assert_same(_arrays(first), want[0])
        third = r.render(_scene(), CAMERAS[1], outputs=CHANNELS, **aa)
    _assert_same(_arrays(third), want[1])  # read after close(): it settled the frame


def test_with_msaa_a_caller_that_uses_colour_only_draws_no_exact_pass():
    """The exact channels' program is compiled and drawn only when a channel is read."""
    with Renderer(SIZE, SIZE, msaa=4) as r:
        def exact_programs():
            return [v for v in r._engine("raster").forward.programs if v.exact_only]

        for camera in CAMERAS:  # the default outputs, colour used
            assert r.render(_scene(), camera).color.any()
        assert exact_programs() == []
        frame = r.render(_scene(), CAMERAS[0])
        assert (frame.object_ids == 0).any()
        assert exact_programs()  # drawn now (a program per culled / two-sided object)


def test_reading_in_another_thread_is_one_clear_error():
    with Renderer(SIZE, SIZE, msaa=4) as r:
        frame = r.render(_scene(), CAMERAS[0])
        errors = []

        def read():
            try:
                frame.depth  # noqa: B018
            except InputError as exc:
                errors.append(str(exc))
        worker = threading.Thread(target=read)
        worker.start()
        worker.join()
        assert len(errors) == 1 and "frame.settle()" in errors[0]
        frame.settle()  # in the rendering thread: fine, and then any thread may read
        worker = threading.Thread(target=read)
        worker.start()
        worker.join()
        assert len(errors) == 1 and (frame.object_ids == 0).any()


@pytest.mark.parametrize("aa", AA, ids=["none", "msaa4", "ssaa4"])
def test_what_an_earlier_frame_drew_is_nothing_in_the_next(aa):
    """The exact channels are cleared on every frame (on the framebuffer the frame draws:
    facet.gl.targets.clear_frame): where the previous frame saw an object and this one
    sees nothing they read "nothing", as from a fresh renderer."""
    moved = Scene()
    moved.add(sphere_mesh(), Material(), transform=T.translate((1.8, 0, 0)))
    moved.add_light(DirectionalLight((-0.3, -0.4, -1)))
    with Renderer(SIZE, SIZE) as fresh:
        want = _arrays(fresh.render(moved, CAMERAS[0], outputs=CHANNELS, **aa))
    with Renderer(SIZE, SIZE) as r:
        first = _arrays(r.render(_scene(), CAMERAS[0], outputs=CHANNELS, **aa))
        got = _arrays(r.render(moved, CAMERAS[0], outputs=CHANNELS, **aa))
    empty = (first["ids"] >= 0) & (got["ids"] < 0)
    assert empty.sum() > SIZE * SIZE // 4  # most of the first frame is empty now
    for name in want:
        np.testing.assert_array_equal(got[name], want[name], err_msg=name)
    assert (got["depth"][empty] == 0).all() and (got["normals"][empty] == 0).all()

"""The notebook widget's logic without a browser: events in through jupyter_rfb's message
entry (what the browser's comm calls), camera and pictures out, over real EGL. The
pictures must be the headless render of the widget's camera (golden tolerance); the
drags must move the camera as the window's arcball does; an idle widget draws nothing.
The same widget in a real browser: tests/test_browser.py."""

import numpy as np
import pytest

from facet.geometry.orbit import OrbitControl
from facet.paths import default_model

from test_golden import CHANNEL_TOL, MAX_DIFFERING

pytest.importorskip("jupyter_rfb", reason="the notebook extra (jupyter_rfb) is not installed")


def edges(ref) -> np.ndarray:
    """(H, W) bool: pixels next to a step in ``ref`` (a silhouette or a crease), where a
    window-like framebuffer (drawn bottom-up) and the headless one (drawn top-down) sample
    their MSAA and coverage ties differently."""
    img = ref[..., :3].astype(int)
    step = np.zeros(img.shape[:2], bool)
    step[:, 1:] |= np.abs(np.diff(img, axis=1)).max(-1) > 2 * CHANNEL_TOL
    step[1:, :] |= np.abs(np.diff(img, axis=0)).max(-1) > 2 * CHANNEL_TOL
    grown = step.copy()
    for axis in (0, 1):
        for shift in (-1, 1):
            grown |= np.roll(step, shift, axis)
    return grown


def same_picture(shown, ref) -> float:
    """The share of pixels away from the reference's edges that are off by more than the
    golden tolerance (a different camera or a wrong picture fails it by far)."""
    diff = np.abs(shown[..., :3].astype(int) - ref[..., :3].astype(int)).max(axis=2)
    return float(((diff > CHANNEL_TOL) & ~edges(ref)).mean())


def headless(widget, **changes):
    """What ``facet render`` gives for the widget's camera and options."""
    s = widget.session
    opts = s.options(outputs=("color",), **changes)
    return s.renderer.render(s.shown_scene(), s.camera(), opts).color


def message(widget, **event):
    """An event as the browser's comm delivers it."""
    widget._rfb_handle_msg(widget, {"modifiers": [], "buttons": [], **event}, [])


@pytest.fixture
def widget():
    from facet.notebook.widget import widget_class

    w = widget_class()(default_model(), size=(160, 120))
    message(w, type="resize", width=160, height=120, pixel_ratio=1.0)
    yield w
    w.session.close()


def test_the_first_picture_is_the_headless_render(widget):
    picture = widget.get_frame()
    assert picture.shape == (120, 160, 3) and picture.std() > 10
    assert same_picture(picture, headless(widget)) <= MAX_DIFFERING


def test_a_drag_orbits_as_the_window_does_and_the_picture_follows(widget):
    before = widget.get_frame().copy()
    control = OrbitControl(widget.session.control.bounds)
    control.set_camera(widget.camera())
    message(widget, type="pointer_down", x=40, y=60, button=1)
    for x in (60, 80, 100):
        message(widget, type="pointer_move", x=x, y=60 + (x - 40) // 4, button=1)
    message(widget, type="pointer_up", x=100, y=75, button=1)
    for (x0, y0), (x1, y1) in zip([(40, 60), (60, 65), (80, 70)], [(60, 65), (80, 70),
                                                                    (100, 75)], strict=True):
        control.orbit((x0, y0), (x1, y1), 160, 120)
    assert np.allclose(widget.camera().view, control.camera(160 / 120).view, atol=1e-9)
    assert widget._rfb_draw_requested  # the change asked for a picture
    after = widget.get_frame()
    assert same_picture(after, before) > 0.02  # it moved (the knot fills ~30% of the view)
    assert same_picture(after, headless(widget)) <= MAX_DIFFERING


def test_right_drag_pans_and_the_wheel_zooms(widget):
    widget.get_frame()
    target = widget.session.control.target.copy()
    message(widget, type="pointer_down", x=80, y=60, button=2)
    message(widget, type="pointer_move", x=100, y=60, button=2)
    message(widget, type="pointer_up", x=100, y=60, button=2)
    moved = widget.session.control.target - target
    assert np.linalg.norm(moved) > 0 and np.allclose(widget.camera().view[:3, :3] @ moved,
                                                      [-np.linalg.norm(moved), 0, 0], atol=1e-6)
    distance = widget.session.control.distance
    message(widget, type="wheel", x=80, y=60, dx=0, dy=-100)  # one notch towards the user: in
    assert widget.session.control.distance < distance


def test_an_idle_widget_draws_nothing(widget):
    widget.get_frame()
    widget._rfb_draw_requested = False
    message(widget, type="pointer_move", x=10, y=10)  # no button: no change
    assert not widget._rfb_draw_requested
    assert widget.get_frame() is None


def test_a_view_shown_again_gets_the_picture(widget):
    """A widget shown again (a reloaded page, ``w`` in a new cell) is a new view: its first
    event is a resize to the same size, and it must get the picture, lossless (the old
    widget returned None, nothing having changed, and the new view stayed grey: found by
    the browser soak, tests/test_remote_soak.py)."""
    first = widget.get_frame().copy()
    assert widget.get_frame() is None  # idle
    sent = widget._rfb_frame_index
    message(widget, type="resize", width=160, height=120, pixel_ratio=1.0)
    # sent at once, lossless, and not drawn again
    assert widget._rfb_frame_index == sent + 1 and widget.get_frame() is None
    assert np.array_equal(widget._rfb_last_frame, first) and widget.session.frames == 1


def test_the_title_bar_is_the_status_line_and_says_how_far_the_view_refined(widget):
    """The page shows the status line (the served page's, under its picture) in the
    widget's title bar: the engine, a refinement's progress (what a person and the browser
    soak wait on)."""
    widget.get_frame()
    assert widget.has_titlebar and widget.title.startswith("facet - default")
    message(widget, type="key_down", key="e")
    widget.get_frame()
    assert "engine trace" in widget.title and "/" in widget.title
    while widget.get_frame() is not None:
        pass
    done = widget.title.rsplit(" - ", 1)[-1].split()[0]
    assert done.split("/")[0] == done.split("/")[1], widget.title


def test_a_reloaded_page_is_not_left_waiting_on_pictures_sent_to_the_old_one(widget):
    """Pictures sent while a page reloads are never confirmed (the old page is gone); the
    new page's view confirms only pictures it gets. jupyter_rfb sends nothing while two are
    unconfirmed, so the reloaded widget stayed grey for good (found by the browser soak).
    A view's resize (a new view's first event) forgets what is in flight."""
    widget._has_visible_views = True
    sent = []
    for _ in range(3):  # (no page confirms them)
        widget._rfb_maybe_draw()
        sent.append(widget._rfb_frame_index)
        message(widget, type="key_down", key="b")
    assert sent == [1, 2, 2]  # the third waits on the first two
    message(widget, type="resize", width=160, height=120, pixel_ratio=1.0)  # the new page
    widget._rfb_maybe_draw()
    assert widget._rfb_frame_index == 3


def test_keys_switch_engine_and_a_still_view_refines_to_the_headless_picture(widget):
    widget.get_frame()
    message(widget, type="key_down", key="e")
    assert widget.session.options().engine == "trace"
    frames = 0
    while widget.get_frame() is not None:
        frames += 1
        assert frames < 100
    assert frames > 1  # refined over several frames, then stopped
    assert not widget._rfb_draw_requested or widget.get_frame() is None
    assert same_picture(widget.picture, headless(widget)) <= MAX_DIFFERING


def test_resizing_with_a_pixel_ratio_draws_more_pixels(widget):
    message(widget, type="resize", width=100, height=80, pixel_ratio=2.0)
    picture = widget.get_frame()
    assert picture.shape == (160, 200, 3)
    assert same_picture(picture, headless(widget)) <= MAX_DIFFERING


def test_q_closes_the_widget_and_releases_its_gl(widget):
    widget.get_frame()
    closed = []
    widget.observe(lambda change: closed.append(change), names="comm")
    message(widget, type="key_down", key="q")
    assert widget.session.quitting
    assert widget.session.canvas is None


def test_show_outside_jupyter_opens_the_window(monkeypatch):
    """No kernel: facet.show is the glfw window (here without a display: one clear error)."""
    import facet
    from facet.window.base import NoDisplayError

    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(NoDisplayError, match="no display"):
        facet.show(default_model())


def test_s_saves_the_picture_shown_and_m_changes_the_shading(widget, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shown = widget.get_frame().copy()
    widget.press("s")  # a screenshot into the kernel's folder, with its camera beside it
    saved = sorted(tmp_path.glob("facet-*.png"))
    assert len(saved) == 1 and saved[0].with_suffix(".json").is_file()
    from PIL import Image

    assert np.array_equal(np.asarray(Image.open(saved[0]).convert("RGB")), shown)
    before = widget.session.options().shading
    widget.press("m")
    assert widget.session.options().shading != before
    changed = widget.get_frame()
    assert same_picture(changed, headless(widget)) <= MAX_DIFFERING


def test_the_widget_reloads_its_file_when_it_changes(tmp_path):
    """As the window does: the open file is looked at (``watch``, on the kernel's event loop
    every WATCH_EVERY seconds), a change that stays put is loaded, the camera kept."""
    import time

    import trimesh

    from facet.notebook.widget import widget_class

    path = tmp_path / "model.ply"
    trimesh.creation.box().export(path)
    w = widget_class()(str(path), size=(96, 72))
    try:
        first = w.get_frame().copy()
        camera = w.camera().view.copy()
        assert w.watch() and w.get_frame() is None  # nothing changed: nothing drawn
        trimesh.creation.icosphere(subdivisions=3).export(path)
        end = time.monotonic() + 30
        while w.session.triangles == 12 and time.monotonic() < end:
            w.watch()  # the change must stay put for the debounce interval
            time.sleep(0.02)
        assert w.session.triangles == 1280 and w._rfb_draw_requested
        assert np.allclose(w.camera().view, camera)  # reloaded in place
        assert same_picture(w.get_frame(), first) > 0.01
        w.session.close()
        assert not w.watch()  # a closed widget stops looking
    finally:
        w.session.close()


def test_frames_asked_for_from_several_threads_at_once_sum_to_the_headless_picture():
    """ipykernel 7 delivers a widget's messages and timers on several threads of its own:
    two frames of a refining view were drawn at once on the one GL context, and the sum of
    supersamples lost or doubled samples (a soak ended 3% darker than the headless picture).
    The session's GL work runs in one thread of the widget's, one call at a time."""
    import threading
    import time

    from facet.notebook.widget import widget_class

    w = widget_class()(default_model(), size=(160, 120), aa="ssaa:jittered:64")
    message(w, type="resize", width=160, height=120, pixel_ratio=1.0)
    try:
        end = time.monotonic() + 60
        errors = []

        def ask():
            try:
                while time.monotonic() < end and (w.session._samples < 64 or
                                                  w.session._dirty):
                    w.get_frame()
            except Exception as exc:  # noqa: BLE001 (reported below)
                errors.append(exc)

        threads = [threading.Thread(target=ask) for _ in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        assert w.session.status().endswith("64/64 samples"), w.session.status()
        assert same_picture(w.picture, headless(w)) <= MAX_DIFFERING
    finally:
        w.session.close()


def test_a_session_can_be_asked_whether_it_refines_before_any_frame():
    """``refining`` (and ``wants_frame``) asks the engine how many samples it sums; an engine
    made on first use makes GL objects, and made outside the renderer's context that was
    "cannot create buffer" (``w.session.refining`` in a cell before the widget drew, or
    after an engine switch not yet drawn)."""
    from facet.viewing.session import Session

    with Session(default_model(), size=(64, 48)) as s:
        assert s.refining is False  # the rasterizer, 4x MSAA: one picture
        s.char("e")  # the ray tracer: a sum of samples, not drawn yet
        s._dirty = False  # (as after a frame: wants_frame then asks refining)
        assert s.refining is True and s.wants_frame
        s.request_frame()
        picture = s.frame()
        assert picture is not None and picture.std() > 10 and " samples" in s.status()


@pytest.mark.parametrize("event", [
    {"type": "wheel", "x": 80, "y": 60, "dx": 0, "dy": float("nan")},
    {"type": "wheel", "x": float("inf"), "y": 60, "dx": 0, "dy": 1},
    {"type": "pointer_move", "x": "a", "y": 0}, {"type": "resize", "width": -4, "height": 3},
])
def test_a_malformed_browser_event_is_dropped_with_one_line(widget, event):
    """Input from a browser: an event the served page would drop (NaN, inf, text, a
    negative size) is dropped by the widget too, with one warning line, and the view is
    as it was."""
    import warnings

    from facet.errors import FacetWarning

    widget.get_frame()
    view = widget.camera().view.copy()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        message(widget, **event)
    lines = [str(w.message) for w in said if issubclass(w.category, FacetWarning)]
    assert len(lines) == 1 and "dropped" in lines[0], lines
    assert np.array_equal(widget.camera().view, view) and np.isfinite(view).all()
    assert widget.get_frame() is None or widget.get_frame().std() > 10


def test_a_keys_result_is_printed_in_the_widgets_cell(widget, capsys):
    """A key pressed in the browser: its result (and h's key map) goes to the widget's
    output area, shown under it in the cell that made it; a plain print() from the comm's
    callback reached no cell."""
    widget.get_frame()
    message(widget, type="key_down", key="w")
    widget.get_frame()
    message(widget, type="key_down", key="h")
    widget.get_frame()
    shown = "".join(o.get("text", "") for o in widget._output_context.outputs)
    assert "wireframe: on" in shown and "facet view keys:" in shown, shown
    assert "wireframe" not in capsys.readouterr().out

"""The viewer's keys in a headless session (what every front runs: the window, the served
page, the notebook widget): each key says what it did, and ``r`` does what its help says
(the camera and every key's change but the engine's, back to how the view opened)."""

from __future__ import annotations

import numpy as np
import pytest

from facet.paths import default_model
from facet.viewing.actions import RESET_SAID
from facet.viewing.keys import KEYMAP
from facet.viewing.session import Session


@pytest.fixture
def session():
    with Session(default_model(), options=dict(aa="none")) as s:
        s.resize(64, 48)
        s.frame()
        s.take_notices()
        yield s


@pytest.mark.parametrize("key", ["f", "r", "o", "m", "w", "a", "l", "x", "b", "e"])
def test_every_key_says_a_word(session, key):
    session.char(key)
    notices = session.take_notices()
    assert len(notices) == 1 and notices[0].strip(), (key, notices)


def test_f_frames_the_model_in_a_session(session):
    """A Session's ``frame()`` is its next picture: the f key once called it (the served
    page and the widget drew a picture instead of framing the model)."""
    framed = session.camera().view.copy()
    session.press(10, 10, pan=False)
    session.move(40, 30)
    session.release()
    session.press(20, 20, pan=True)  # a pan moves the target off the centre
    session.move(35, 28)
    session.release()
    assert not np.allclose(session.camera().view, framed)
    session.char("f")
    assert session.take_notices() == ["framed the model"]
    moved = session.camera().view
    assert np.isfinite(moved).all()
    # Framed again: the model's centre straight ahead, at the framing distance.
    target = session.control.target
    np.testing.assert_allclose(target, np.asarray(session.control.bounds).mean(0), atol=1e-6)


def test_r_undoes_the_camera_and_every_keys_change_but_the_engine(session):
    view = session.camera().view.copy()
    opened = session.options()
    session.press(10, 10, pan=False)
    session.move(40, 30)
    session.release()
    for key in "mwaxbloe":  # shading, wireframe, aa, shadows, background, lights, ortho, engine
        session.char(key)
    changed = session.options()
    assert not np.allclose(session.camera().view, view)
    assert session.control.orthographic
    assert (changed.shading, changed.wireframe, changed.background) != \
        (opened.shading, opened.wireframe, opened.background)
    session.take_notices()
    session.char("r")
    assert session.take_notices() == [RESET_SAID]
    after = session.options()
    np.testing.assert_allclose(session.camera().view, view, atol=1e-9)
    assert not session.control.orthographic
    for name in ("shading", "wireframe", "background", "shadows", "aa", "lights"):
        assert getattr(after, name) == getattr(opened, name), name
    assert after.engine == changed.engine != opened.engine  # the engine stays
    assert "the engine stays" in KEYMAP["r"].description
    assert all(word in KEYMAP["r"].description for word in
               ("camera", "shading", "wireframe", "background", "shadows", "anti-aliasing",
                "lights"))

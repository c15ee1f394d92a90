"""The Python API raises documented FacetError subclasses for a user's mistakes, and the
headless context failure says what to install."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from facet.errors import ContextError, FacetError, InputError
from facet.geometry.camera import Camera
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, Mesh, PointLight, Scene, SpotLight

from conftest import sphere_mesh

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("kwargs,message", [
    (dict(width=0, height=10), "width and height must be >= 1"),
    (dict(width=10, height=10**6), "height must be between 1 and"),
    (dict(width=10.5, height=10), "expected two integers"),
    (dict(width=10, height=10, msaa=3), "msaa must be one of 0, 2, 4, 8, got 3"),
    (dict(width=10, height=10, shading="toon"), "unknown shading model 'toon'"),
    (dict(width=10), "give both width and height"),
    (dict(outputs=("color", "albedo")), "unknown output channel 'albedo'"),
    (dict(lights="sun"), "unknown lights mode 'sun'"),
    (dict(speed=3), "unknown render option 'speed'"),
])
def test_renderer_arguments(kwargs, message):
    with pytest.raises(InputError, match=message):
        Renderer(**kwargs)


def test_msaa_beyond_the_driver_limit_is_clamped_with_a_warning(renderer):
    """One policy everywhere (Python, CLI, scene files, viewer): MSAA above the context's
    maximum is lowered to it, with one warning line naming the maximum."""
    from facet.errors import FacetWarning

    r = renderer(24, 24)
    max_samples = r.ctx.max_samples
    scene = Scene()
    scene.add(sphere_mesh(2))
    if max_samples >= 8:
        pytest.skip(f"this GL offers {max_samples} samples: nothing to clamp")
    with pytest.warns(FacetWarning, match=f"msaa:8 .*max {max_samples} samples.*using msaa"):
        clamped = r.render(scene, msaa=8, outputs=("color",)).color
    best = max(n for n in (2, 4) if n <= max_samples)
    assert np.array_equal(clamped, r.render(scene, msaa=best, outputs=("color",)).color)


def test_render_arguments(renderer):
    r = renderer(16, 16)
    scene = Scene()
    with pytest.raises(InputError, match="scene is empty"):
        r.render(scene)  # no camera to frame an empty scene with
    scene.add(sphere_mesh(1))
    with pytest.raises(InputError, match="unknown output channel 'albedo'"):
        r.render(scene, outputs=("color", "albedo"))
    intr = Camera.from_intrinsics(10, 10, 7.5, 7.5, 32, 32)
    with pytest.raises(InputError, match="intrinsics are for 32x32"):
        r.render(scene, intr)


@pytest.mark.parametrize("make,message", [
    (lambda: Mesh([[0, 0, 0], [1, 0, 0]], [[0, 1, 2]]), "face indices must be in"),
    (lambda: Mesh(np.zeros((3, 3)), np.zeros((0, 3), int)), "no faces"),
    (lambda: Mesh([[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]], [[0, 1, 2]]), "NaN or infinite"),
    (lambda: Material(color=(1.5, 0, 0)), "material color"),
    (lambda: Material(shininess=-1), "shininess must be a number >= 0"),
    (lambda: DirectionalLight(direction=(0, 0, 0)), "zero vector"),
    (lambda: PointLight(attenuation=(0, 0, 0)), "attenuation"),
    (lambda: SpotLight(inner_angle=40, outer_angle=30), "inner_angle <= outer_angle"),
    (lambda: Scene(background=(1, 1)), "background"),
    (lambda: Scene().add("bunny.obj"), "mesh: expected a facet.Mesh"),
    (lambda: Scene().add(sphere_mesh(0), transform=np.zeros((4, 4))), "singular"),
    (lambda: Camera.look_at((0, 0, 1), (0, 0, 1)), "same point"),
    (lambda: Camera.look_at((0, 0, 1), (0, 0, 0), near=2, far=1), "near < far"),
    (lambda: Camera.look_at((0, 0, 1), (0, 0, 0), ortho_height=-1), "ortho_height"),
    (lambda: Camera.from_intrinsics(-5, 5, 1, 1, 4, 4), "fx: expected a finite number > 0"),
])
def test_scene_and_camera_validation(make, message):
    with pytest.raises(FacetError, match=message):
        make()


def test_too_many_lights():
    scene = Scene()
    for _ in range(16):
        scene.add_light(DirectionalLight())
    with pytest.raises(InputError, match="at most 16 lights"):
        scene.add_light(DirectionalLight())


def test_no_context_error_says_what_to_install(tmp_path):
    """With EGL pointed at no vendor library, context creation fails with one clear line
    (EGL alone: the OSMesa fallback has its own tests, tests/test_osmesa.py)."""
    env = {**os.environ, "__EGL_VENDOR_LIBRARY_FILENAMES": str(tmp_path / "none.json"),
           "PYTHONPATH": str(ROOT / "app"), "FACET_GL_BACKEND": "egl"}
    res = subprocess.run([sys.executable, "-m", "facet", "info"], capture_output=True,
                         text=True, env=env)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert "cannot create a headless OpenGL" in res.stderr
    assert "apt-get install libegl1 libgl1-mesa-dri" in res.stderr
    code = ("from facet.errors import ContextError\nfrom facet.render.renderer import Renderer\n"
            "try:\n    Renderer(8, 8)\nexcept ContextError as e:\n    print('ContextError')")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert res.stdout.strip() == "ContextError"
    assert issubclass(ContextError, FacetError)


def test_bad_arguments_from_python_are_facets_errors_naming_them(renderer):
    """Frame.save(quality=101), colored_by with text, a Session event with a non-number:
    facet's own errors with the argument's name, as the command line gives (quality 101
    was written silently; text values were numpy's ValueError)."""
    import numpy as np
    import pytest

    import facet
    from facet.errors import InputError

    frame = renderer(8, 8).render(facet.load(facet.paths.default_model()))
    for quality in (101, 0, "x", True, 50.5):
        with pytest.raises(InputError, match="quality"):
            frame.save("/tmp/never-written.jpg", quality=quality)
    mesh = facet.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(InputError, match="colored_by: values"):
        mesh.colored_by(["a", "b", "c"])
    points = facet.Points(np.zeros((2, 3)))
    with pytest.raises(InputError, match="colored_by: values"):
        points.colored_by([{"x": 1}, None])
    from facet.viewing.session import Session

    with Session(facet.load(facet.paths.default_model()), size=(16, 16),
                 renderer=renderer(16, 16)) as session:
        for event in ({"type": "pointer_move", "x": "a", "y": 0},
                      {"type": "wheel", "dy": float("nan")}, {"type": "resize", "width": [1]}):
            with pytest.raises(InputError, match=r"\.(x|dy|width):"):
                session.handle(event)


def test_a_render_that_sees_nothing_says_why():
    """Camera.from_intrinsics given an OpenGL-convention pose looks away from the model:
    the empty picture comes with one warning line naming the likely causes (it came with
    none); a camera that sees the model says nothing."""
    import warnings

    import numpy as np

    import facet

    scene = facet.Scene()
    scene.add(facet.primitives.cube(1.0))
    gl_pose = np.eye(4)
    gl_pose[:3, 3] = (0.0, 0.0, 4.0)  # an OpenGL camera at +z looking down -z at the cube
    away = facet.Camera.from_intrinsics(60, 60, 32, 32, 64, 64, pose=gl_pose)
    cv_pose = gl_pose.copy()
    cv_pose[:3, :3] = np.diag([1.0, -1.0, -1.0])  # the same camera in OpenCV's axes
    seeing = facet.Camera.from_intrinsics(60, 60, 32, 32, 64, 64, pose=cv_pose)
    with facet.Renderer(64, 64) as r:
        with pytest.warns(facet.FacetWarning, match="nothing of the scene .* other "
                                                    "convention"):
            frame = r.render(scene, away)
        assert (frame.object_ids >= 0).sum() == 0
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            frame = r.render(scene, seeing)
        assert (frame.object_ids >= 0).sum() > 100

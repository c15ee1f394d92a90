"""The public API's one boundary (facet.boundary), walked: every public callable in
tests/api_walk.py's table, each argument replaced by bad values hypothesis draws from its
annotation, in a child process under a 4 GiB address-space limit and a timeout. Any
exception but facet's own, an error that does not name the argument, a MemoryError or a
hang fails. And the mechanism itself: errors are TypeError / ValueError subclasses as
Python code expects, each names the callable, the argument, what was expected and what was
given, and the entry points declare their checks (``__facet_checked__``)."""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys

import numpy as np
import pytest

import facet
from facet.boundary import ArgumentError
from facet.errors import InputError

from conftest import ROOT

MEMORY = 4 << 30

CHECKED = ["Splats", "Splats.from_colors", "Splats.load", "Environment", "Environment.sky",
           "Environment.constant", "Environment.from_faces", "Environment.from_equirect",
           "load", "open_scene", "load_scene", "Mesh", "Mesh.load", "Mesh.load_parts",
           "Points", "Lines", "Texture", "Texture.load", "Camera.look_at", "Camera.frame",
           "Camera.from_intrinsics", "Camera.orbit", "Camera.projection", "Scene",
           "Scene.add", "Scene.add_light", "Scene.add_camera", "Mesh.colored_by",
           "Points.colored_by", "Points.sized", "Lines.widened", "Renderer.render",
           "Renderer.samples", "Renderer.present", "Frame.save", "ShaderToy",
           "ShaderToy.render", "ShaderToy.step", "ShaderToy.set_uniform", "ShaderToy.resize",
           "batch.render_dataset", "view", "show", "primitives.sphere", "primitives.cube",
           "primitives.cone", "primitives.cylinder", "primitives.disk", "primitives.plane",
           "primitives.torus", "transforms.translate", "transforms.scale", "transforms.rotate",
           "transforms.rotate_x", "transforms.rotate_y", "transforms.rotate_z",
           "transforms.look_at", "transforms.perspective", "transforms.orthographic",
           "transforms.normal_matrix", "transforms.transform_points"]
# Checked in their own construction (dataclasses: facet.boundary.reals / finite), walked:
# Material, PbrMaterial, TextureSlot, Intrinsics, the lights; shapes through their helpers.


def _limit():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


@pytest.mark.slow
def test_the_walk_finds_nothing(tmp_path):
    run = subprocess.run([sys.executable, str(ROOT / "tests" / "api_walk.py"), "60"],
                         capture_output=True, text=True, timeout=600, preexec_fn=_limit,
                         env={**os.environ, "FACET_WALK_DATA": str(tmp_path)})
    assert run.returncode == 0 and run.stdout.strip().endswith("walked"), run.stderr[-3000:]
    findings = [json.loads(line) for line in run.stdout.splitlines() if line.startswith("{")]
    assert not findings, "\n".join(json.dumps(f) for f in findings[:40])


@pytest.mark.parametrize("name", CHECKED)
def test_each_entry_point_checks_its_arguments(name):
    target = facet
    for part in name.split("."):
        target = getattr(target, part)
    if isinstance(target, type):
        target = target.__init__
    assert getattr(target, "__facet_checked__", False), f"{name} is not @checked"


@pytest.mark.parametrize("call,argument,error", [
    (lambda: facet.Splats(np.zeros(3), np.ones((1, 3)), [[1, 0, 0, 0]], [0.5],
                          np.zeros((1, 1, 3))), "means", InputError),
    (lambda: facet.Splats.from_colors(np.zeros((2, 3)), np.ones((2, 3)),
                                      np.tile([1.0, 0, 0, 0], (2, 1)), [0.5, 0.5],
                                      np.zeros(3)), "colors", InputError),
    (lambda: facet.Environment(np.zeros((0, 4, 4, 3))), "faces", InputError),
    (lambda: facet.Environment(np.zeros((6, 4, 4, 3)) + 1j), "faces", ArgumentError),
    (lambda: facet.Environment(np.zeros((6, 4, 4, 3)), equirect=np.zeros((8, 3))),
     "equirect", InputError),
    (lambda: facet.Environment(np.zeros((6, 4, 4, 3)), equirect=np.full((4, 8, 3), np.nan)),
     "equirect", InputError),
    (lambda: facet.Environment(np.broadcast_to(np.float32(0.5), (6, 16384, 16384, 3))),
     "faces", InputError),
    (lambda: facet.Environment.sky(size=0), "size", InputError),
    (lambda: facet.Environment.sky(size=1 << 20), "size", InputError),
    (lambda: facet.load(None), "path", ArgumentError),
    (lambda: facet.Mesh.load(3.5), "path", ArgumentError),
    (lambda: facet.Camera.look_at("eye", (0, 0, 0)), "eye", ArgumentError),
    (lambda: facet.Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=float("nan")), "fov_y",
     InputError),
    (lambda: facet.Scene().add(None), "mesh", ArgumentError),
])
def test_a_bad_argument_is_one_named_error(call, argument, error):
    """Each refusal is facet's error of the right kind (ArgumentError: also a TypeError;
    InputError: a ValueError), naming the callable's argument and what was given."""
    with pytest.raises(error) as caught:
        call()
    message = str(caught.value)
    assert f"{argument}:" in message and "expected" in message, message
    assert isinstance(caught.value, TypeError if error is ArgumentError else ValueError)


def test_a_scene_environment_of_the_wrong_kind_is_one_line(renderer):
    renderer = renderer(8, 8)
    scene = facet.Scene()
    scene.add(facet.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
                         np.array([[0, 1, 2]])))
    scene.environment = 3
    with pytest.raises(InputError, match="environment: expected 'sky'"):
        renderer.render(scene, facet.Camera.look_at((0, 0, 3), (0, 0, 0)), size=(8, 8))
    scene.environment = "sky"  # a spec, as the option takes it
    frame = renderer.render(scene, facet.Camera.look_at((0, 0, 3), (0, 0, 0)), size=(8, 8),
                            outputs=("color",))
    assert frame.color.shape == (8, 8, 4)

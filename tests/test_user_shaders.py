"""User shaders on meshes and the bundled examples (real GL)."""

from pathlib import Path

import numpy as np
import pytest

from facet.errors import InputError, SceneError
from facet.formats import load_scene
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.lab.shadertoy import ShaderToy
from facet.scene import Material, Scene
from facet.scene.light import camera_rig
from facet.scene.shader import UserShader

from conftest import sphere_mesh
from reference import erode

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "glsl" / "examples"
SIZE = 64
CAMERA = Camera.look_at((1.5, 1.0, 3.5), (0, 0, 0), fov_y=40, near=1, far=10)


def _scene(material, transform=None, mesh=None):
    scene = Scene()
    scene.add(mesh or sphere_mesh(4), material, transform)
    for light in camera_rig(CAMERA.view):
        scene.add_light(light)
    return scene


def test_normal_matrix_shader_equals_the_built_in_normals_view(renderer, tmp_path):
    """A user vertex + fragment shader that outputs (M^-1)^T n as colour gives the same
    picture as --shading normals, under a non-uniform scale and shear."""
    (tmp_path / "n.vert").write_text(
        "#version 330 core\nin vec3 in_position;\nin vec3 in_normal;\nuniform mat4 u_mvp;\n"
        "uniform mat3 u_normal_matrix;\nout vec3 v_n;\nvoid main() {\n"
        "    gl_Position = u_mvp * vec4(in_position, 1.0);\n"
        "    v_n = u_normal_matrix * in_normal;\n}\n")
    (tmp_path / "n.frag").write_text(
        "#version 330 core\nin vec3 v_n;\nout vec4 f_color;\n"
        "void main() { f_color = vec4(normalize(v_n) * 0.5 + 0.5, 1.0); }\n")
    m = T.compose(T.scale((1.0, 0.5, 1.5)), T.shear(xy=0.4))
    r = renderer(SIZE, SIZE)
    builtin = r.render(_scene(Material(), m), CAMERA, shading="normals").color
    user = Material(shader=UserShader(tmp_path / "n.frag", tmp_path / "n.vert"))
    mine = r.render(_scene(user, m), CAMERA).color
    assert np.abs(mine.astype(int) - builtin).max() <= 1
    example = r.render(_scene(Material(shader=UserShader(EXAMPLES / "normals.frag")), m),
                       CAMERA).color
    assert np.abs(example.astype(int) - builtin).max() <= 1


@pytest.mark.parametrize("name", ["toon", "rim", "normals", "checker"])
def test_mesh_examples_render_non_trivial_images(renderer, name):
    from facet.scene import primitives

    material = Material(color=(0.9, 0.5, 0.2), shader=UserShader(EXAMPLES / f"{name}.frag"))
    frame = renderer(SIZE, SIZE).render(_scene(material, mesh=primitives.sphere(1.0)), CAMERA,
                                        outputs=("color", "ids"))
    hit = frame.object_ids == 0
    colors = frame.color[..., :3][hit].astype(int)
    assert hit.mean() > 0.2 and colors.max() > 60
    assert colors.std(axis=0).max() > 8  # not one flat colour
    assert np.all(frame.color[..., :3][~hit] == 0)  # background untouched


def test_the_waves_example_is_its_formula():
    """glsl/examples/waves.frag at two times equals its formula evaluated in numpy at every
    pixel centre (the picture moves as the formula says)."""
    w, h = 96, 54
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    uv = np.stack([x / w, y / h], -1)
    with ShaderToy(EXAMPLES / "waves.frag", size=(w, h)) as toy:
        for t in (1.0, 2.0):
            got = toy.render(t)[::-1]  # row 0 of the array is the top; fragCoord's y is up
            d = np.linalg.norm((uv - 0.5) * [w / h, 1.0], axis=-1)
            wave = 0.5 + 0.5 * np.sin(30.0 * d - 4.0 * t)
            uvx = np.stack([uv[..., 0], uv[..., 1], uv[..., 0]], -1)
            color = 0.5 + 0.5 * np.cos(t + uvx * 3.0 + [0.0, 2.0, 4.0])
            expected = color * (0.6 + 0.4 * wave)[..., None]
            assert np.abs(got[..., :3] - expected).max() < 2e-3, t


def test_the_sdf_example_moves_and_is_deterministic():
    with ShaderToy(EXAMPLES / "sdf.frag", size=(96, 54)) as toy:
        a, b, again = toy.render(1.0), toy.render(2.0), toy.render(1.0)
    assert np.array_equal(a, again)  # a time is one picture
    assert a[..., :3].std() > 0.05 and np.abs(a - b).mean() > 0.005  # and time moves it


def test_user_shader_reload_and_errors(renderer, tmp_path):
    frag = tmp_path / "live.frag"
    lib = tmp_path / "lib.glsl"
    lib.write_text("vec3 tint() { return vec3(1.0, 0.0, 0.0); }\n")
    frag.write_text('#version 330 core\n#include "lib.glsl"\nout vec4 c;\n'
                    "void main() { c = vec4(tint(), 1.0); }\n")
    r = renderer(SIZE, SIZE)
    scene = _scene(Material(shader=UserShader(frag)))
    centre = lambda: r.render(scene, CAMERA).color[SIZE // 2, SIZE // 2, :3]  # noqa: E731
    assert tuple(centre()) == (255, 0, 0)
    with r.ctx:
        assert r.user_programs().reload().changed is False
    lib.write_text("vec3 tint() { return vec3(0.0, 1.0, 0.0); }\n")
    with r.ctx:
        assert r.user_programs().reload().success
    assert tuple(centre()) == (0, 255, 0)
    lib.write_text("// line 1\nvec3 tint() { return vec3(zero); }\n")
    with r.ctx:
        result = r.user_programs().reload()
    assert not result.success and "lib.glsl:2:" in result.errors.splitlines()[0]
    assert tuple(centre()) == (0, 255, 0)  # the last good program keeps drawing
    lib.write_text("vec3 tint() { return vec3(0.0, 0.0, 1.0); }\n")
    with r.ctx:
        assert r.user_programs().reload().success
    assert tuple(centre()) == (0, 0, 255)


def test_scene_file_shaders_and_uniforms(renderer, tmp_path):
    (tmp_path / "s.toml").write_text(f"""
[uniforms]
u_squares = 2
[materials.board]
shader = "{EXAMPLES / 'checker.frag'}"
uniforms = {{ u_squares = 4 }}
[materials.flat]
shader = "{EXAMPLES / 'toon.frag'}"
[[objects]]
primitive = "sphere"
material = "board"
""")
    scene = load_scene(tmp_path / "s.toml")
    shader = scene.objects[0].material.shader
    assert shader.fragment.name == "checker.frag" and shader.uniforms == {"u_squares": [4.0]}
    frame = renderer(SIZE, SIZE).render(scene, CAMERA, outputs=("color", "uv", "ids"),
                                        msaa=0)
    # The uniform's effect: the checker cells follow floor(uv * u_squares) with the
    # material's 4, not the file-wide 2 nor the shader's default 8.
    hit = erode(frame.object_ids == 0, 1)
    bright = frame.color[..., :3].max(axis=2)[hit].astype(int)

    def agreement(squares):
        cell = np.floor(frame.uv[hit] * squares)
        dark = cell.sum(axis=1) % 2 == 0  # mod(x + y, 2) == 0: the 0.15 albedo
        return (np.where(dark, bright < np.median(bright), bright >= np.median(bright))).mean()

    assert agreement(4) > 0.9 and agreement(2) < 0.75 and agreement(8) < 0.75
    (tmp_path / "bad.toml").write_text('[materials.m]\nshader = "none.frag"\n')
    with pytest.raises(SceneError, match=r"materials\.m\.shader: .*none\.frag: no such"):
        load_scene(tmp_path / "bad.toml")


def test_bad_user_uniforms(renderer):
    for uniforms, message in (({"u_nope": [1]}, "no user uniform named 'u_nope'; it has: u_steps"),
                              ({"u_steps": [1, 2]}, "u_steps is float: expected 1")):
        material = Material(shader=UserShader(EXAMPLES / "toon.frag", uniforms=uniforms))
        with pytest.raises(InputError, match=message):
            renderer(16, 16).render(_scene(material), CAMERA)


def test_list_uniforms_of_a_mesh_shader(capsys):
    from facet.cli import main

    assert main(["shader", "--list-uniforms", str(EXAMPLES / "toon.frag")]) == 0
    rows = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()}
    assert "user" in rows["u_steps"] and "float" in rows["u_steps"]
    assert "filled by facet" in rows["u_normal_matrix"] and "mat3" in rows["u_normal_matrix"]


def test_the_readme_multipass_and_glslviewer_examples_run():
    """glsl/examples/trail (a buffer with feedback, as a TOML project) and book.frag (The
    Book of Shaders style): pictures that are not flat and that move."""
    from facet.lab.project import load_project

    with ShaderToy(project=load_project(EXAMPLES / "trail" / "trail.toml"),
                   size=(96, 54)) as toy:
        a, b = toy.render(1.0), toy.render(1.5)
    assert a[..., 0].max() > 0.8 and np.abs(a - b).mean() > 0.002  # a trail that moves
    with ShaderToy(EXAMPLES / "book.frag", size=(96, 54)) as toy:
        a, b = toy.render(0.5, mouse=(48, 27, 0, 0)), toy.render(1.0)
    assert a[..., :3].std() > 0.05 and np.abs(a - b).mean() > 0.005
    assert np.allclose(a[27, 48, :3], 1.0)  # the circle under the mouse

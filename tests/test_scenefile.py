"""Scene files: the same scene as the Python API (pixel-identical), transform lists, parents,
glTF hierarchies, and every kind of bad file -> one SceneError naming file and key path."""

import numpy as np
import pytest
import trimesh

from facet.errors import SceneError
from facet.formats import load_scene
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, PointLight, Scene, shapes

SCENE = """
[render]
size = [64, 48]
background = [0.1, 0.2, 0.3]
msaa = 0
camera = "main"

[materials.red]
color = [0.9, 0.2, 0.1]
ks = 0.5
shininess = 64

[[objects]]
name = "ground"
primitive = "plane"
size = [4, 3]
material = { color = [0.5, 0.5, 0.5], ks = 0 }

[[objects]]
name = "table"
transform = [{translate = [0, 0.5, 0]}]

[[objects]]
name = "ball"
primitive = "sphere"
radius = 0.4
parent = "table"
material = "red"
transform = [{translate = [0.6, 0, 0]}]

[[objects]]
name = "box"
primitive = "cube"
size = [0.5, 0.3, 0.5]
parent = "table"
transform = [{shear = {xy = 0.3}}, {rotate = {axis = "y", degrees = 30}},
             {translate = [-0.6, 0, 0]}]

[[lights]]
type = "ambient"
intensity = 0.15

[[lights]]
type = "directional"
direction = [-1, -2, -1]

[[lights]]
type = "point"
position = [1, 2, 2]
intensity = 0.5
attenuation = [1, 0, 0.1]

[cameras.main]
type = "perspective"
eye = [2, 2, 3]
target = [0, 0.4, 0]
fov = 45
near = 0.5
far = 20

[cameras.top]
type = "orthographic"
eye = [0, 5, 0.001]
target = [0, 0, 0]
height = 4
"""


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def api_scene() -> Scene:
    scene = Scene(ambient=0.15, background=(0.1, 0.2, 0.3))
    table = T.translate((0, 0.5, 0))
    # A scene file's primitives are the exact shapes (facet.shapes), drawn tessellated.
    scene.add(shapes.Plane((4, 3)), Material(color=(0.5, 0.5, 0.5), ks=0))
    scene.add(shapes.Sphere(0.4), Material(color=(0.9, 0.2, 0.1), ks=0.5, shininess=64),
              table @ T.translate((0.6, 0, 0)))
    box = T.compose(T.shear(xy=0.3), T.rotate_y(30), T.translate((-0.6, 0, 0)))
    scene.add(shapes.Box((0.5, 0.3, 0.5)), None, table @ box)
    scene.add_light(DirectionalLight((-1, -2, -1)))
    scene.add_light(PointLight((1, 2, 2), intensity=0.5, attenuation=(1, 0, 0.1)))
    return scene


def test_scene_file_matches_the_api_pixel_for_pixel(tmp_path, renderer):
    loaded = load_scene(_write(tmp_path, SCENE))
    assert loaded.options["size"] == (64, 48) and loaded.options["aa"].kind == "none"
    assert [o.name for o in loaded.objects] == ["ground", "ball", "box"]
    camera = Camera.look_at((2, 2, 3), (0, 0.4, 0), fov_y=45, near=0.5, far=20)
    assert np.allclose(loaded.camera().view, camera.view)
    r = renderer(64, 48)
    a = r.render(loaded, loaded.camera())
    b = r.render(api_scene(), camera)
    assert np.array_equal(a.color, b.color)
    assert np.array_equal(a.depth, b.depth) and np.array_equal(a.object_ids, b.object_ids)
    assert set(np.unique(a.object_ids)) == {-1, 0, 1, 2}
    top = loaded.camera("top")
    assert top.is_orthographic and top.ortho_height == 4


def test_transform_list_order(tmp_path):
    """Steps apply first to last: [shear, rotate] is R @ Sh, and differs from [rotate, shear]."""
    base = '[[objects]]\nprimitive = "cube"\ntransform = [{}, {}]\n'
    shear, rot = "{shear = {xy = 0.5}}", '{rotate = {axis = "z", degrees = 90}}'
    a = load_scene(_write(tmp_path, base.format(shear, rot))).objects[0].transform
    b = load_scene(_write(tmp_path, base.format(rot, shear))).objects[0].transform
    r, sh = T.rotate_z(90), T.shear(xy=0.5)
    assert np.allclose(a, r @ sh) and np.allclose(b, sh @ r)
    assert not np.allclose(a, b)
    m = load_scene(_write(tmp_path, '[[objects]]\nprimitive = "cube"\nmatrix = '
                          '[[1,0,0,2],[0,1,0,3],[0,0,1,4],[0,0,0,1]]\n')).objects[0].transform
    assert np.allclose(m, T.translate((2, 3, 4)))


def test_parents_compose_over_several_levels(tmp_path):
    text = """
[[objects]]
name = "c"
primitive = "sphere"
parent = "b"
transform = [{translate = [0, 0, 1]}]
[[objects]]
name = "a"
transform = [{scale = 2}]
[[objects]]
name = "b"
parent = "a"
transform = [{rotate = {axis = "y", degrees = 90}}, {translate = [1, 0, 0]}]
"""
    scene = load_scene(_write(tmp_path, text))
    (c,) = scene.objects
    expected = T.scale(2) @ T.compose(T.rotate_y(90), T.translate((1, 0, 0))) @ \
        T.translate((0, 0, 1))
    assert np.allclose(c.transform, expected)
    assert np.allclose(c.transform @ [0, 0, 0, 1], [4, 0, 0, 1])


def test_gltf_keeps_its_node_hierarchy(tmp_path):
    tm = trimesh.Scene()
    tm.add_geometry(trimesh.creation.box(), node_name="left", transform=T.translate((-2, 0, 0)))
    tm.add_geometry(trimesh.creation.icosphere(), node_name="right",
                    transform=T.compose(T.scale(0.5), T.translate((2, 1, 0))))
    tm.export(tmp_path / "parts.glb")
    scene = load_scene(_write(tmp_path, '[[objects]]\nname = "model"\nmesh = "parts.glb"\n'
                              'transform = [{translate = [0, 0, -1]}]\n'))
    assert len(scene.objects) == 2
    centres = sorted(tuple(np.round(o.world_bounds.mean(axis=0), 3)) for o in scene.objects)
    assert centres == [(-2.0, 0.0, -1.0), (2.0, 1.0, -1.0)]
    sizes = sorted(np.round(np.ptp(o.world_bounds, axis=0)[0], 3) for o in scene.objects)
    assert sizes == [1.0, 1.0]  # the unit box, and the radius-1 sphere scaled by 0.5


BAD = [
    ("[render\nsize = 3\n", r"scene\.toml: invalid TOML: .*line 1"),
    ('[[objects]]\nprimitive = "sphere"\nmaterial = { shininess = "shiny" }\n',
     r'scene\.toml: objects\[0\]\.material\.shininess: expected a number >= 0, got "shiny"'),
    ('[[objects]]\nprimitiv = "sphere"\n', r"objects\[0\]\.primitiv: unknown key; did you mean "
                                           r"'primitive'\?"),
    ("[rendr]\n", r"rendr: unknown key; did you mean 'render'\?"),
    ('[[objects]]\nmesh = "missing.obj"\n', r"objects\[0\]\.mesh: .*missing\.obj: no such file"),
    ('[[objects]]\nname = "a"\nparent = "b"\n[[objects]]\nname = "b"\nparent = "a"\n',
     r"parent cycle: a -> b -> a"),
    ('[[objects]]\nname = "a"\nparent = "tabel"\n[[objects]]\nname = "table"\n',
     r"objects\[0\]\.parent: no object named \"tabel\" \(did you mean 'table'\?\)"),
    ('[[objects]]\nprimitive = "cube"\n[cameras.c]\ntype = "perspective"\neye = [0, 3, 0]\n'
     'target = [0, 0, 0]\n', r"cameras\.c: the camera looks along its up vector"),
    ('[[objects]]\nprimitive = "sphere"\nradius = 0\n',
     r"objects\[0\]\.radius: expected a number > 0, got 0"),
    ('[[objects]]\nprimitive = "cube"\nradius = 1\n', r"objects\[0\]\.radius: cube takes size"),
    ('[[objects]]\nprimitive = "sphere"\nmaterial = "gold"\n', r'no material named "gold"'),
    ('[[objects]]\nprimitive = "spere"\n', r"did you mean 'sphere'"),
    ('[[objects]]\nprimitive = "cube"\ntransform = [{scale = 0}]\n', r"a scale of 0"),
    ('[[lights]]\ntype = "point"\nposition = [0, 1]\n',
     r"lights\[0\]\.position: expected 3 numbers"),
    ('[render]\ncamera = "nope"\n', r'render\.camera: no camera named "nope"'),
    ('[[objects]]\nprimitive = "cube"\nmaterial = { color = [2, 0, 0] }\n',
     r"objects\[0\]\.material\.color: expected colour values in \[0, 1\]"),
]


@pytest.mark.parametrize("text,pattern", BAD, ids=[p[:30] for _, p in BAD])
def test_bad_scene_files(tmp_path, text, pattern):
    with pytest.raises(SceneError, match=pattern) as info:
        load_scene(_write(tmp_path, text))
    assert "\n" not in str(info.value)


def test_bad_scene_file_from_the_cli(tmp_path, capsys):
    from facet.cli import main

    path = _write(tmp_path, BAD[1][0])
    code = main(["render", str(path), "-o", str(tmp_path / "out.png")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert 'objects[0].material.shininess: expected a number >= 0, got "shiny"' in err
    assert not (tmp_path / "out.png").exists()


def test_cli_renders_a_scene_file_with_its_settings(tmp_path, capsys):
    from PIL import Image

    from facet.cli import main

    path = _write(tmp_path, SCENE)
    assert main(["render", str(path), "-o", str(tmp_path / "s.png")]) == 0
    img = np.asarray(Image.open(tmp_path / "s.png"))
    assert img.shape == (48, 64, 3)  # size from [render]
    assert tuple(img[0, 0]) == (26, 51, 76)  # background from [render]
    assert main(["render", str(path), "--camera", "top", "--size", "40x40", "-o",
                 str(tmp_path / "t.png")]) == 0
    assert np.asarray(Image.open(tmp_path / "t.png")).shape == (40, 40, 3)


def test_documented_example_is_the_bundled_one_and_renders(renderer):
    """docs/scene-format.md's complete example is models/example.toml, and it renders every
    object with each of its three camera kinds."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    doc = (root / "docs" / "scene-format.md").read_text()
    block = re.search(r"## A complete example.*?```toml\n(.*?)```", doc, re.S).group(1)
    assert block == (root / "models" / "example.toml").read_text()
    scene = load_scene(root / "models" / "example.toml")
    assert [o.name for o in scene.objects] == ["floor", "top", "ball", "box", "knot", "ring"]
    assert set(scene.cameras) == {"main", "top", "dataset"}
    for name in ("main", "top", "dataset"):
        cam = scene.camera(name)
        size = (640, 480) if cam.intrinsics is not None else (160, 120)
        frame = renderer(*size).render(scene, cam)
        visible = set(np.unique(frame.object_ids)) - {-1}
        assert visible == set(range(6)), (name, visible)
    assert scene.camera("top").is_orthographic and scene.camera("dataset").intrinsics


def test_cli_intrinsics_camera_sets_the_image_size(tmp_path, capsys):
    from PIL import Image

    from facet.cli import main

    path = tmp_path / "s.toml"
    path.write_text('[[objects]]\nprimitive = "sphere"\n[cameras.k]\ntype = "intrinsics"\n'
                    "fx = 50\nfy = 50\ncx = 31.5\ncy = 23.5\nwidth = 64\nheight = 48\n"
                    "pose = [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 4], [0, 0, 0, 1]]\n")
    assert main(["render", str(path), "-o", str(tmp_path / "k.png"), "-q"]) == 0
    img = np.asarray(Image.open(tmp_path / "k.png"))
    assert img.shape == (48, 64, 3) and img[24, 32].max() > 50  # the sphere, centred
    code = main(["render", str(path), "--camera", "nope", "-o", str(tmp_path / "x.png")])
    assert code == 2 and "no camera named 'nope'" in capsys.readouterr().err


def test_a_top_level_constant_environment_is_the_render_tables(tmp_path, renderer):
    """``environment = {color = [r, g, b]}`` at the top of a scene file reads as it does
    under [render] (one parser: the top level refused it, "expected a non-empty string"),
    and both draw the same picture; a wrong key is one line naming it."""
    import facet
    from facet.errors import FacetError

    body = '[[objects]]\nprimitive = "sphere"\n'
    top = tmp_path / "top.toml"
    top.write_text("environment = {color = [0.2, 0.3, 0.4]}\n" + body)
    table = tmp_path / "table.toml"
    table.write_text(body + "[render]\nenvironment = {color = [0.2, 0.3, 0.4]}\n")
    r = renderer(32, 24)
    a, b = (r.render(facet.load(p), engine="path", spp=4, seed=1).color
            for p in (top, table))
    assert np.array_equal(a, b)
    bad = tmp_path / "bad.toml"
    bad.write_text("environment = {colour = [1, 1, 1]}\n" + body)
    with pytest.raises(FacetError, match="environment: a constant environment is"):
        facet.load(bad)

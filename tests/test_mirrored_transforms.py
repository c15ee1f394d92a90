"""Objects whose transform mirrors (negative determinant: ``scale = [-1, 1, 1]``, glTF's
NegativeScaleTest) look like the mirror image of the unmirrored object, in every engine:
their front faces stay front faces (culling and two-sided lighting follow the winding the
determinant gives, per draw), so they are not drawn dark or inside out."""

import numpy as np
import pytest

from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, Scene
from facet.scene.mesh import Mesh

from conftest import ROOT

S = 96
# The camera and the light lie in the plane x = 0, so mirroring the world in x maps the
# picture to itself flipped left to right (pixel centres are symmetric about the middle).
CAMERA = Camera.look_at((0.0, 1.2, 4.0), (0, 0, 0), fov_y=40, near=0.5, far=20)
LIGHT = DirectionalLight((0.0, -1.0, -0.8))


def _scene(mirror: bool, material=None):
    mesh = Mesh.load(ROOT / "models" / "default.obj")  # the torus knot: no symmetry in x
    scene = Scene(ambient=0.1)
    fit = T.compose(T.translate(-mesh.bounds.mean(0)), T.scale(1.5 / np.ptp(mesh.bounds)))
    place = T.compose(fit, T.rotate_y(30), T.rotate_x(-20))
    scene.add(mesh, material or Material(color=(0.9, 0.5, 0.2), ks=0.5),
              T.compose(place, T.scale((-1, 1, 1))) if mirror else place)
    scene.add_light(LIGHT)
    return scene


@pytest.mark.parametrize("cull", ["auto", "off"])
@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_a_mirrored_object_is_the_mirror_image(renderer, engine, cull):
    r = renderer(S, S)
    kw = dict(engine=engine, cull=cull, aa="none", outputs=("color", "ids", "normals"),
              float_color=True)
    plain = r.render(_scene(False), CAMERA, **kw)
    mirrored = r.render(_scene(True), CAMERA, **kw)
    ids = plain.object_ids[:, ::-1]
    both = (ids == 0) & (mirrored.object_ids == 0)
    assert both.sum() > 1000
    assert (ids != mirrored.object_ids).mean() < 0.005  # edge pixels may round either way
    expected = plain.color[:, ::-1, :3]
    diff = np.abs(expected - mirrored.color[..., :3]).max(-1)
    assert np.percentile(diff[both], 99) < 2 / 255, np.percentile(diff[both], 99)
    normals = plain.normals[:, ::-1] * np.array([-1.0, 1.0, 1.0])
    assert np.abs(normals[both] - mirrored.normals[both]).max() < 1e-3


def test_a_mirrored_object_in_a_scene_file_is_lit_like_its_twin(tmp_path, renderer):
    """The report's case: ``scale = [-1, 1, 1]`` in a scene file drew the model dark."""
    model = ROOT / "models" / "default.obj"
    (tmp_path / "twins.toml").write_text(f"""
[render]
aa = "none"
[[objects]]
mesh = "{model}"
transform = [{{translate = [0, 0, 0]}}]
[[objects]]
mesh = "{model}"
transform = [{{scale = [-1, 1, 1]}}]
[[lights]]
type = "directional"
direction = [0, -1, -0.8]
""")
    from facet.formats.source import open_scene

    scene = open_scene(tmp_path / "twins.toml")
    camera = Camera.look_at((0.0, 0.5, 6.0), (0, 0, 0), fov_y=40, near=0.5, far=30)
    r = renderer(S, S)
    a, b = Scene(ambient=scene.ambient), Scene(ambient=scene.ambient)
    for one, obj in ((a, scene.objects[0]), (b, scene.objects[1])):
        one.add(obj.mesh, obj.material, obj.transform)
        one.add_light(scene.lights[0])
    fa = r.render(a, camera, outputs=("color", "ids"), aa="none", float_color=True)
    fb = r.render(b, camera, outputs=("color", "ids"), aa="none", float_color=True)
    lit_a = fa.color[fa.object_ids == 0, :3].mean()
    lit_b = fb.color[fb.object_ids == 0, :3].mean()
    assert lit_a > 0.15 and abs(lit_a - lit_b) < 0.02 * lit_a, (lit_a, lit_b)


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_gltf_negative_scale_test_looks_like_its_reference(renderer, engine):
    """Khronos NegativeScaleTest: every cell shows a green check, none a red cross (a cross
    is the back of a single-sided panel, visible when winding or culling is wrong), and
    the spheres under scale -1 are lit like those under scale 1."""
    from facet.formats.source import open_scene

    from conftest import SHARED_GLTF, shared_model

    scene = open_scene(shared_model("NegativeScaleTest/NegativeScaleTest.glb", SHARED_GLTF))
    camera = Camera.frame(scene.bounds, (0.0, 0.0, -1.0), aspect=4 / 3)
    frame = renderer(384, 288).render(scene, camera, engine=engine, shadows=False,
                                      aa="none", outputs=("color",))
    rgb = frame.color[..., :3].astype(int)
    red = (rgb[..., 0] > 150) & (rgb[..., 1] < 90) & (rgb[..., 2] < 90)
    green = (rgb[..., 1] > 120) & (rgb[..., 0] < 90) & (rgb[..., 2] < 90)
    assert red.sum() == 0, f"{red.sum()} red pixels (crosses)"
    assert green.sum() > 300
    # The checks of the six cells: as many under scale -1 (lower row) as under scale 1.
    ys = np.nonzero(green)[0]
    upper, lower = (ys < np.median(ys)).sum(), (ys >= np.median(ys)).sum()
    assert abs(upper - lower) < 0.25 * max(upper, lower)

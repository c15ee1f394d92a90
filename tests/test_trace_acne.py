"""Shadow rays never shadow the surface they leave: every exact shape of the ray tracer
(sphere, box, cylinder, cone, disk, plane), sheared and scaled unevenly, lit at grazing
angles, at scene scales 1e-3, 1 and 1e3. A lone convex shape cannot shadow itself, so its
picture with shadows on must equal the picture with them off, pixel for pixel (acne shows
as lit pixels gone dark)."""

import numpy as np
import pytest

from facet.formats.source import open_scene
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, PointLight, Scene, shapes

S = 96
SHAPES = {
    "sphere": lambda: shapes.Sphere(0.8),
    "box": lambda: shapes.Box((1.2, 0.8, 1.0)),
    "cylinder": lambda: shapes.Cylinder(0.6, 1.4),
    "cone": lambda: shapes.Cone(0.5, 1.2),
    "disk": lambda: shapes.Disk(1.0),
    "plane": lambda: shapes.Plane((2.0, 1.5)),
}
PLACES = {
    "sheared": T.compose(T.shear(xy=0.6, zy=-0.3), T.rotate_y(35)),
    "uneven": T.compose(T.scale((1.6, 0.7, 1.1)), T.rotate_x(20), T.rotate_y(-25)),
}


def _lone(kind: str, place: str, unit: float):
    scene = Scene(ambient=0.05)
    scene.add(SHAPES[kind](), Material(color=(0.9, 0.4, 0.3)),
              T.compose(PLACES[place], T.scale(unit)))
    # Grazing: 3.4 degrees above the horizontal, so it skims every near-level face; the
    # point light close by, for rays of every direction.
    scene.add_light(DirectionalLight((-1.0, -0.06, -0.3)))
    scene.add_light(PointLight((1.2 * unit, 1.5 * unit, 1.4 * unit)))
    return scene


@pytest.mark.parametrize("unit", [1e-3, 1.0, 1e3])
@pytest.mark.parametrize("place", list(PLACES))
@pytest.mark.parametrize("kind", list(SHAPES))
def test_exact_shapes_do_not_shadow_themselves(renderer, kind, place, unit):
    scene = _lone(kind, place, unit)
    camera = Camera.frame(scene.bounds, (-0.4, -0.5, -1.0))
    r = renderer(S, S)
    kw = dict(engine="trace", aa="none", outputs=("color", "ids"), float_color=True)
    plain = r.render(scene, camera, shadows=False, **kw)
    shadowed = r.render(scene, camera, shadows=True, **kw)
    shape = plain.object_ids == 0
    assert shape.sum() > 400
    dark = np.abs(plain.color[..., :3] - shadowed.color[..., :3]).max(-1) > 1e-6
    assert not dark[shape].any(), f"{dark.sum()} of {shape.sum()} pixels shadowed"


CONE_ON_A_PLANE = """
[render]
size = [256, 256]
engine = "trace"
shadows = true
aa = "none"

[[objects]]
primitive = "plane"
size = [6, 6]

[[objects]]
primitive = "cone"
radius = 0.5
height = 1.2
material = { color = [0.9, 0.3, 0.2] }
transform = [{translate = [0, 0.6, 0]}]

[[lights]]
type = "directional"
direction = [-1, -1.5, -0.7]

[[lights]]
type = "point"
position = [1.5, 2.5, 2.0]

[cameras.main]
type = "perspective"
eye = [0, 1.5, 3.0]
target = [0, 0.5, 0]
"""


def test_the_cone_on_a_plane_has_no_acne(tmp_path, renderer):
    """The report's scene: speckles near the apex, where a ray through the two nappes of
    the cone's quadric has nearly equal roots and its hit point lay inside the cone."""
    path = tmp_path / "cone.toml"
    path.write_text(CONE_ON_A_PLANE)
    scene = open_scene(path)
    r = renderer(256, 256)
    kw = dict(outputs=("color", "ids"), float_color=True)
    plain = r.render(scene, shadows=False, **kw)
    shadowed = r.render(scene, **kw)
    cone = plain.object_ids == 1
    assert cone.sum() > 5000
    dark = np.abs(plain.color[..., :3] - shadowed.color[..., :3]).max(-1) > 1e-6
    assert not dark[cone].any(), f"{dark[cone].sum()} of {cone.sum()} cone pixels shadowed"
    floor = plain.object_ids == 0
    assert dark[floor].sum() > 1000  # the cone's shadow on the floor is there

"""Emitting analytic shapes as lights (facet.render.path.emitters): a point uniformly by
area on a sphere, disk, plane, box, cylinder or cone, weighed against BSDF sampling by
multiple importance sampling. A sphere lamp above a Lambertian floor against the closed
form (the floor below it shows albedo x L x (R / H)^2); every shape's light the same with
light sampling only, BSDF sampling only and both, both with less noise than BSDF sampling
alone (before, these shapes were found by BSDF sampling alone)."""

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.render.path.engine import PathEngine
from facet.scene.pbr import PbrMaterial

ALBEDO, RADIANCE, HEIGHT = 0.7, 3.0, 1.2
DOWN = Camera.look_at((0, 0.6, 0.001), (0, 0, 0), fov_y=20, near=0.05, far=10)


def _scene(shape, transform=None):
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(8.0),
              material=PbrMaterial(base_color=(ALBEDO,) * 3, metallic=0.0, specular=0.0))
    lamp = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0,
                       emissive=(1, 1, 1), emissive_strength=RADIANCE, double_sided=True)
    place = facet.transforms.translate((0, HEIGHT, 0))
    scene.add(shape, material=lamp, transform=place if transform is None else place @ transform)
    return scene


def _render(scene, strategy, spp, camera=DOWN, size=16):
    PathEngine.strategy = strategy
    try:
        with facet.Renderer(size, size) as r:
            return r.render(scene, camera, engine="path", spp=spp, max_depth=0,
                            float_color=True, lights="scene").color[..., :3]
    finally:
        PathEngine.strategy = "mis"


def test_a_sphere_lamp_lights_the_floor_below_as_the_closed_form_says():
    """A sphere of radius R and radiance L seen from a point H below its centre fills a
    cap of sin^2 = (R / H)^2 of the projected hemisphere: irradiance pi L (R / H)^2."""
    radius = 0.3
    colour = _render(_scene(facet.shapes.Sphere(radius)), "mis", 256, size=8)
    # the camera sees the floor right under the lamp (its 8 x 8 pixels within 0.1 of it)
    expected = ALBEDO * RADIANCE * (radius / HEIGHT) ** 2
    np.testing.assert_allclose(colour.mean(), expected, rtol=0.03)


SIDE = Camera.look_at((0, 2.5, 3.5), (0, 0.4, 0), fov_y=45, near=0.1, far=20)
SHAPES = {
    "sphere": (facet.shapes.Sphere(0.3), None),
    "disk": (facet.shapes.Disk(0.4), facet.transforms.rotate_x(180.0)),
    "plane": (facet.shapes.Plane((0.6, 0.4)), facet.transforms.rotate_x(180.0)),
    "box": (facet.shapes.Box((0.5, 0.2, 0.3)), facet.transforms.rotate_y(30.0)),
    "cylinder": (facet.shapes.Cylinder(0.2, 0.5), facet.transforms.rotate_z(60.0)),
    "cone": (facet.shapes.Cone(0.3, 0.5), facet.transforms.scale(1.5)),
}


@pytest.mark.parametrize("name", list(SHAPES))
def test_every_shape_is_light_sampled_to_the_same_picture_with_less_noise(name):
    shape, turn = SHAPES[name]
    scene = _scene(shape, turn)
    reference = _render(scene, "mis", 1024, camera=SIDE)
    floor = reference.mean(axis=-1) < 0.9 * RADIANCE  # not the lamp itself
    errors = {}
    for strategy in ("mis", "light", "bsdf"):
        converged = _render(scene, strategy, 256, camera=SIDE)
        assert converged[floor].mean() == pytest.approx(reference[floor].mean(), rel=0.03), \
            strategy
        picture = _render(scene, strategy, 16, camera=SIDE)
        errors[strategy] = np.sqrt(((picture - reference)[floor] ** 2).mean())
    assert errors["mis"] < 0.7 * errors["bsdf"], errors


def test_shape_areas_and_what_is_left_to_bsdf_sampling():
    from facet.render.path.emitters import shape_area

    def area(shape, transform=None):
        scene = facet.Scene()
        scene.add(shape, transform=np.eye(4) if transform is None else transform)
        return shape_area(scene.objects[0])

    assert area(facet.shapes.Sphere(0.5), facet.transforms.scale(2.0)) == \
        pytest.approx(4 * np.pi)
    assert area(facet.shapes.Cone(0.3, 0.4)) == pytest.approx(np.pi * 0.3 * (0.5 + 0.3))
    assert area(facet.shapes.Box((1, 2, 3))) == pytest.approx(22.0)
    assert area(facet.shapes.Cylinder(0.5, 2.0)) == pytest.approx(2 * np.pi * 0.5 * 2.5)
    # not uniform by area in the world: BSDF sampling alone finds them
    assert area(facet.shapes.Sphere(1.0), facet.transforms.scale((1, 2, 1))) == 0.0
    assert area(facet.shapes.Plane()) == 0.0


@pytest.mark.parametrize("shape", ["plane", "disk"])
def test_a_flat_light_under_an_uneven_scale_is_sampled_as_one_of_its_size(shape):
    """A plane light written as a 2 x 2 plane scaled 0.23 x 0.19 (how a Cornell box's is
    usually written), and a disk scaled unevenly (an ellipse), are light-sampled as the
    same lights written by their size: uniform area sampling of a flat shape stays uniform
    under any affine map (the old code left them to BSDF sampling: 0.156 block error
    against 0.008 at 64 spp). With light sampling only, the two pictures are the same
    samples at the same points."""
    from facet.render.path.emitters import shape_area

    flip = facet.transforms.rotate_x(180.0)
    if shape == "plane":
        sized = (facet.shapes.Plane((0.46, 0.38)), flip)
        scaled = (facet.shapes.Plane((2.0, 2.0)), flip @ facet.transforms.scale((0.23, 1, 0.19)))
    else:
        sized = None
        scaled = (facet.shapes.Disk(0.5), flip @ facet.transforms.scale((0.6, 1, 0.3)))
    scene = _scene(*scaled)
    assert shape_area(scene.objects[1]) == pytest.approx(
        0.46 * 0.38 if shape == "plane" else np.pi * 0.25 * 0.18)
    light = _render(scene, "light", 16, camera=SIDE)
    floor = light.mean(axis=-1) < 0.9 * RADIANCE
    assert light[floor].mean() > 0.01  # light sampling finds it
    reference = _render(scene, "mis", 512, camera=SIDE)
    error = np.sqrt(((light - reference)[floor] ** 2).mean())
    bsdf_error = np.sqrt(((_render(scene, "bsdf", 16, camera=SIDE) - reference)[floor] ** 2)
                         .mean())
    assert error < 0.7 * bsdf_error, (error, bsdf_error)
    if sized is not None:
        same = _render(_scene(*sized), "light", 16, camera=SIDE)
        np.testing.assert_allclose(same, light, atol=1e-3)


def test_no_light_sample_of_a_sphere_lamp_is_lost_where_its_rays_graze_it():
    """One path per pixel over 64 x 64 pixels of the floor, light sampling alone: every
    pixel is lit (a shadow ray aimed near the lamp's silhouette from the offset start met
    the lamp a little before the point it aimed at and counted it as its own shadow: about
    one sample in 500 was black)."""
    colour = _render(_scene(facet.shapes.Sphere(0.3)), "light", 1, size=64).mean(axis=-1)
    dark = np.argwhere(colour < 0.5 * np.median(colour))
    assert len(dark) == 0, f"{len(dark)} of 4096 floor pixels got no light: {dark[:5]}"


def test_a_sphere_lamp_is_sampled_by_the_cone_it_subtends():
    """Light sampling alone, 4 paths per pixel: directions uniformly in the cone the lamp
    subtends leave only the cosine's small spread over the cone: the floor's pixels are
    within 1% of the closed form albedo x L x (R / d)^2 x cos in the mean square, 3% each
    (uniform points on the whole sphere spent half on its hidden side: 40% off)."""
    radius, size = 0.3, 16
    colour = _render(_scene(facet.shapes.Sphere(radius)), "light", 4, size=size).mean(axis=-1)
    half = 0.6 * np.tan(np.radians(10.0))  # the floor the camera sees: +-half around 0
    x = ((np.arange(size) + 0.5) / size * 2 - 1) * half
    r2 = x[None, :] ** 2 + x[:, None] ** 2
    d2 = r2 + HEIGHT ** 2
    expected = ALBEDO * RADIANCE * radius ** 2 / d2 * (HEIGHT / np.sqrt(d2))
    relative = colour / expected - 1
    assert np.sqrt((relative ** 2).mean()) < 0.01 and np.abs(relative).max() < 0.03, \
        (np.sqrt((relative ** 2).mean()), np.abs(relative).max())

"""facet.SphereLight: a sphere that lights as a point light of its intensity does from afar;
the rasterizer and the Whitted tracer light by points of it, the path tracer samples it as
an emitting sphere of radiance I / r^2 (facet.render.path.area_lights)."""

import numpy as np
import pytest

import facet
from facet.errors import InputError
from facet.scene.light import SphereLight
from facet.scene.pbr import PbrMaterial


def test_its_points_lie_on_it_and_its_centre_stands_for_it():
    light = SphereLight(position=(1, 2, 3), radius=0.5, intensity=2.0)
    assert np.allclose(light.point_light().position, (1, 2, 3))
    for u, v in ((-0.5, -0.5), (0.1, 0.3), (0.4, -0.2), (0.0, 0.5)):
        p = light.point_light(u, v)
        assert np.linalg.norm(p.position - (1, 2, 3)) == pytest.approx(0.5)
        assert p.intensity == 2.0
    with pytest.raises(InputError, match="sphere light radius must be a number > 0"):
        SphereLight(radius=0.0)


def test_the_path_tracer_sees_and_samples_the_sphere():
    """The camera sees the sphere's radiance I / r^2 at its centre; the plane below is lit
    as the rasterizer's point at the centre lights it (no ambient term, medians)."""
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.Mesh(np.array([(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0.0)]),
                         np.array([[0, 1, 2], [0, 2, 3]])),
              PbrMaterial(base_color=(0.8, 0.8, 0.8, 1), roughness=1.0, metallic=0.0))
    scene.add_light(SphereLight(position=(0, 0, 2), radius=0.2, intensity=1.5,
                                attenuation=(0, 0, 1)))
    cam = facet.Camera.look_at((0, -3, 4), (0, 0, 1), fov_y=40)
    with facet.Renderer(48, 48) as r:
        raster = r.render(scene, cam, lights="scene", float_color=True).color[..., :3]
        path = r.render(scene, cam, engine="path", spp=64, lights="scene",
                        float_color=True).color[..., :3]
    assert path.max() == pytest.approx(1.5 / 0.2 ** 2, rel=1e-4)  # the sphere, seen
    assert raster.max() < 2  # (the rasterizer draws no geometry for a light)
    plane = (path.max(axis=-1) < 5) & (raster.max(axis=-1) > 0)
    assert np.median(path[plane]) == pytest.approx(np.median(raster[plane]), rel=0.03)

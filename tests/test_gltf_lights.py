"""glTF's KHR_lights_punctual: lights placed by their nodes, photometric units turned into
facet's (irradiance pi I per light of intensity I), the inverse-square falloff, spot cones,
and bad definitions refused in one line."""

import numpy as np
import pytest

import facet
from facet.errors import MeshError
from facet.scene.light import DirectionalLight, PointLight, SpotLight

from gltf_files import GltfBuilder, quad


def _lit_quad(tmp_path, lights, placements):
    b = GltfBuilder()
    mat = b.material(pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1],
                                           "metallicFactor": 0.0})
    b.node(mesh=quad(b, mat), matrix=[1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, -0.5, 0, 0.5, 1])
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    b.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    for index, node in placements:
        b.node(extensions={"KHR_lights_punctual": {"light": index}}, **node)
    return b.write_gltf(tmp_path / "lit.gltf")


def test_lights_are_placed_and_converted(tmp_path):
    down = [0.7071068, 0, 0, 0.7071068]  # a quarter turn about x: -z becomes -y
    path = _lit_quad(tmp_path, [
        {"type": "point", "intensity": 8.0, "color": [1, 0.5, 0.25]},
        {"type": "directional", "intensity": 3.0},
        {"type": "spot", "intensity": 2.0, "spot": {"innerConeAngle": 0.2,
                                                   "outerConeAngle": 0.5}},
    ], [(0, {"translation": [0, 2, 0]}), (1, {"rotation": [-0.7071068, 0, 0, 0.7071068]}),
        (2, {"translation": [1, 3, 0], "rotation": down})])
    scene = facet.load(path)
    point, sun, spot = scene.lights
    assert isinstance(point, PointLight) and isinstance(sun, DirectionalLight)
    assert isinstance(spot, SpotLight)
    np.testing.assert_allclose(point.position, (0, 2, 0))
    assert point.intensity == pytest.approx(8.0 / np.pi)
    np.testing.assert_allclose(point.attenuation, (0, 0, 1))
    np.testing.assert_allclose(point.color, (1, 0.5, 0.25))
    np.testing.assert_allclose(sun.direction, (0, -1, 0), atol=1e-6)
    assert sun.intensity == pytest.approx(3.0 / np.pi)
    np.testing.assert_allclose(spot.position, (1, 3, 0))
    np.testing.assert_allclose(spot.direction, (0, 1, 0), atol=1e-6)  # -z turned by +90
    assert (spot.inner_angle, spot.outer_angle) == pytest.approx((np.degrees(0.2),
                                                                  np.degrees(0.5)))


def test_a_point_light_gives_candela_over_distance_squared(tmp_path):
    """A white Lambert-like floor 2 m under a 10 cd light: irradiance 10 / 4 lux, so the
    floor below shows (f pi) (E / pi) = f E with the BRDF's value f there (raster and path
    agree, and both are that)."""
    path = _lit_quad(tmp_path, [{"type": "point", "intensity": 10.0}],
                     [(0, {"translation": [0, 2, 0]})])
    scene = facet.load(path)
    scene.ambient = np.zeros(3)
    camera = facet.Camera.look_at((0, 2, 0.001), (0, 0, 0), fov_y=10, near=0.5, far=5)
    with facet.Renderer(16, 16) as r:
        raster = r.render(scene, camera, shading="pbr", float_color=True,
                          aa="none").color[8, 8, 0]  # float colour: linear in every engine
        path_ = r.render(scene, camera, engine="path", spp=16, max_depth=0,
                         float_color=True).color[8, 8, 0]
    from reference import _pbr_brdf_cos
    n = np.array([[0.0, 1.0, 0.0]])
    f_cos = _pbr_brdf_cos(n, n, n, (1, 1, 1), 0.0, 1.0)[0, 0] / np.pi  # f at normal view
    assert raster == pytest.approx(f_cos * 10 / 4, rel=0.02)
    assert path_ == pytest.approx(f_cos * 10 / 4, rel=0.02)


@pytest.mark.parametrize("lights, placements, message", [
    ([{"type": "laser"}], [], "type must be one of directional, point, spot"),
    ([{"type": "point", "intensity": -1}], [], "intensity must be a number >= 0"),
    ([{"type": "spot", "spot": {"innerConeAngle": 1.0, "outerConeAngle": 0.5}}], [],
     "innerConeAngle < outerConeAngle"),
    ([{"type": "point"}], [(3, {})], "must index the document's 1 lights"),
])
def test_bad_lights_are_one_line(tmp_path, lights, placements, message):
    path = _lit_quad(tmp_path, lights, placements)
    with pytest.raises(MeshError, match=message) as info:
        facet.load(path)
    assert "\n" not in str(info.value)

"""KHR_materials_diffuse_transmission: the share dt of a dielectric's diffuse part goes
through the surface as a Lambertian lobe of its own colour. In a white furnace a sheet
shows (1 - dt) base + dt colour exactly, in every engine; a lamp behind a sheet lights
its front only when the sheet transmits; the extension is read from glTF."""

import json
import warnings

import numpy as np
import pytest

import facet
from facet.scene.pbr import PbrMaterial

from gltf_files import GltfBuilder, quad

CAM = facet.Camera.look_at((0, 0, 3), (0, 0, 0), fov_y=30, near=0.5, far=20)
SHEET = dict(base_color=(0.2, 0.2, 0.2), metallic=0.0, specular=0.0, double_sided=True,
             diffuse_transmission=0.5, diffuse_transmission_color=(1.0, 0.5, 0.25))


def _sheet(**material):
    scene = facet.Scene(ambient=1.0)
    scene.add(facet.shapes.Plane((2.0, 2.0)), PbrMaterial(**material),
              facet.transforms.rotate_x(90.0))  # facing +z, the camera
    return scene


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_sheet_in_a_white_furnace_shows_both_lobes(engine):
    kw = dict(engine=engine, float_color=True, lights="scene")
    if engine == "path":
        kw.update(spp=256, max_depth=1, environment={"color": [1.0, 1.0, 1.0]})
    elif engine == "raster":
        kw.update(environment={"color": [1.0, 1.0, 1.0]})
    with facet.Renderer(32, 32) as r:
        image = r.render(_sheet(**SHEET), CAM, **kw).color[..., :3]
    want = 0.5 * 0.2 + 0.5 * np.array([1.0, 0.5, 0.25])
    np.testing.assert_allclose(image[12:20, 12:20].reshape(-1, 3).mean(0), want, rtol=0.03)


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_lamp_behind_a_sheet_lights_its_front(engine):
    def front(dt):
        scene = _sheet(**{**SHEET, "diffuse_transmission": dt})
        scene.ambient = np.zeros(3)
        scene.lights.append(facet.PointLight((0.0, 0.0, -1.5), intensity=2.0))
        with facet.Renderer(32, 32) as r:
            return float(r.render(scene, CAM, engine=engine, float_color=True, lights="scene",
                                  spp=16 if engine == "path" else 1).color[12:20, 12:20, :3]
                         .mean())

    lit, dark = front(0.8), front(0.0)
    assert dark < 0.01 and lit > 0.05, (lit, dark)


def test_diffuse_transmission_is_read_from_gltf(tmp_path):
    b = GltfBuilder()
    b.doc["extensionsUsed"] = ["KHR_materials_diffuse_transmission"]
    b.node(mesh=quad(b, b.material(extensions={"KHR_materials_diffuse_transmission": {
        "diffuseTransmissionFactor": 0.4, "diffuseTransmissionColorFactor": [1, 0.5, 0]}})))
    path = b.write_gltf(tmp_path / "dt.gltf")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = facet.load(path).objects[0].material
    assert m.diffuse_transmission == 0.4
    np.testing.assert_allclose(m.diffuse_transmission_color, (1, 0.5, 0))
    json.loads(path.read_text())  # (the file is plain glTF)

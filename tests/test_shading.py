"""Tier 2: the rendered fine icosphere against the exact sphere of tests/reference.py.

Per pixel centre, the reference intersects the exact sphere and evaluates the shading equation
in numpy. Interior pixels (2 px away from the silhouette) must agree within 2/255; the
silhouette masks must overlap with IoU >= 0.99.
"""

import numpy as np
import pytest

from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, PointLight, Scene, SpotLight

from conftest import sphere_mesh
from reference import erode, iou, sphere_reference

SIZE = 96
TOL = 2.0 / 255.0

CAMERAS = {
    "perspective": lambda: Camera.look_at((0.8, 1.2, 4.0), (0, 0, 0), fov_y=40, near=1, far=10),
    "orthographic": lambda: Camera.look_at((0.8, 1.2, 4.0), (0, 0, 0), ortho_height=2.6,
                                           near=1, far=10),
}
MATERIALS = {
    "matte": Material(color=(0.2, 0.5, 0.9), ka=1.0, kd=0.9, ks=0.0, shininess=1),
    "glossy": Material(color=(0.9, 0.3, 0.2), ka=0.5, kd=0.7, ks=0.5, shininess=40),
}
LIGHTS = {
    "directional": lambda: [DirectionalLight((-1, -0.8, -1.2), (1, 0.95, 0.9), 0.9)],
    "point": lambda: [PointLight((2.0, 2.5, 3.0), (1, 1, 1), 6.0, attenuation=(1, 0.2, 0.3))],
    "mixed": lambda: [DirectionalLight((1, -0.3, -0.5), (0.3, 0.3, 1.0), 0.6),
                      PointLight((-2.0, 1.0, 2.0), (1, 0.8, 0.6), 2.0, (0.5, 0.1, 0.05)),
                      SpotLight((0, 3, 1.5), (0, -1, -0.5), (1, 1, 1), 1.0,
                                inner_angle=15, outer_angle=25)],
}


def _render_sphere(renderer, camera, material, lights, shading="phong", msaa=0):
    scene = Scene(ambient=(0.15, 0.15, 0.2))
    scene.add(sphere_mesh(), material)
    for light in lights:
        scene.add_light(light)
    frame = renderer(SIZE, SIZE, msaa).render(scene, camera, shading=shading)
    return scene, frame


@pytest.mark.parametrize("cam", CAMERAS)
@pytest.mark.parametrize("mat", MATERIALS)
@pytest.mark.parametrize("lights", LIGHTS)
def test_phong_sphere_matches_reference(renderer, cam, mat, lights):
    camera, material = CAMERAS[cam](), MATERIALS[mat]
    scene, frame = _render_sphere(renderer, camera, material, LIGHTS[lights]())
    rgb, mask, _ = sphere_reference(camera, SIZE, SIZE, (0, 0, 0), 1.0, material,
                                    scene.lights, scene.ambient)
    got_mask = frame.object_ids == 0
    assert iou(got_mask, mask) >= 0.99
    inner = erode(mask, 2)
    assert inner.sum() > 0.4 * mask.sum()
    err = np.abs(frame.color[..., :3] / 255.0 - rgb)[inner]
    assert err.max() <= TOL, f"max error {err.max() * 255:.2f}/255"
    # The picture is lit, not flat: shading varies across the sphere.
    assert np.ptp(frame.color[..., :3][inner].mean(axis=1)) > 40


def test_blinn_matches_reference(renderer):
    camera, material = CAMERAS["perspective"](), MATERIALS["glossy"]
    scene, frame = _render_sphere(renderer, camera, material, LIGHTS["mixed"](), "blinn")
    rgb, mask, _ = sphere_reference(camera, SIZE, SIZE, (0, 0, 0), 1.0, material,
                                    scene.lights, scene.ambient, blinn=True)
    inner = erode(mask, 2)
    assert np.abs(frame.color[..., :3] / 255.0 - rgb)[inner].max() <= TOL
    phong = _render_sphere(renderer, camera, material, LIGHTS["mixed"]())[1]
    assert np.abs(phong.color.astype(int) - frame.color).max() > 10  # a different highlight


def test_gouraud_close_but_not_identical(renderer):
    """Per-vertex shading on a fine sphere approximates per-pixel Phong (within 4/255 on the
    diffuse-only material) but is evaluated elsewhere, so it is not bit-identical."""
    camera, material = CAMERAS["perspective"](), MATERIALS["matte"]
    lights = LIGHTS["directional"]()
    _, gouraud = _render_sphere(renderer, camera, material, lights, "gouraud")
    _, phong = _render_sphere(renderer, camera, material, lights, "phong")
    inner = erode(phong.object_ids == 0, 2)
    diff = np.abs(gouraud.color[..., :3].astype(int) - phong.color[..., :3])[inner]
    assert diff.max() <= 4 and diff.max() > 0


def test_unlit_normals_and_flat(renderer):
    camera, material = CAMERAS["orthographic"](), MATERIALS["glossy"]
    lights = LIGHTS["directional"]()
    _, unlit = _render_sphere(renderer, camera, material, lights, "unlit")
    inner = erode(unlit.object_ids == 0, 1)
    assert np.all(np.abs(unlit.color[..., :3][inner] - material.color * 255) <= 1)
    _, normals = _render_sphere(renderer, camera, material, lights, "normals")
    n = normals.color[..., :3][inner] / 255.0 * 2 - 1
    assert np.allclose(np.linalg.norm(n, axis=1), 1, atol=0.03)
    # At the image centre the visible normal points at the camera.
    centre = normals.color[SIZE // 2, SIZE // 2, :3] / 255.0 * 2 - 1
    to_eye = -camera.forward
    assert np.dot(centre, to_eye) > 0.99
    # Flat shading is piecewise constant: far fewer distinct colours than smooth Phong.
    coarse = sphere_mesh(subdivisions=2)
    scene = Scene()
    scene.add(coarse, material)
    scene.add_light(lights[0])
    flat = renderer(SIZE, SIZE).render(scene, camera, shading="flat")
    smooth = renderer(SIZE, SIZE).render(scene, camera, shading="phong")
    inner2 = erode(flat.object_ids == 0, 1)
    n_flat = len(np.unique(flat.color[inner2].reshape(-1, 4), axis=0))
    n_smooth = len(np.unique(smooth.color[inner2].reshape(-1, 4), axis=0))
    assert n_flat < n_smooth / 3


def test_transform_and_normal_matrix(renderer):
    """A sphere squashed to an ellipsoid by a non-uniform scale, then moved, is lit by the
    normal matrix: the reference is the exact sphere seen through the inverse transform."""
    from facet.geometry import transforms as T

    m = T.compose(T.scale((1.0, 0.6, 1.0)), T.translate((0.2, -0.1, 0.0)))
    camera = CAMERAS["orthographic"]()
    scene = Scene(ambient=0.1)
    scene.add(sphere_mesh(), MATERIALS["matte"], transform=m)
    scene.add_light(DirectionalLight((-1, -1, -1)))
    frame = renderer(SIZE, SIZE).render(scene, camera)
    # Reference: ellipsoid normals are G n with G = (M^-1)^T (numpy, from the equation).
    from reference import phong, pixel_rays

    o, d = pixel_rays(camera.view, camera.projection(SIZE, SIZE), SIZE, SIZE)
    inv = np.linalg.inv(m)
    o2, d2 = o @ inv[:3, :3].T + inv[:3, 3], d @ inv[:3, :3].T
    a = np.sum(d2 * d2, -1)
    b = np.sum(o2 * d2, -1)
    c = np.sum(o2 * o2, -1) - 1
    disc = b * b - a * c
    hit = disc > 0
    t = np.where(hit, (-b - np.sqrt(np.maximum(disc, 0))) / a, 0)
    p_obj = o2 + t[..., None] * d2
    n = p_obj @ T.normal_matrix(m).T
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    p = o + t[..., None] * d
    rgb = phong(p, n, -d, MATERIALS["matte"].color, MATERIALS["matte"], scene.lights,
                scene.ambient)
    inner = erode(hit, 2)
    assert iou(frame.object_ids == 0, hit) > 0.99
    assert np.abs(frame.color[..., :3] / 255 - rgb)[inner].max() <= TOL


def test_many_mixed_lights(renderer):
    """Nine lights of all three kinds at once (the shader holds up to 16)."""
    camera, material = CAMERAS["perspective"](), MATERIALS["glossy"]
    lights = []
    for i in range(3):
        a = np.radians(120 * i)
        lights.append(DirectionalLight((np.cos(a), -0.5, np.sin(a) - 0.5), (0.3, 0.3, 0.3), 0.6))
        lights.append(PointLight((2 * np.cos(a), 1.5, 2 * np.sin(a) + 2), (0.4, 0.3, 0.2), 1.5,
                                 (1, 0.1, 0.1)))
        lights.append(SpotLight((np.cos(a), 2, 2), (-np.cos(a), -2, -2), (0.2, 0.3, 0.5), 1.0,
                                inner_angle=10 + 5 * i, outer_angle=20 + 5 * i))
    scene, frame = _render_sphere(renderer, camera, material, lights)
    rgb, mask, _ = sphere_reference(camera, SIZE, SIZE, (0, 0, 0), 1.0, material,
                                    scene.lights, scene.ambient)
    inner = erode(mask, 2)
    assert np.abs(frame.color[..., :3] / 255.0 - rgb)[inner].max() <= TOL

"""KHR_materials_anisotropy: GGX stretched along a tangent direction (alpha_t =
mix(alpha, 1, strength^2) along it), as the extension gives D and Vis. A white metal sphere
in a white furnace shows the lobe's directional albedo at normal incidence (a numpy
quadrature of D Vis cos, times the multiple-scattering scale the isotropic lobe of that
roughness gets) within 2% in the path tracer, which samples the stretched lobe; a point
light's highlight stretches across the tangent in every engine; AnisotropyStrengthTest
is read without a warning."""

import warnings

import numpy as np
import pytest

import facet
from facet.scene.pbr import PbrMaterial

from conftest import SHARED_GLTF, shared_model

ROUGHNESS = 0.5


def _albedo(alpha_t, alpha_b, n=1200):
    """int D Vis (N.L) dL over the hemisphere, V = N (the extension's anisotropic GGX and
    height-correlated Smith; F = 1)."""
    theta = (np.arange(n) + 0.5) / n * (np.pi / 2)
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    L = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    V = np.array([0.0, 0.0, 1.0])
    H = L + V
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    a2 = alpha_t * alpha_b
    f = np.stack([alpha_b * H[..., 0], alpha_t * H[..., 1], a2 * H[..., 2]], axis=-1)
    w2 = a2 / (f ** 2).sum(-1)
    d = a2 * w2 * w2 / np.pi
    n_l, n_v = L[..., 2], 1.0
    gv = n_l * np.sqrt((alpha_t * V[0]) ** 2 + (alpha_b * V[1]) ** 2 + n_v ** 2)
    gl = n_v * np.sqrt((alpha_t * L[..., 0]) ** 2 + (alpha_b * L[..., 1]) ** 2 + n_l ** 2)
    integrand = d * 0.5 / (gv + gl) * n_l * np.sin(th)
    return float(integrand.sum() * (np.pi / 2 / n) * (2 * np.pi / (2 * n)))


def _sphere_scene(material):
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.shapes.Sphere(1.0), material)
    return scene


CAM = facet.Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=30, near=0.5, far=20)


@pytest.mark.parametrize("strength", [0.0, 0.5, 0.9])
def test_a_white_anisotropic_metal_in_a_furnace_shows_its_albedo(strength):
    alpha = ROUGHNESS ** 2
    alpha_t = alpha + (1 - alpha) * strength ** 2
    want = _albedo(alpha_t, alpha) / _albedo(alpha, alpha)  # (times the isotropic 1 / E)
    material = PbrMaterial(base_color=(1, 1, 1), metallic=1.0, roughness=ROUGHNESS,
                           anisotropy=strength)
    with facet.Renderer(32, 32) as r:
        image = r.render(_sphere_scene(material), CAM, engine="path", spp=1024, max_depth=0,
                         float_color=True, lights="scene",
                         environment={"color": [1.0, 1.0, 1.0]}).color[..., :3]
    got = float(image[15:17, 15:17].mean())
    assert got == pytest.approx(want, rel=0.02), (strength, got, want)


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_highlight_stretches_across_the_tangent(engine):
    """A point light's highlight on a smooth metal sphere: round without anisotropy,
    stretched with it (the second moments of the highlight's pixels differ by 2x). The
    highlight is what an 8-bit picture shows above half white: float colour is unclamped,
    and the exact sphere's grazing rim (the tracers') holds a lone retro-reflection peak
    above the highlight's own."""
    def spread(strength):
        m = PbrMaterial(base_color=(0.9, 0.9, 0.9), metallic=1.0, roughness=0.25,
                        anisotropy=strength)
        scene = _sphere_scene(m)
        scene.lights.append(facet.PointLight((0.0, 0.0, 6.0), intensity=30.0))
        with facet.Renderer(96, 96) as r:
            c = r.render(scene, CAM, engine=engine, spp=64 if engine == "path" else 1,
                         float_color=True, lights="scene").color[..., :3].mean(-1)
        ys, xs = np.nonzero(np.minimum(c, 1.0) > 0.5)
        return np.var(xs) + 1e-3, np.var(ys) + 1e-3

    round_x, round_y = spread(0.0)
    wide_x, wide_y = spread(0.9)
    assert 0.6 < round_x / round_y < 1.6
    assert max(wide_x / wide_y, wide_y / wide_x) > 2.0, (wide_x, wide_y)


def test_anisotropy_is_read_from_gltf():
    path = shared_model("AnisotropyStrengthTest/AnisotropyStrengthTest.glb", SHARED_GLTF)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(path)
    strengths = {round(o.material.anisotropy, 3) for o in scene.objects}
    assert {0.0, 0.5, 1.0} <= strengths


def test_scene_file_keys_of_the_newer_extensions_reach_the_material(tmp_path):
    """iridescence_*, anisotropy_* and diffuse_transmission_* in a scene file set the
    material (iridescence_ior, the film's thickness range and anisotropy_rotation were
    accepted and dropped: a key that parses must act)."""
    toml = tmp_path / "s.toml"
    toml.write_text("""[materials.m]
base_color = [0.8, 0.8, 0.8]
iridescence = 0.5
iridescence_ior = 1.4
iridescence_thickness_min = 150.0
iridescence_thickness_max = 450.0
anisotropy = 0.6
anisotropy_rotation = 0.5
diffuse_transmission = 0.3
diffuse_transmission_color = [0.9, 0.6, 0.4]

[[objects]]
primitive = "sphere"
material = "m"
""")
    m = facet.load(toml).objects[0].material
    assert (m.iridescence, m.iridescence_ior) == (0.5, 1.4)
    assert (m.iridescence_thickness_min, m.iridescence_thickness_max) == (150.0, 450.0)
    assert (m.anisotropy, m.anisotropy_rotation) == (0.6, 0.5)
    assert m.diffuse_transmission == 0.3
    np.testing.assert_allclose(m.diffuse_transmission_color, (0.9, 0.6, 0.4))


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_anisotropy_without_a_tangent_frame_is_said(engine):
    """A mesh with no uvs and no tangents gives the lobe no direction: drawn isotropic,
    and one line says so (it was silent)."""
    import trimesh

    ico = trimesh.creation.icosphere(subdivisions=2)
    scene = facet.Scene(ambient=0.3)
    scene.add(facet.Mesh(np.asarray(ico.vertices), np.asarray(ico.faces)),
              PbrMaterial(metallic=1.0, roughness=0.3, anisotropy=0.8))
    with facet.Renderer(16, 16) as r, pytest.warns(facet.FacetWarning,
                                                   match="without uvs or tangents"):
        r.render(scene, CAM, engine=engine, spp=1)
    with warnings.catch_warnings():  # (a sphere shape has its frame: nothing said)
        warnings.simplefilter("error")
        with facet.Renderer(16, 16) as r:
            r.render(_sphere_scene(PbrMaterial(metallic=1.0, roughness=0.3, anisotropy=0.8)),
                     CAM, engine=engine, spp=1, lights="scene")

"""The path tracer (engine="path") against references from the equations: furnace tests (a
sphere in a constant environment shows the directional albedo of its BRDF, integrated here
in numpy from the glTF metallic-roughness formulas, independently of the shader's
sampling), direct light against the rasterizer where both are exact, determinism, and what
it does not honour named in one warning line."""

import numpy as np
import pytest

import facet
from facet.errors import FacetWarning
from facet.geometry.camera import Camera
from facet.scene.light import DirectionalLight
from facet.scene.pbr import PbrMaterial

SIZE = 48
CAMERA = Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=40, near=1, far=10)
F0_DIELECTRIC = 0.04


def _albedo(base, metallic, roughness, n_dot_v, n=400):
    """The directional albedo int f cos dL of glTF's BRDF (as lib/pbr.glsl writes it: GGX,
    height-correlated Smith, Schlick; diffuse (1 - F0_dielectric) (1 - Fc) c_diff / pi)
    for viewing angle n_dot_v, by the midpoint rule over the hemisphere (n x 4n cells)."""
    base = np.asarray(base, float)
    alpha = max(roughness ** 2, 1e-3)
    theta = (np.arange(n) + 0.5) / n * (np.pi / 2)
    phi = (np.arange(4 * n) + 0.5) / (4 * n) * (2 * np.pi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    L = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    V = np.array([np.sqrt(1 - n_dot_v ** 2), 0.0, n_dot_v])
    H = L + V
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    nl, nh, vh = L[..., 2], H[..., 2], np.clip(H @ V, 0, 1)
    a2 = alpha * alpha
    d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    g = nl * np.sqrt(n_dot_v ** 2 * (1 - a2) + a2) + n_dot_v * np.sqrt(nl * nl * (1 - a2) + a2)
    vis = 0.5 / g
    fc = (1 - vh) ** 5
    f0 = (1 - metallic) * F0_DIELECTRIC + metallic * base
    c_diff = (1 - metallic) * base
    # The lobe with the multiple-scattering scale 1 + F0 (1 - E) / E, E = int D Vis cos
    # (F = 1) integrated here too (facet.render.energy tabulates it for the shaders).
    cell = np.sin(t) * (np.pi / 2 / n) * (2 * np.pi / (4 * n))
    e = (d * vis * nl * cell).sum()
    spec = (d * vis)[..., None] * (f0 + (1 - f0) * fc[..., None]) * (1 + f0 * (1 - e) / e)
    diff = (1 - F0_DIELECTRIC) * (1 - fc)[..., None] * c_diff / np.pi
    integrand = (spec + diff) * nl[..., None] * cell[..., None]
    return integrand.sum(axis=(0, 1))


def _sphere_scene(material, ambient=0.0):
    scene = facet.Scene(ambient=ambient)
    scene.add(facet.primitives.sphere(1.0, segments=96, rings=48), material=material)
    return scene


def _normals_and_colour(material, **kw):
    with facet.Renderer(SIZE, SIZE) as r:
        frame = r.render(_sphere_scene(material), CAMERA, engine="path", lights="scene",
                         float_color=True, outputs=("color", "normals"), **kw)
    return frame.color, frame.normals


@pytest.mark.parametrize("base, metallic, roughness", [
    ((0.8, 0.8, 0.8), 0.0, 1.0),    # a rough dielectric
    ((0.8, 0.5, 0.2), 0.0, 0.4),    # coloured, glossier
    ((1.0, 1.0, 1.0), 1.0, 0.5),    # a rough white metal: 1 (multiple scattering kept)
    ((1.0, 1.0, 1.0), 1.0, 1.0),    # the roughest: single scattering alone keeps 31%
    ((0.9, 0.6, 0.3), 1.0, 0.15),   # gold-like, nearly a mirror
])
def test_furnace_shows_the_brdf_albedo(base, metallic, roughness):
    """A convex object in a constant environment of radiance 1: every bounce escapes, so a
    pixel is the BRDF's directional albedo at its viewing angle."""
    mat = PbrMaterial(base_color=(*base, 1.0), metallic=metallic, roughness=roughness)
    color, normals = _normals_and_colour(mat, environment={"color": [1, 1, 1]}, spp=256)
    n_dot_v = normals[..., 2]  # camera on +z, far away enough: V ~ +z near the centre
    centre = n_dot_v > 0.97
    assert centre.sum() > 20
    expected = _albedo(base, metallic, roughness, 1.0)
    measured = color[centre][:, :3].mean(axis=0)
    np.testing.assert_allclose(measured, expected, rtol=0.02, atol=0.005)


def test_a_white_lambert_like_sphere_in_a_white_furnace_is_nearly_invisible():
    """Base colour 1, roughness 1: the BRDF's albedo is close to 1 at normal incidence and
    the sphere (all of it) sits within a few percent of the environment around it."""
    mat = PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0, roughness=1.0)
    color, normals = _normals_and_colour(mat, environment={"color": [0.5, 0.5, 0.5]},
                                         spp=128)
    centre = normals[..., 2] > 0.97
    expected = 0.5 * _albedo((1, 1, 1), 0.0, 1.0, 1.0)
    np.testing.assert_allclose(color[centre][:, :3].mean(axis=0), expected, rtol=0.02)


def _direct_against_raster(material, direction, facing=0.3, least=300):
    """(path, raster) float colour of a sphere of ``material`` under one directional light
    without ambient or bounces, and the pixels both light unclipped; asserts that the two
    engines' linear colour agrees there (they evaluate the same BRDF for the light)."""
    scene = _sphere_scene(material)
    scene.add_light(DirectionalLight(direction=direction))
    with facet.Renderer(SIZE, SIZE) as r:
        path = r.render(scene, CAMERA, engine="path", max_depth=0, float_color=True,
                        aa="none", outputs=("color", "normals"))
        raster = r.render(scene, CAMERA, engine="raster", shading="pbr", float_color=True,
                          aa="none")
    lit = (path.normals[..., 2] > facing) & (path.color[..., 0] > 0.01) & \
        (raster.color[..., :3].max(axis=-1) < 1)  # not clipped
    assert lit.sum() > least
    diff = np.abs(path.color[lit][:, :3] - raster.color[lit][:, :3])  # both linear
    assert diff.mean() < 0.005 and np.percentile(diff, 99) < 0.02, (diff.mean(), diff.max())
    return path.color, raster.color, lit


def test_direct_light_matches_the_rasterizer():
    """No bounces (max_depth 0), one directional light, no ambient: both engines evaluate
    the same BRDF for the same light, exactly: their float colour (linear light in every
    engine) and their 8-bit pictures (sRGB-encoded) agree."""
    mat = PbrMaterial(base_color=(0.7, 0.4, 0.2, 1), metallic=0.3, roughness=0.5)
    _, _, lit = _direct_against_raster(mat, (-0.4, -0.5, -1.0))
    scene = _sphere_scene(mat)
    scene.add_light(DirectionalLight(direction=(-0.4, -0.5, -1.0)))
    with facet.Renderer(SIZE, SIZE) as r:
        path8 = r.render(scene, CAMERA, engine="path", max_depth=0, aa="none").color
        raster8 = r.render(scene, CAMERA, engine="raster", shading="pbr", aa="none").color
    diff8 = np.abs(path8[lit][:, :3].astype(int) - raster8[lit][:, :3])
    assert diff8.mean() < 1.5 and np.percentile(diff8, 99) <= 6, (diff8.mean(), diff8.max())


def test_the_same_picture_on_every_run_and_bounces_add_light():
    scene = _sphere_scene(PbrMaterial(base_color=(0.8, 0.8, 0.8, 1), metallic=0.0,
                                      roughness=0.8))
    scene.add(facet.primitives.plane(6.0), transform=facet.transforms.translate(
        (0, -1.0, 0)), material=PbrMaterial(base_color=(0.9, 0.9, 0.9, 1), metallic=0.0,
                                            roughness=1.0))
    scene.add_light(DirectionalLight(direction=(0.3, -1.0, -0.4)))
    with facet.Renderer(SIZE, SIZE) as r:
        a = r.render(scene, CAMERA, engine="path", spp=8, float_color=True).color
        b = r.render(scene, CAMERA, engine="path", spp=8, float_color=True).color
        direct = r.render(scene, CAMERA, engine="path", spp=8, max_depth=0,
                          float_color=True).color
    assert np.array_equal(a, b)
    # The sphere's underside sees only light bounced off the floor.
    assert a[..., :3].sum() > direct[..., :3].sum() * 1.05


def test_what_the_path_tracer_ignores_is_one_warning_line():
    mat = facet.Material(color=(1, 1, 1), opacity=0.5, ior=1.5)
    with facet.Renderer(16, 16) as r, pytest.warns(FacetWarning,
                                                   match="path tracer ignores Phong ior"):
        r.render(_sphere_scene(mat), CAMERA, engine="path", spp=1)


def test_the_albedo_table_is_what_the_generator_writes_and_the_integral_says():
    """glsl/lib/ggx_albedo.glsl is facet.render.energy's output (regenerate it with
    ``python -m facet.render.energy``), and its values are the midpoint-rule integral of
    the lobe at a few points (an independent quadrature)."""
    from facet.render import energy

    assert energy.table_path().read_text() == energy.glsl_table()
    assert energy.table_path("sheen_albedo").read_text() == energy.glsl_sheen_table()
    for mu, r in ((1.0, 0.5), (1.0, 1.0), (0.25, 0.7), (0.04, 1.0)):
        alpha = r * r
        n = 300
        t = (np.arange(n) + 0.5) / n * (np.pi / 2)
        p = (np.arange(4 * n) + 0.5) / (4 * n) * (2 * np.pi)
        t, p = np.meshgrid(t, p, indexing="ij")
        L = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
        V = np.array([np.sqrt(1 - mu * mu), 0, mu])
        H = (L + V) / np.linalg.norm(L + V, axis=-1, keepdims=True)
        a2 = alpha * alpha
        d = a2 / (np.pi * (H[..., 2] ** 2 * (a2 - 1) + 1) ** 2)
        nl = L[..., 2]
        g = nl * np.sqrt(mu * mu * (1 - a2) + a2) + mu * np.sqrt(nl * nl * (1 - a2) + a2)
        e = (d * 0.5 / g * nl * np.sin(t)).sum() * (np.pi / 2 / n) * (2 * np.pi / (4 * n))
        assert energy.ggx_albedo(mu, r) == pytest.approx(e, rel=0.01), (mu, r)


def test_a_white_rough_metal_in_a_white_furnace_keeps_its_energy():
    """The issue's goal: base colour 1, metallic 1, rough: at most 2% lost (single
    scattering alone loses 10% at roughness 0.5 and 69% at 1)."""
    for roughness in (0.5, 1.0):
        mat = PbrMaterial(base_color=(1, 1, 1, 1), metallic=1.0, roughness=roughness)
        color, normals = _normals_and_colour(mat, environment={"color": [1, 1, 1]}, spp=256)
        centre = normals[..., 2] > 0.9
        assert color[centre][:, :3].mean() == pytest.approx(1.0, abs=0.02), roughness


def test_float_colour_is_radiance_unclamped_and_8_bit_is_clamped():
    """An emitter of radiance 4 reads 4 in float colour (the finishing pass clamped it to 1
    before), and white in 8-bit colour."""
    mat = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, emissive=(1, 0.5, 0.25),
                      emissive_strength=4.0)
    with facet.Renderer(16, 16) as r:
        hdr = r.render(_sphere_scene(mat), CAMERA, engine="path", spp=2, float_color=True,
                       lights="scene")
        ldr = r.render(_sphere_scene(mat), CAMERA, engine="path", spp=2)
    np.testing.assert_allclose(hdr.color[8, 8], (4.0, 2.0, 1.0, 1.0), rtol=1e-5)
    assert tuple(ldr.color[8, 8]) == (255, 255, 255, 255)


@pytest.mark.parametrize("engine,aa", [("raster", "none"), ("raster", "msaa:4"),
                                       ("raster", "ssaa:grid:4"), ("trace", "none"),
                                       ("trace", "ssaa:grid:4"), ("path", None)])
def test_float_colour_is_unclamped_in_every_engine_and_every_anti_aliasing(engine, aa):
    """The same emitter of radiance 4 reads 4 in float colour from every engine and every
    kind of anti-aliasing (the Whitted tracer and the rasterizer's supersampling clamped it
    to 1 in the finishing pass, while the one-sample rasterizer kept it: a highlight of 3.1
    read 0.18, issue 49's AnisotropyStrengthTest difference)."""
    mat = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, emissive=(1, 0.5, 0.25),
                      emissive_strength=4.0)
    sampling = dict(spp=2) if aa is None else dict(aa=aa)
    with facet.Renderer(16, 16) as r:
        hdr = r.render(_sphere_scene(mat), CAMERA, engine=engine, float_color=True,
                       lights="scene", **sampling)
    np.testing.assert_allclose(hdr.color[8, 8], (4.0, 2.0, 1.0, 1.0), rtol=1e-4)


def test_the_rasterizer_keeps_a_rough_metals_energy_too():
    """The same lobe scale in the rasterizer's image-based light (split sum) and in its
    direct light: a white rough metal in a white constant environment reads 1."""
    for roughness in (0.5, 1.0):
        mat = PbrMaterial(base_color=(1, 1, 1, 1), metallic=1.0, roughness=roughness)
        with facet.Renderer(SIZE, SIZE) as r:
            frame = r.render(_sphere_scene(mat), CAMERA, engine="raster", lights="scene",
                             environment={"color": [1, 1, 1]}, float_color=True,
                             outputs=("color", "normals"))
        centre = frame.normals[..., 2] > 0.9
        linear = frame.color[centre][:, :3]  # float colour: linear in every engine
        assert linear.mean() == pytest.approx(1.0, abs=0.02), roughness


def test_the_seed_picks_the_random_stream():
    """The same seed, the same picture; another seed, other paths (and the same mean)."""
    scene = _sphere_scene(PbrMaterial(base_color=(0.8, 0.8, 0.8, 1), metallic=0.0))
    with facet.Renderer(24, 24) as r:
        def draw(seed):
            return r.render(scene, CAMERA, engine="path", spp=4, float_color=True,
                            environment={"color": [1, 1, 1]}, seed=seed).color
        a, b, c = draw(3), draw(3), draw(4)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert a.mean() == pytest.approx(c.mean(), rel=0.02)


def _coated_albedo(base, coat, coat_roughness, n=400):
    """Directional albedo at normal incidence of a Lambertian base (specular 0) under a
    clear coat: (1 - c F_c(N.V)) base + c int D Vis F_c(V.H) cos (KHR_materials_clearcoat),
    by the midpoint rule."""
    alpha = max(coat_roughness ** 2, 1e-3)
    theta = (np.arange(n) + 0.5) / n * (np.pi / 2)
    phi = (np.arange(4 * n) + 0.5) / (4 * n) * (2 * np.pi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    L = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    H = L + np.array([0, 0, 1.0])
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    nl, nh, vh = L[..., 2], H[..., 2], H[..., 2]
    a2 = alpha * alpha
    d = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    vis = 0.5 / (nl * np.sqrt(1.0) + 1.0 * np.sqrt(nl * nl * (1 - a2) + a2))
    fc = 0.04 + 0.96 * (1 - vh) ** 5
    cell = np.sin(t) * (np.pi / 2 / n) * (2 * np.pi / (4 * n))
    layer = (d * vis * fc * nl * cell).sum()
    return (1 - coat * 0.04) * np.asarray(base) + coat * layer


@pytest.mark.parametrize("coat_roughness", [0.1, 0.5])
def test_a_clear_coat_in_a_furnace(coat_roughness):
    base = (0.6, 0.3, 0.1)
    mat = PbrMaterial(base_color=(*base, 1), metallic=0.0, specular=0.0, clearcoat=1.0,
                      clearcoat_roughness=coat_roughness)
    color, normals = _normals_and_colour(mat, environment={"color": [1, 1, 1]}, spp=256)
    centre = normals[..., 2] > 0.97
    np.testing.assert_allclose(color[centre][:, :3].mean(axis=0),
                               _coated_albedo(base, 1.0, coat_roughness), rtol=0.02)


def test_a_clear_coat_under_direct_light_matches_the_rasterizer():
    """Both engines evaluate the same coated BRDF (lib/pbr.glsl) for one light."""
    mat = PbrMaterial(base_color=(0.2, 0.4, 0.7, 1), metallic=0.0, roughness=0.7,
                      clearcoat=1.0, clearcoat_roughness=0.15)
    _, raster, _ = _direct_against_raster(mat, (-0.4, -0.5, -1.0))
    plain = _sphere_scene(PbrMaterial(base_color=(0.2, 0.4, 0.7, 1), metallic=0.0,
                                      roughness=0.7))
    plain.add_light(DirectionalLight(direction=(-0.4, -0.5, -1.0)))
    with facet.Renderer(SIZE, SIZE) as r:
        uncoated = r.render(plain, CAMERA, engine="raster", shading="pbr", float_color=True,
                            aa="none").color
    assert np.abs(raster - uncoated).max() > 0.1  # the coat shows


def test_a_sheen_in_a_furnace_shows_its_lobes_albedo():
    """A black Lambertian base under a white sheen of roughness 1 (KHR_materials_sheen) in
    a white furnace: the sheen lobe's albedo at normal incidence (facet.render.energy's
    quadrature of the Charlie lobe), about 0.16."""
    from facet.render.energy import sheen_albedo

    mat = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0,
                      sheen_color=(1, 1, 1), sheen_roughness=1.0)
    color, normals = _normals_and_colour(mat, environment={"color": [1, 1, 1]}, spp=256)
    centre = normals[..., 2] > 0.97
    expected = np.mean([sheen_albedo(n, 1.0, 128) for n in normals[..., 2][centre]])
    assert 0.1 < expected < 0.25
    assert color[centre][:, :3].mean() == pytest.approx(expected, rel=0.03)


def test_a_sheen_under_direct_light_matches_the_rasterizer():
    mat = PbrMaterial(base_color=(0.3, 0.1, 0.1, 1), metallic=0.0, roughness=0.8,
                      sheen_color=(0.9, 0.8, 0.2), sheen_roughness=0.4)
    _direct_against_raster(mat, (0.6, -0.2, -0.5), facing=0.2, least=100)  # a rim light


def test_pcf_given_to_the_path_tracer_is_one_warning_line():
    """The path tracer's own list of what it ignores replaced the tracer's, which named
    pcf: given to the path tracer, pcf went unsaid."""
    mat = PbrMaterial(base_color=(0.5, 0.5, 0.5, 1), metallic=0.0)
    with facet.Renderer(16, 16) as r, pytest.warns(FacetWarning,
                                                   match="path tracer's shadow rays are exact"):
        r.render(_sphere_scene(mat), CAMERA, engine="path", spp=1, pcf=2)

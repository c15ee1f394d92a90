"""Skies for the path tracer: HDR environment images (.hdr read here, radiance above 1
kept), importance sampling by luminance (a small bright sun) against a numpy integral of
the same image, and the lowest error with both light and BSDF sampling."""

import numpy as np
import pytest

import facet
from facet.formats.environment_files import load_environment
from facet.formats.hdr_image import read_hdr_image, write_hdr
from facet.geometry.camera import Camera
from facet.render.path.engine import PathEngine
from facet.scene.environment import equirect_directions
from facet.scene.pbr import PbrMaterial

SUN = np.array([0.5, 0.7071, -0.5]) / np.linalg.norm([0.5, 0.7071, -0.5])
ALBEDO = 0.8


def _sun_sky(path, w=256, h=128):
    img = np.full((h, w, 3), 0.2, np.float32)
    img[(equirect_directions(w, h) @ SUN) > np.cos(np.radians(3))] = (200.0, 180.0, 150.0)
    write_hdr(path, img)
    return img


def test_hdr_files_round_trip_and_run_length_lines_decode(tmp_path):
    img = np.random.default_rng(1).uniform(0, 50, (5, 9, 3)).astype(np.float32)
    write_hdr(tmp_path / "a.hdr", img)
    # RGBE keeps 8 bits of mantissa for the brightest channel: others err by its 1/256.
    err = np.abs(read_hdr_image(tmp_path / "a.hdr") - img)
    assert (err <= img.max(axis=-1, keepdims=True) / 128).all()
    # One 8-pixel line in the run-length form: R a run of 128, G 8 literal values, B a run
    # of 64, E a run of 129 (x 2^(129 - 136)).
    line = bytes([2, 2, 0, 8, 136, 128, 8, *range(10, 90, 10), 136, 64, 136, 129])
    (tmp_path / "b.hdr").write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n"
                                     + line)
    got = read_hdr_image(tmp_path / "b.hdr")[0]
    np.testing.assert_allclose(got[:, 0], 1.0)
    np.testing.assert_allclose(got[:, 1], np.arange(10, 90, 10) / 128)
    np.testing.assert_allclose(got[:, 2], 0.5)


def test_a_bad_hdr_file_is_one_line(tmp_path):
    (tmp_path / "bad.hdr").write_bytes(b"#?RADIANCE\n\n-Y 4 +X 4\n\x02\x02")
    with pytest.raises(facet.FacetError, match="bad.hdr: not a readable Radiance HDR") as e:
        load_environment(str(tmp_path / "bad.hdr"))
    assert "\n" not in str(e.value)


def test_radiance_above_one_is_kept(tmp_path):
    """A constant HDR sky of radiance 3: a white Lambertian sphere shows 3 (it was clipped
    to 1 when environments were 8-bit values)."""
    write_hdr(tmp_path / "bright.hdr", np.full((16, 32, 3), 3.0, np.float32))
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.sphere(1.0), PbrMaterial(base_color=(1, 1, 1), metallic=0.0,
                                                        specular=0.0))
    camera = Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=20, near=1, far=10)
    with facet.Renderer(16, 16) as r:
        img = r.render(scene, camera, engine="path", spp=256, float_color=True,
                       lights="scene", environment=str(tmp_path / "bright.hdr")).color
    assert img[6:10, 6:10, :3].mean() == pytest.approx(3.0, rel=0.01)
    assert img[..., :3].min() > 2.5  # every pixel, the sky behind too: nothing clipped


def _floor(tmp_path, strategy, spp, sky="sun.hdr"):
    if sky == "sun.hdr":
        _sun_sky(tmp_path / "sun.hdr")
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(4), PbrMaterial(base_color=(ALBEDO,) * 3, metallic=0.0,
                                                     specular=0.0))
    camera = Camera.look_at((0, 3, 0.01), (0, 0, 0), fov_y=20, near=0.5, far=20)
    PathEngine.strategy = strategy
    try:
        with facet.Renderer(32, 32) as r:
            return r.render(scene, camera, engine="path", spp=spp, max_depth=0,
                            float_color=True, lights="scene",
                            environment=str(tmp_path / sky)).color[..., :3]
    finally:
        PathEngine.strategy = "mis"


def _floor_radiance(img):
    """albedo / pi x sum over the image's texels of radiance x cos x solid angle."""
    h, w = img.shape[:2]
    d = equirect_directions(w, h)
    theta = (np.arange(h) + 0.5) / h * np.pi
    solid = (2 * np.pi / w) * (np.pi / h) * np.sin(theta)[:, None]
    irradiance = (img * (np.clip(d[..., 1], 0, None) * solid)[..., None]).sum(axis=(0, 1))
    return ALBEDO / np.pi * irradiance


def test_a_sun_in_the_sky_lights_a_floor_as_the_integral_says(tmp_path):
    """A Lambertian floor under the sky image: the integral over the upper half, within
    3%."""
    img = _sun_sky(tmp_path / "ref.hdr")
    got = _floor(tmp_path, "mis", 256).reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(got, _floor_radiance(img), rtol=0.03)


@pytest.mark.parametrize("width, corner", [(2048, (300, 1001)), (2048, (301, 1002)),
                                           (2048, (302, 1003)), (5000, (301, 1002))])
def test_a_small_sun_in_a_wide_sky_keeps_its_power(tmp_path, corner, width):
    """A 2K sky (and one wider than the path tracer's grid, reduced by area) with a sun of
    3 x 3 texels, wherever it falls: the floor is lit as the full-resolution integral says,
    within 3% (a 2K sky was thinned to every 4th texel: the sun lit nothing or counted 16
    texels, 0.4x or 1.4x the reference)."""
    h = width // 2
    img = np.full((h, width, 3), 0.05, np.float32)
    y, x = corner[0] * h // 1024, corner[1] * width // 2048
    img[y:y + 3, x:x + 3] = 4000.0 * (2048 / width) ** 2  # the same sun's power in each
    write_hdr(tmp_path / "wide.hdr", img)
    img = read_hdr_image(tmp_path / "wide.hdr")  # (as RGBE keeps it)
    got = _floor(tmp_path, "mis", 64, sky="wide.hdr").reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(got, _floor_radiance(img), rtol=0.03)


def test_importance_sampling_the_sun_beats_bsdf_sampling(tmp_path):
    reference = _floor(tmp_path, "mis", 1024)
    errors = {s: np.sqrt(((_floor(tmp_path, s, 16) - reference) ** 2).mean())
              for s in ("mis", "bsdf")}
    assert errors["mis"] < 0.5 * errors["bsdf"], errors


@pytest.mark.parametrize("strategy", ["light", "mis", "bsdf"])
def test_a_constant_sky_lights_a_lambertian_floor_without_noise(strategy):
    """Under a constant sky L a Lambertian floor (nothing above it) sends albedo x L. Light
    sampling draws the sky's directions by the cosine about the surface, so each of its
    samples is that value exactly (uniform on the sphere, half of them fell below the floor
    and the rest carried the cosine's noise: 10-20% per pixel at 4 paths); MIS and BSDF
    sampling converge to it (both unbiased)."""
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(40), PbrMaterial(base_color=(ALBEDO,) * 3, metallic=0.0,
                                                      specular=0.0))
    camera = Camera.look_at((0, 3, 0.01), (0, 0, 0), fov_y=20, near=0.5, far=20)
    sky = np.array([0.25, 0.5, 1.0])
    PathEngine.strategy = strategy
    try:
        with facet.Renderer(32, 32) as r:
            img = r.render(scene, camera, engine="path", spp=4 if strategy == "light" else 256,
                           max_depth=0, float_color=True, lights="scene",
                           environment={"color": sky.tolist()}).color[..., :3]
    finally:
        PathEngine.strategy = "mis"
    want = ALBEDO * sky
    if strategy == "light":
        np.testing.assert_allclose(img.reshape(-1, 3), np.broadcast_to(want, (32 * 32, 3)),
                                   rtol=1e-4)
    else:
        np.testing.assert_allclose(img.reshape(-1, 3).mean(axis=0), want, rtol=0.01)


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_a_sky_of_one_colour_is_a_value_that_draws_what_its_cube_map_drew(engine,
                                                                           monkeypatch):
    """An environment of one colour (Environment.uniform_color) reaches the tracers'
    programs as a value (SKY_CONSTANT), not as a cube map looked up by every ray that
    escapes (on llvmpipe a tenth of a path-traced view of one object under a white sky):
    the same picture as through the cube map, eye rays, bounces and light sampling alike."""
    from facet.scene.environment import Environment

    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(6), PbrMaterial(base_color=(0.7, 0.5, 0.3),
                                                     metallic=0.0, roughness=0.6))
    scene.add(facet.primitives.sphere(0.5), PbrMaterial(base_color=(1, 1, 1), metallic=1.0,
                                                        roughness=0.0),
              facet.transforms.translate((0, 0.5, 0)))
    camera = Camera.look_at((0, 1.5, 3), (0, 0.4, 0), fov_y=40, near=0.5, far=20)
    sky = Environment.constant((1.0, 0.9, 0.7))

    def draw():
        with facet.Renderer(32, 32) as r:
            frames = [r.render(scene, camera, engine=engine, spp=4, float_color=f,
                               environment=sky, lights="scene").color for f in (True, False)]
            held = [dict(key[1]) for key in r._engines[engine].rays.programs]
        return frames, any("SKY_CONSTANT" in d for d in held)

    value, constant = draw()
    monkeypatch.setattr(Environment, "uniform_color", property(lambda self: None))
    cube, cube_constant = draw()
    assert constant and not cube_constant
    np.testing.assert_allclose(value[0], cube[0], rtol=1e-5, atol=1e-6)
    # (8-bit: a float's last bits may round a value the other way)
    assert np.abs(value[1].astype(int) - cube[1].astype(int)).max() <= 1
    assert (np.abs(value[0][..., :3] - (1.0, 0.9, 0.7)).max(axis=-1) < 1e-6).sum() > 32


@pytest.mark.parametrize("srgb", [False, True])
@pytest.mark.parametrize("kind", ["sky", "png", "hdr"])
def test_the_path_tracer_shows_the_sky_the_rasterizer_shows(tmp_path, kind, srgb):
    """The generated sky and 8-bit images hold display values, which the rasterizer shows
    as given outside the sRGB mode; the path tracer, whose output is linear radiance and
    encoded, decodes them there (it showed them brighter: each sky value taken as linear
    radiance). HDR images are linear radiance: shown encoded in the sRGB mode by both."""
    from PIL import Image

    spec = "sky"
    if kind != "sky":
        grid = equirect_directions(512, 256)
        img = np.clip(0.2 + 0.6 * np.abs(grid), 0, 1)
        spec = tmp_path / f"env.{kind}"
        if kind == "png":
            Image.fromarray((img * 255).round().astype(np.uint8)).save(spec)
        else:
            write_hdr(spec, img.astype(np.float32))
    if kind == "hdr" and not srgb:
        return  # the rasterizer shows linear values unencoded there (its own convention)
    scene = facet.Scene()
    cam = Camera.look_at((0, 0, 0), (1, 0.3, 0.2), fov_y=90, near=0.1, far=10)
    kw = dict(srgb=srgb, aa="none", environment=str(spec))
    with facet.Renderer(24, 24) as r:
        raster = r.render(scene, cam, engine="raster", **kw).color
        path = r.render(scene, cam, engine="path", **kw).color
    diff = np.abs(raster.astype(int) - path.astype(int)).max(axis=-1)
    if kind == "sky":
        # The generated sky is known by its equation: the path tracer's eye ray through
        # each pixel's centre sees it there (its grid filtered between texel centres). The
        # rasterizer's mipmapped cube map averages each pixel's footprint, which rounds
        # the horizon's steep gradient off by a few levels (3 at the 90th percentile here).
        from facet.scene.environment import sky_color

        n = raster.shape[0]
        j, i = np.meshgrid(np.arange(n), np.arange(n))
        d = np.stack([(j + 0.5) / n * 2 - 1, 1 - (i + 0.5) / n * 2, -np.ones((n, n))], -1)
        d = d @ np.asarray(cam.view, np.float64)[:3, :3]
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        want = np.clip(sky_color(d, *facet.Environment.SKY), 0, 1)  # display values,
        if srgb:  # or in the sRGB mode linear ones, encoded
            from facet.srgb import linear_to_srgb

            want = linear_to_srgb(want)
        error = np.abs(path[..., :3].astype(int) - np.round(want * 255)).max(axis=-1)
        assert np.percentile(error, 90) <= 1 and error.max() <= 3, (error.max(), error.mean())
        assert np.percentile(diff, 90) <= 3, np.percentile(diff, 90)
    else:
        # (the path tracer's samples are spread over each pixel: the horizon's row differs)
        assert np.percentile(diff, 90) <= 2, np.percentile(diff, 90)


def _floor_and_mirror(scene):
    lambert = PbrMaterial(base_color=(ALBEDO,) * 3, metallic=0.0, specular=0.0)
    scene.add(facet.primitives.plane(6), lambert)
    scene.add(facet.primitives.sphere(0.5), PbrMaterial(base_color=(1, 1, 1), metallic=1.0,
                                                        roughness=0.0),
              facet.transforms.translate((0, 0.5, 0)))
    return scene, Camera.look_at((0, 1.5, 3), (0, 0.4, 0), fov_y=40, near=0.5, far=20)


def test_no_light_but_what_the_scene_declares(tmp_path):
    """No ambient line and no lights (lights = "scene"): the path tracer's picture is black,
    as Mitsuba's is with no emitter (the default ambient term lit it as a grey sky the
    background did not show: a floor of 0.08, a mirror ball reflecting grey). An ambient
    light the file gives is a constant sky: a white-lit floor of albedo a under sky L shows
    a L, and the warning says eye rays see the background, not that sky."""
    scene, camera = _floor_and_mirror(facet.Scene())
    with facet.Renderer(32, 32) as r:
        img = r.render(scene, camera, engine="path", spp=4, float_color=True,
                       lights="scene").color[..., :3]
    assert img.max() == 0.0
    (tmp_path / "lit.toml").write_text(
        '[render]\nlights = "scene"\n[[lights]]\ntype = "ambient"\nintensity = 0.5\n')
    scene, camera = _floor_and_mirror(facet.load(tmp_path / "lit.toml"))
    with facet.Renderer(32, 32) as r, \
            pytest.warns(facet.FacetWarning, match="eye rays that escape show the background"):
        img = r.render(scene, camera, engine="path", spp=64, float_color=True).color
    assert img[28:, :, :3].mean() == pytest.approx(0.5 * ALBEDO, rel=0.05)
    # The rasterizer keeps the notes' ambient term (I_a = 0.1) when none is given.
    scene, camera = _floor_and_mirror(facet.Scene())
    with facet.Renderer(32, 32) as r:
        img = r.render(scene, camera, lights="scene", float_color=True).color[..., :3]
    assert img[28:].mean() > 0.05

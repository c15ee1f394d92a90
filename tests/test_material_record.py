"""The material record every engine reads (facet.render.material_record, glsl/lib/
material.glsl): slots the tracers used to leave out now reach them, engine against engine.

* occlusionTexture dims the ambient light in the rasterizer and the Whitted tracer alike
  (both light by an ambient term); the path tracer traces occlusion and says so.
* the clear coat's normal texture shows in what the coat reflects, in every engine: a
  striped coat normal over a dark base, under a sky bright on one side, gives stripes of
  the same contrast in the three engines.
"""

from __future__ import annotations

import numpy as np
import pytest

import facet
from facet.scene import primitives

SIZE = 64
CAM = facet.Camera.look_at((0, 0, 2.2), (0, 0, 0), fov_y=40)


def _quad_scene(material, ambient=0.0):
    scene = facet.Scene(ambient=ambient, background=(0, 0, 0))
    scene.add(primitives.plane(2.0), material, facet.transforms.rotate_x(90))
    return scene


def _halves(color):
    """Mean colour of the left and right thirds of the quad's middle rows (linear)."""
    rows = color[SIZE // 3: 2 * SIZE // 3]
    return rows[:, SIZE // 6: SIZE // 3, :3].mean(), rows[:, 2 * SIZE // 3: 5 * SIZE // 6,
                                                           :3].mean()


def test_occlusion_dims_the_ambient_light_in_the_rasterizer_and_the_ray_tracer(renderer):
    """A grey quad whose occlusion image is 0.25 on its left half and 1 on its right, lit by
    the ambient light alone (lights = "scene": no default rig): the left half is dimmer by the same ratio in both engines
    (within 3%), near the file's 0.25 (the ambient light's diffuse and specular parts are
    both dimmed). (Old code: the ray tracer left the slot out, both halves equal.)"""
    pixels = np.full((8, 8, 4), 255, np.uint8)
    pixels[:, :4, :3] = 64  # occlusion in red (and the rest)
    m = facet.PbrMaterial(base_color=(0.6, 0.6, 0.6, 1), metallic=0.0, roughness=0.8,
                          occlusion_texture=facet.TextureSlot(facet.Texture(pixels)))
    scene = _quad_scene(m, ambient=0.8)
    r = renderer(SIZE, SIZE)
    ratios = {}
    for engine in ("raster", "trace"):
        color = r.render(scene, CAM, engine=engine, aa="none", float_color=True,
                         lights="scene", outputs=("color",)).color
        left, right = _halves(color)
        ratios[engine] = left / right
    assert ratios["raster"] == pytest.approx(64 / 255, abs=0.03), ratios
    assert ratios["trace"] == pytest.approx(ratios["raster"], rel=0.03), ratios


def _stripes(n=64, tilt=0.5):
    """A normal map of vertical stripes 8 texels wide, tilted +x and -x by turns."""
    x = np.arange(n)
    t = np.where((x // 8) % 2 == 0, tilt, -tilt)
    normals = np.zeros((n, n, 3))
    normals[..., 0] = t[None, :]
    normals[..., 2] = np.sqrt(1 - t ** 2)[None, :]
    return facet.Texture(((normals * 0.5 + 0.5) * 255).round().astype(np.uint8)), t


def _half_sky(bright=4.0):
    """An environment of radiance ``bright`` where x < 0, black elsewhere (linear)."""
    from facet.scene.environment import Environment, equirect_directions, face_directions

    def radiance(d):
        out = np.zeros(d.shape[:-1] + (3,), np.float32)
        out[d[..., 0] < 0] = bright
        return out

    env = Environment(radiance(face_directions(64)), "half sky",
                      radiance(equirect_directions(256, 128)))
    env.linear = True
    return env


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_clear_coat_normal_map_shows_in_what_the_coat_reflects(renderer, engine):
    """A smooth clear coat whose normal map tilts by stripes over a dark rough base, under a
    sky bright where x < 0: stripes tilted towards -x reflect the bright half, the others
    the black one. The stripes' contrast (linear, mean over stripes of each tilt) is the
    coat's Fresnel reflectance times the sky, 0.04 x 4 = 0.16 at normal incidence, within
    25% in every engine. (Old code: the ray tracer traced no coat reflection, contrast 0.)"""
    tex, tilt = _stripes()
    m = facet.PbrMaterial(base_color=(0.05, 0.05, 0.05, 1), metallic=0.0, roughness=1.0,
                          clearcoat=1.0, clearcoat_roughness=0.0,
                          clearcoat_normal_texture=facet.TextureSlot(tex))
    scene = _quad_scene(m)
    r = renderer(SIZE, SIZE)
    sampling = {"raster": {"aa": "none"}, "trace": {"aa": "ssaa:grid:4"}, "path": {"spp": 64}}
    color = r.render(scene, CAM, engine=engine, environment=_half_sky(), float_color=True,
                     lights="scene", outputs=("color",), **sampling[engine]).color
    uv = r.render(scene, CAM, outputs=("uv",), aa="none").uv
    column = np.clip((uv[..., 0] * 64).astype(int), 0, 63)
    inside = (uv[..., 0] > 0.05) & (uv[..., 0] < 0.95) & (uv[..., 1] > 0.2) & (uv[..., 1] < 0.8)
    edge = (column % 8 == 0) | (column % 8 == 7)  # away from the stripes' edges
    towards_bright = inside & ~edge & (tilt[column] < 0)
    away = inside & ~edge & (tilt[column] > 0)
    contrast = color[towards_bright, :3].mean() - color[away, :3].mean()
    assert contrast == pytest.approx(0.16, rel=0.25), contrast

"""The path tracer's materials and lights against independent references: every texture
slot (with transforms, both uv sets and wrap modes) against the rasterizer under direct
light from one light, where both evaluate the same BRDF exactly; cut-outs in the colour
and in the exact channels; BLEND coverage; an emitting rectangle's light on a floor against
a numpy integration of the BRDF over the rectangle; light sampling, BSDF sampling and both
(multiple importance sampling) converging to the same picture, both with the lowest error;
one-sided emitters."""

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.render.path.engine import PathEngine
from facet.scene.light import DirectionalLight
from facet.scene.mesh import Mesh
from facet.scene.pbr import PbrMaterial, TextureSlot, texture_transform
from facet.scene.texture import Texture

from reference import _pbr_brdf_cos as pbr_f_cos

SIZE = 48
FRONT = Camera.look_at((0, 0, 3.2), (0, 0, 0), fov_y=40, near=0.5, far=10)


def _quad(size=2.0) -> Mesh:
    """A quad facing +z, uv (0, 0) at the lower left; the second set mirrored in u."""
    h = size / 2
    pos = [[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]]
    uv = [[0, 0], [1, 0], [1, 1], [0, 1]]
    uv1 = [[1, 0], [0, 0], [0, 1], [1, 1]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4, uv, uvs1=uv1, name="quad")


def _image(fn, n=16) -> Texture:
    """A texture of n x n texels from fn(x, y) -> (n, n, 4) values in [0, 1]."""
    y, x = np.mgrid[0:n, 0:n] / (n - 1.0)
    return Texture((np.clip(fn(x, y), 0, 1) * 255).round().astype(np.uint8))


def _textured_material() -> PbrMaterial:
    base = _image(lambda x, y: np.stack([x, y, 1 - x * y, np.ones_like(x)], -1))
    mr = _image(lambda x, y: np.stack([np.ones_like(x), 0.3 + 0.7 * x, y, np.ones_like(x)], -1))
    bumps = _image(lambda x, y: np.stack([0.5 + 0.3 * np.sin(6 * x), 0.5 + 0.3 * np.cos(5 * y),
                                          np.ones_like(x), np.ones_like(x)], -1))
    glow = _image(lambda x, y: np.stack([(x > 0.5) * 1.0, 0 * x, (y > 0.5) * 1.0,
                                         np.ones_like(x)], -1))
    return PbrMaterial(
        base_color=(0.9, 0.8, 0.7, 1), metallic=0.6, roughness=0.8, emissive=(0.2, 0.1, 0.3),
        base_color_texture=TextureSlot(base, transform=texture_transform(
            offset=(0.1, 0.0), rotation=0.3, scale=(0.8, 0.9)), wrap=("mirror", "clamp")),
        metallic_roughness_texture=TextureSlot(mr, texcoord=1),
        normal_texture=TextureSlot(bumps), emissive_texture=TextureSlot(glow),
        double_sided=True)


def _direct(scene, engine, **kw):
    with facet.Renderer(SIZE, SIZE) as r:
        if engine == "path":
            return r.render(scene, FRONT, engine="path", max_depth=0, float_color=True,
                            aa="none", lights="scene", **kw)
        frame = r.render(scene, FRONT, engine="raster", shading="pbr", float_color=True,
                         aa="none", lights="scene", **kw)
        return frame  # float colour: linear in every engine


def test_every_texture_slot_matches_the_rasterizer_under_direct_light():
    """Base colour (transformed, mirrored and clamped), metallic-roughness (second uv set),
    normal map and emissive texture, lit by one light without shadows and no ambient: the
    path tracer's one bounce is the rasterizer's equation, texel for texel."""
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=_textured_material())
    scene.add_light(DirectionalLight(direction=(-0.3, -0.4, -1.0), intensity=0.9))
    path = _direct(scene, "path").color[..., :3]
    raster = _direct(scene, "raster").color[..., :3]
    inside = raster.max(axis=-1) > 0  # the quad covers the middle of the picture
    inside[[0, -1], :] = inside[:, [0, -1]] = False
    assert inside.sum() > 900
    diff = np.abs(path[inside] - raster[inside])
    assert diff.mean() < 0.006 and np.percentile(diff, 99) < 0.03, (diff.mean(), diff.max())
    # Not trivially equal: the textures make the picture vary.
    assert path[inside].std(axis=0).min() > 0.05


def test_without_its_textures_the_picture_differs():
    """The comparison above can fail: dropping a slot changes the path tracer's picture."""
    scene = facet.Scene(ambient=0.0)
    full = _textured_material()
    scene.add(_quad(), material=full)
    scene.add_light(DirectionalLight(direction=(-0.3, -0.4, -1.0), intensity=0.9))
    a = _direct(scene, "path").color[..., :3]
    full.normal_texture = None
    b = _direct(scene, "path").color[..., :3]
    assert np.abs(a - b).mean() > 0.005


def _cutout_scene():
    holes = _image(lambda x, y: np.stack([x, x, x, ((x * 3).astype(int) + (y * 3).astype(int))
                                          % 2 * 1.0], -1), n=12)
    scene = facet.Scene(ambient=0.3)
    scene.add(_quad(), material=PbrMaterial(base_color=(1, 1, 1, 1), metallic=0.0,
                                            base_color_texture=TextureSlot(holes),
                                            alpha_mode="MASK", alpha_cutoff=0.5,
                                            double_sided=True))
    behind = PbrMaterial(base_color=(0.2, 0.3, 0.9, 1), metallic=0.0)
    scene.add(_quad(4.0), transform=facet.transforms.translate((0, 0, -1)), material=behind)
    return scene


def test_cut_outs_are_holes_in_colour_and_in_the_exact_channels():
    scene = _cutout_scene()
    with facet.Renderer(SIZE, SIZE) as r:
        path = r.render(scene, FRONT, engine="path", spp=4, outputs=("color", "ids", "depth"))
        raster = r.render(scene, FRONT, engine="raster", aa="none",
                          outputs=("color", "ids", "depth"))
    agree = (path.object_ids == raster.object_ids).mean()
    assert agree > 0.97, agree  # texel edges may round either way
    front = path.object_ids == 0
    assert 0.15 < front.mean() < 0.5  # both: the quad with its holes, the blue one behind
    # Where the quad is cut out, the blue one behind shows in the colour as well.
    holes = path.object_ids == 1
    blue = path.color[..., 2].astype(int) - path.color[..., 0]
    # (Colour is supersampled, the ids are pixel centres: edge pixels of the holes mix.)
    assert (blue[holes] > 60).mean() > 0.95 and (blue[front] < 30).mean() > 0.85


def test_blend_coverage_mixes_front_and_back():
    """An emitting BLEND quad of alpha 0.3 over an emitting opaque one, nothing lit: each
    path passes the front one with probability 0.7, so the picture is 0.3 front + 0.7 back,
    as the rasterizer blends it."""
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=PbrMaterial(base_color=(0, 0, 0, 0.3), alpha_mode="BLEND",
                                            emissive=(0.9, 0.9, 0.9), metallic=0.0))
    scene.add(_quad(4.0), transform=facet.transforms.translate((0, 0, -1)),
              material=PbrMaterial(base_color=(0, 0, 0, 1), emissive=(0.5, 0.2, 0.1),
                                   metallic=0.0))
    with facet.Renderer(SIZE, SIZE) as r:
        path = r.render(scene, FRONT, engine="path", spp=256, float_color=True,
                        lights="scene").color
    expected = 0.3 * np.array([0.9, 0.9, 0.9]) + 0.7 * np.array([0.5, 0.2, 0.1])
    centre = path[SIZE // 2 - 6:SIZE // 2 + 6, SIZE // 2 - 6:SIZE // 2 + 6, :3]
    np.testing.assert_allclose(centre.reshape(-1, 3).mean(axis=0), expected, rtol=0.02)


# -- emitters ------------------------------------------------------------------------------
LAMP_HEIGHT, LAMP_SIDE, LAMP_RADIANCE = 1.5, 1.0, 4.0
SIDE_CAMERA = Camera.look_at((0, 1.0, 3.0), (0, 0, 0), fov_y=30, near=0.5, far=20)
FLOOR = dict(base_color=(0.8, 0.7, 0.6, 1), metallic=0.0, roughness=0.6)


def _lamp_scene(floor=FLOOR, lamp=LAMP_RADIANCE, one_sided=True, flip=False):
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(8.0), material=PbrMaterial(**floor))
    lamp_mesh = facet.primitives.plane(LAMP_SIDE)  # faces +y: turned to face the floor
    turn = facet.transforms.rotate_x(180.0 if not flip else 0.0)
    scene.add(lamp_mesh, transform=facet.transforms.translate((0, LAMP_HEIGHT, 0)) @ turn,
              material=PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0,
                                   emissive=(1.0, 1.0, 1.0), emissive_strength=lamp,
                                   double_sided=not one_sided))
    return scene


def _lamp_on_floor_centre(n=400):
    """The radiance the floor's centre sends to SIDE_CAMERA in the light of the lamp: the
    BRDF integrated over the rectangle (midpoint rule, n x n cells)."""
    s = (np.arange(n) + 0.5) / n - 0.5
    x, z = np.meshgrid(s * LAMP_SIDE, s * LAMP_SIDE)
    p = np.stack([x.ravel(), np.full(x.size, LAMP_HEIGHT), z.ravel()], -1)
    r2 = (p ** 2).sum(-1)
    to_lamp = p / np.sqrt(r2)[:, None]
    cos_lamp = to_lamp[:, 1]  # the lamp faces straight down
    v = np.array([0.0, 1.0, 3.0]) / np.sqrt(10.0)
    up = np.broadcast_to([0.0, 1.0, 0.0], to_lamp.shape)
    f = pbr_f_cos(up, np.broadcast_to(v, to_lamp.shape), to_lamp, FLOOR["base_color"][:3],
                  FLOOR["metallic"], FLOOR["roughness"]) / np.pi
    d_area = (LAMP_SIDE / n) ** 2
    return LAMP_RADIANCE * (f * (cos_lamp / r2)[:, None]).sum(0) * d_area


def _render_lamp(strategy="mis", spp=64, size=32, **kw):
    PathEngine.strategy = strategy
    try:
        with facet.Renderer(size, size) as r:
            return r.render(_lamp_scene(**kw), SIDE_CAMERA, engine="path", spp=spp,
                            max_depth=0, float_color=True, lights="scene").color
    finally:
        PathEngine.strategy = "mis"


def test_an_emitting_rectangle_lights_the_floor_as_the_integral_says():
    colour = _render_lamp(spp=512)
    c = colour.shape[0] // 2
    measured = colour[c - 1:c + 1, c - 1:c + 1, :3].reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(measured, _lamp_on_floor_centre(), rtol=0.02)


def test_light_sampling_bsdf_sampling_and_both_agree_and_both_is_best():
    """The three estimators of the same integral converge to the same picture; at equal
    samples, multiple importance sampling has the lowest error against a converged one.
    A glossy metal floor (where BSDF sampling does well) and a rough one (where light
    sampling does): each single strategy has a floor it is bad at. (BSDF sampling alone
    is heavy-tailed here: its mean needs hundreds of paths to settle.)"""
    glossy = dict(base_color=(0.9, 0.9, 0.9, 1), metallic=1.0, roughness=0.25)
    errors = dict.fromkeys(("mis", "light", "bsdf"), 0.0)
    for floor in (FLOOR, glossy):
        reference = _render_lamp("mis", spp=1024, floor=floor, size=16)[..., :3]
        for strategy in errors:
            converged = _render_lamp(strategy, spp=512, floor=floor, size=16)[..., :3]
            # (The glossy floor's 512-path means scatter by about 2%: highlights.)
            np.testing.assert_allclose(converged.mean(), reference.mean(), rtol=0.03)
            noisy = _render_lamp(strategy, spp=16, floor=floor, size=16)[..., :3]
            errors[strategy] += np.sqrt(((noisy - reference) ** 2).mean())
    assert errors["mis"] < errors["light"] and errors["mis"] < errors["bsdf"], errors


def test_one_sided_emitters_light_only_their_front():
    lit = _render_lamp(spp=16)
    dark = _render_lamp(spp=16, flip=True)  # its front faces the sky
    assert lit[..., :3].mean() > 0.05
    assert dark[..., :3].max() == 0.0  # its back neither shines nor shows


@pytest.mark.parametrize("strategy", ["light", "bsdf"])
def test_two_sided_emitters_light_both_ways(strategy):
    a = _render_lamp(strategy, spp=64, one_sided=False)
    b = _render_lamp(strategy, spp=64, one_sided=False, flip=True)
    np.testing.assert_allclose(a[..., :3].mean(), b[..., :3].mean(), rtol=0.05)


def test_a_coloured_glass_block_absorbs_by_beer_lambert():
    """Through a cube of clear-coloured glass seen face on, against a sky of radiance 1:
    the front's reflection R, and sum over k of (1 - R)^2 e^(-sigma d) (R^2 e^(-2 sigma
    d))^k through it plus (1 - R)^2 R e^(-2 sigma d) (...)^k back out of the front, with
    R = ((n - 1) / (n + 1))^2 (the exact Fresnel factor at normal incidence)."""
    colour, distance, side, ior = np.array([0.9, 0.5, 0.2]), 0.8, 1.0, 1.5
    glass = PbrMaterial(base_color=(1, 1, 1), metallic=0.0, roughness=0.0, transmission=1.0,
                        thickness=side, ior=ior, attenuation_color=colour,
                        attenuation_distance=distance)
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.cube(side), glass)
    camera = Camera.look_at((0, 0, 6), (0, 0, 0), fov_y=4, near=1, far=20)
    with facet.Renderer(16, 16) as r:
        img = r.render(scene, camera, engine="path", spp=1024, float_color=True,
                       lights="scene", environment={"color": [1, 1, 1]}).color[..., :3]
    # Each path reflects or passes at random (the front's 4% of reflection: a bright
    # outlier): 36 pixels x 1024 paths put the mean's noise near 0.5%.
    sigma = -np.log(colour) / distance
    R = ((ior - 1) / (ior + 1)) ** 2
    through = np.exp(-sigma * side)
    series = (1 - R) ** 2 / (1 - R ** 2 * through ** 2)
    expected = R + series * through + series * R * through ** 2
    np.testing.assert_allclose(img[5:11, 5:11].reshape(-1, 3).mean(axis=0), expected,
                               rtol=0.02)


@pytest.mark.parametrize("thickness", [1.0, 0.0])
def test_clear_glass_in_a_white_furnace_disappears(thickness):
    """Smooth clear glass, a volume or thin-walled, neither makes nor loses light: in a
    constant sky every path ends in the sky with weight 1 (reflected or let through).
    At the silhouette a path may run out of bounces inside (total internal reflection):
    there only the picture's mean is held to it."""
    glass = PbrMaterial(base_color=(1, 1, 1), metallic=0.0, roughness=0.0, transmission=1.0,
                        thickness=thickness, ior=1.5, double_sided=True)
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.sphere(1.0), glass)
    with facet.Renderer(16, 16) as r:
        frame = r.render(scene, FRONT, engine="path", spp=16, float_color=True,
                         lights="scene", environment={"color": [1, 1, 1]},
                         outputs=("color", "normals"))
    img = frame.color[..., :3]
    facing = frame.normals[..., 2] > 0.5
    assert facing.sum() > 60
    np.testing.assert_allclose(img[facing], 1.0, atol=1e-3)
    assert img.mean() == pytest.approx(1.0, abs=0.005)


def test_an_area_light_is_an_emitting_rectangle():
    """facet.AreaLight in the path tracer: the rectangle of radiance pi I / A (area_lights):
    the floor below shows the same integral as under the emitting plane above."""
    from facet.scene.light import AreaLight

    scene = facet.Scene(ambient=0.0)
    scene.add(facet.primitives.plane(8.0), material=PbrMaterial(**FLOOR))
    area = LAMP_SIDE * LAMP_SIDE
    scene.add_light(AreaLight(position=(0, LAMP_HEIGHT, 0), normal=(0, -1, 0),
                              size=(LAMP_SIDE, LAMP_SIDE), attenuation=(0, 0, 1),
                              intensity=LAMP_RADIANCE * area / np.pi))
    with facet.Renderer(32, 32) as r:
        colour = r.render(scene, SIDE_CAMERA, engine="path", spp=512, max_depth=0,
                          float_color=True, lights="scene").color
    measured = colour[15:17, 15:17, :3].reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(measured, _lamp_on_floor_centre(), rtol=0.02)


def test_the_whitted_tracer_shades_gltf_materials_as_the_rasterizer_does():
    """engine="trace" shades a PbrMaterial by the rasterizer's BRDF with every texture slot
    (it traced Phong stand-ins before): under one light without ambient both engines agree
    to a few levels of 8 bits (the quad casts no shadow on itself)."""
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=_textured_material())
    scene.add_light(DirectionalLight(direction=(-0.3, -0.4, -1.0), intensity=0.9))
    with facet.Renderer(SIZE, SIZE) as r:
        kw = dict(aa="none", lights="scene", outputs=("color", "ids"))
        traced = r.render(scene, FRONT, engine="trace", **kw)
        raster = r.render(scene, FRONT, engine="raster", **kw)
    inside = (raster.object_ids == 0) & (traced.object_ids == 0)
    inside[[0, -1], :] = inside[:, [0, -1]] = False
    diff = np.abs(traced.color[..., :3].astype(int) - raster.color[..., :3])[inside]
    assert inside.sum() > 900
    assert diff.mean() < 1.5 and np.percentile(diff, 99) <= 6, (diff.mean(), diff.max())


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_unlit_materials_show_their_base_colour(engine):
    """KHR_materials_unlit: the base colour as it is, whatever the lights (the flag was
    packed where the shaders did not read it)."""
    scene = facet.Scene(ambient=0.3)
    scene.add(_quad(), material=PbrMaterial(base_color=(0.3, 0.6, 0.9), unlit=True))
    scene.add_light(DirectionalLight(direction=(-0.3, -0.4, -1.0), intensity=0.9))
    with facet.Renderer(16, 16) as r:
        img = r.render(scene, FRONT, engine=engine, float_color=True, srgb=True,
                       lights="scene", aa="none" if engine == "trace" else "ssaa:grid:1")
    linear = img.color[8, 8, :3]  # float colour: linear in every engine
    np.testing.assert_allclose(linear, (0.3, 0.6, 0.9), atol=2e-3)


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_colour_images_are_decoded_before_they_are_filtered(engine):
    """A 2-texel emissive image, black and white, stretched over a quad (glTF's
    TextureLinearInterpolationTest): in between, linear light blends to 0.5, as the
    rasterizer's sRGB textures do. The tracers resize images to one layer size; they did it
    on the encoded bytes, which gave srgb_to_linear(0.5) = 0.21 there."""
    glow = Texture(np.array([[[0, 0, 0, 255], [255, 255, 255, 255]]], np.uint8))
    mat = PbrMaterial(base_color=(0, 0, 0, 1), metallic=0.0, specular=0.0,
                      emissive=(1, 1, 1), emissive_texture=TextureSlot(glow),
                      double_sided=True)
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=mat)
    # A second, larger image makes the layers bigger than this one: it is resized.
    scene.add(_quad(0.1), material=PbrMaterial(base_color_texture=TextureSlot(
        _image(lambda x, y: np.stack([x, y, x, x * 0 + 1], -1), n=64))),
        transform=facet.transforms.translate((5, 5, 0)))
    with facet.Renderer(SIZE, SIZE) as r:
        kw = dict(lights="scene", srgb=True, float_color=True)
        img = r.render(scene, FRONT, engine=engine, aa="none" if engine == "trace" else
                       "ssaa:grid:1", **kw).color
        ref = r.render(scene, FRONT, engine="raster", aa="none", **kw).color
    row = img[SIZE // 2, :, 0]  # float colour: linear in every engine
    ref_row = ref[SIZE // 2, :, 0]
    c = SIZE // 2
    assert row[c] == pytest.approx(0.5, abs=0.06) and ref_row[c] == pytest.approx(0.5, abs=0.06)
    np.testing.assert_allclose(row[c - 8:c + 8], ref_row[c - 8:c + 8], atol=0.04)


@pytest.mark.parametrize("engine", ["trace", "path"])
@pytest.mark.parametrize("wrap", ["repeat", "clamp", "mirror"])
def test_nearest_filtering_shows_whole_texels_as_the_rasterizer_does(engine, wrap):
    """A 5 x 3 image of distinct texels, magnified with nearest filtering (and shifted by
    its transform so that the wrap modes show): each pixel is one texel's value, the
    rasterizer's, not a blend of neighbours (the tracers sampled it linearly, with a
    warning). A larger image elsewhere makes the layers bigger than this one."""
    rng = np.random.default_rng(3)
    pixels = rng.integers(0, 256, (3, 5, 4)).astype(np.uint8)
    pixels[..., 3] = 255
    slot = TextureSlot(Texture(pixels), filter=("nearest", "nearest"), wrap=(wrap, wrap),
                       transform=texture_transform(offset=(-0.3, -0.2), scale=(1.6, 1.4)))
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(), material=PbrMaterial(base_color_texture=slot, unlit=True))
    scene.add(_quad(0.1), material=PbrMaterial(base_color_texture=TextureSlot(
        _image(lambda x, y: np.stack([x, y, x, x * 0 + 1], -1), n=64))),
        transform=facet.transforms.translate((5, 5, 0)))
    with facet.Renderer(SIZE, SIZE) as r:
        kw = dict(lights="scene", float_color=True)
        img = r.render(scene, FRONT, engine=engine, aa="none" if engine == "trace" else
                       "ssaa:grid:1", **kw).color[..., :3]
        ref = r.render(scene, FRONT, engine="raster", aa="none", **kw).color[..., :3]
    inside = _inside_quad(ref)
    same = np.abs(img - ref).max(axis=-1)[inside] < 0.02
    assert same.mean() > 0.93, same.mean()  # all but pixels on texel borders


def _inside_quad(picture):
    inside = picture.max(axis=-1) > 0
    inside[[0, -1], :] = inside[:, [0, -1]] = False
    return inside


@pytest.mark.parametrize("shape", ["sphere", "box", "cylinder", "cone", "plane"])
def test_normal_maps_on_analytic_shapes_bend_as_on_the_tessellation(shape):
    """An analytic shape's tangent frame from its uvs (glsl/trace/shapes.glsl
    shape_tangent), as the rasterizer's tessellation gets its own: a normal-mapped shape
    under one light, path tracer against rasterizer (the path tracer ignored normal maps
    on shapes, with a warning)."""
    make = {"sphere": lambda: facet.shapes.Sphere(0.9), "box": lambda: facet.shapes.Box(1.1),
            "cylinder": lambda: facet.shapes.Cylinder(0.6, 1.2),
            "cone": lambda: facet.shapes.Cone(0.7, 1.2),
            "plane": lambda: facet.shapes.Plane((1.6, 1.6))}[shape]
    # Gentle bumps (where a mapped normal turns from the viewer the path tracer bends it
    # back, glsl/trace/material.glsl valid_normal, and the rasterizer does not) on a small
    # image, magnified everywhere (minified, the rasterizer's mip levels blur it).
    bumps = _image(lambda x, y: np.stack([0.5 + 0.15 * np.sin(9 * x),
                                          0.5 + 0.15 * np.cos(7 * y),
                                          np.ones_like(x), np.ones_like(x)], -1), n=16)
    mat = PbrMaterial(base_color=(0.8, 0.7, 0.6), metallic=0.0, roughness=0.5,
                      normal_texture=TextureSlot(bumps), double_sided=True)
    turn = facet.transforms.rotate_x(35.0) @ facet.transforms.rotate_y(25.0)
    if shape == "plane":
        turn = facet.transforms.rotate_x(70.0)
    if shape == "cylinder":  # on its side: its caps (whose v is constant: no frame) unseen
        turn = facet.transforms.rotate_x(30.0) @ facet.transforms.rotate_z(90.0)
    results = {}
    for with_map in (True, False):
        scene = facet.Scene(ambient=0.0)
        scene.add(make(), material=mat if with_map else PbrMaterial(
            base_color=(0.8, 0.7, 0.6), metallic=0.0, roughness=0.5, double_sided=True),
            transform=turn)
        scene.add_light(DirectionalLight(direction=(-0.4, -0.5, -1.0), intensity=1.0))
        raster = _direct(scene, "raster", outputs=("color", "normals"))
        results[with_map] = (_direct(scene, "path").color[..., :3], raster.color[..., :3],
                             raster.normals)
    path, raster, normals = results[True]
    # Where the surface faces the camera: at grazing angles the path tracer's valid_normal
    # bends mapped normals back (above).
    inside = (path.max(axis=-1) > 0) & (raster.max(axis=-1) > 0) & (normals[..., 2] > 0.5)
    diff = np.abs(path - raster)[inside]
    assert diff.mean() < 0.012, diff.mean()
    flat_path = results[False][0]
    assert np.abs(path - flat_path)[inside].mean() > 0.01  # the map does bend the light


@pytest.mark.parametrize("roughness", [0.0, 0.2])
def test_the_whitted_tracer_reflects_the_scene_in_gltf_metals_as_the_path_tracer(roughness):
    """A metal ball before a red wall (behind the camera, lit by nothing: unlit): what the
    ball shows is the wall reflected, which the Whitted tracer traced as the ambient
    light's split sum alone (black here, with a warning). Against the path tracer, block
    means over the ball."""
    scene = facet.Scene(ambient=0.0)
    scene.add(facet.shapes.Sphere(0.8), material=PbrMaterial(
        base_color=(0.9, 0.85, 0.8), metallic=1.0, roughness=roughness))
    scene.add(_quad(12.0), material=PbrMaterial(base_color=(0.8, 0.1, 0.1), unlit=True),
              transform=facet.transforms.translate((0, 0, 5)) @ facet.transforms.rotate_y(180))
    with facet.Renderer(SIZE, SIZE) as r:
        kw = dict(lights="scene", float_color=True)
        traced = r.render(scene, FRONT, engine="trace", **kw).color[..., :3]
        path = r.render(scene, FRONT, engine="path", spp=64, max_depth=2, **kw).color[..., :3]
    ball = (slice(16, 32), slice(16, 32))
    a, b = traced[ball].mean(axis=(0, 1)), path[ball].mean(axis=(0, 1))
    assert b[0] > 0.3  # the wall is there
    np.testing.assert_allclose(a, b, rtol=0.05, atol=0.01)


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_blend_coverage_follows_the_texture_alpha_as_rasterized(engine):
    """A BLEND pane whose base-colour texture fades from clear to opaque across it, over a
    backdrop: each tracer mixes front and back by the texel's alpha, as the rasterizer's
    transparent pass does (the Whitted tracer used the factor's alpha alone, with a
    warning)."""
    fade = _image(lambda x, y: np.stack([np.ones_like(x), 0.2 + 0 * x, 0.2 + 0 * x, x], -1))
    scene = facet.Scene(ambient=0.0)
    scene.add(_quad(4.0), material=PbrMaterial(base_color=(0.1, 0.3, 0.9), unlit=True),
              transform=facet.transforms.translate((0, 0, -1)))
    scene.add(_quad(), material=PbrMaterial(base_color_texture=TextureSlot(fade), unlit=True,
                                            alpha_mode="BLEND"))
    with facet.Renderer(SIZE, SIZE) as r:
        kw = dict(lights="scene", float_color=True)
        # (the path tracer's coverage is stochastic: many samples)
        aa = "ssaa:grid:4" if engine == "trace" else "ssaa:jittered:256"
        traced = r.render(scene, FRONT, engine=engine, aa=aa, **kw).color[..., :3]
        raster = r.render(scene, FRONT, engine="raster", aa="ssaa:grid:4", **kw).color[..., :3]
    row = (slice(20, 28), slice(10, 38))  # across the fade
    a, b = traced[row].mean(axis=0), raster[row].mean(axis=0)
    assert np.ptp(b[:, 0]) > 0.5  # the fade is there
    np.testing.assert_allclose(a, b, atol=0.03)


def test_whitted_shadow_rays_pass_blend_coverage_and_cut_outs():
    """A pane between a light and a floor: BLEND with texture alpha 0.25 lets 0.75 of the
    light through, a MASK cut-out (alpha below its cutoff) all of it (the Whitted tracer's
    shadow rays took the factor's alpha: a full shadow under both)."""
    quarter = _image(lambda x, y: np.stack([x * 0 + 1, x * 0 + 1, x * 0 + 1, x * 0 + 0.25], -1))
    down = Camera.look_at((0, 3, 0.001), (0, 0, 0), fov_y=20, near=0.5, far=10)
    seen = {}
    for name, pane in (("none", None),
                       ("blend", PbrMaterial(base_color_texture=TextureSlot(quarter),
                                             alpha_mode="BLEND", double_sided=True)),
                       ("mask", PbrMaterial(base_color_texture=TextureSlot(quarter),
                                            alpha_mode="MASK", alpha_cutoff=0.5,
                                            double_sided=True))):
        scene = facet.Scene(ambient=0.0)
        scene.add(facet.primitives.plane(4.0), material=PbrMaterial(
            base_color=(0.8, 0.8, 0.8), metallic=0.0, specular=0.0))
        if pane is not None:  # above the floor, out of the camera's view below it
            scene.add(facet.primitives.plane(8.0), material=pane,
                      transform=facet.transforms.translate((0, 3.5, 0)))
        scene.add_light(DirectionalLight(direction=(0, -1, 0), intensity=1.0))
        with facet.Renderer(16, 16) as r:
            seen[name] = r.render(scene, down, engine="trace", float_color=True, aa="none",
                                  lights="scene").color[8, 8, :3]
    assert seen["none"][0] > 0.5
    np.testing.assert_allclose(seen["blend"], 0.75 * seen["none"], rtol=0.02)
    np.testing.assert_allclose(seen["mask"], seen["none"], rtol=0.02)

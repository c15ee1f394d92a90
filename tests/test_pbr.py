"""Tier 2: the physically based model (glsl/mesh/pbr.frag) against numpy references of the
glTF specification's BRDF (tests/reference.py): spheres under one directional light and
under uniform light from everywhere (the exact hemisphere integral, not the split sum),
colour management, alpha modes, texture transforms and wrap modes, normal maps, emissive,
occlusion, single-sided culling and vertex colours.

Outputs are sRGB-encoded 8-bit; interior pixels must agree within the stated tolerances.
"""

import numpy as np
import pytest

from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Mesh, Scene
from facet.scene.environment import Environment
from facet.scene.pbr import PbrMaterial, TextureSlot, texture_transform
from facet.scene.texture import Texture

from conftest import sphere_mesh
from reference import (
    erode,
    pbr_directional,
    pbr_uniform_environment,
    pixel_rays,
    ray_sphere,
    srgb_encode,
)

SIZE = 64
CAMERA = Camera.look_at((0, 0, 4), (0, 0, 0), ortho_height=2.4, near=1, far=10)
MATERIALS = {
    "rough dielectric": dict(base_color=(0.8, 0.3, 0.2, 1), metallic=0.0, roughness=0.9),
    "glossy dielectric": dict(base_color=(0.2, 0.4, 0.8, 1), metallic=0.0, roughness=0.35),
    "gold": dict(base_color=(1.0, 0.77, 0.34, 1), metallic=1.0, roughness=0.4),
    "half metal": dict(base_color=(0.6, 0.6, 0.6, 1), metallic=0.5, roughness=0.6),
}


def _sphere_geometry():
    """Per pixel: the exact sphere's normal, the view direction and the interior mask."""
    origins, dirs = pixel_rays(CAMERA.view, CAMERA.projection(SIZE, SIZE), SIZE, SIZE)
    t = ray_sphere(origins, dirs, (0, 0, 0), 1.0)
    mask = np.isfinite(t)
    normals = origins + np.where(mask, t, 0)[..., None] * dirs
    # Grazing pixels depend on the tessellation's normals, not on the BRDF.
    return normals, -dirs, erode(mask, 2) & (normals[..., 2] > 0.35)


def _render(renderer, material, lights=(), ambient=0.0, environment=None, srgb=False,
            mesh=None, camera=CAMERA, size=SIZE, **opts):
    scene = Scene(ambient=ambient)
    scene.add(mesh or sphere_mesh(), material)
    for light in lights:
        scene.add_light(light)
    return renderer(size, size).render(scene, camera, lights="scene", environment=environment,
                                       srgb=srgb, aa="none", **opts)


@pytest.mark.parametrize("name", MATERIALS)
def test_sphere_under_a_directional_light(renderer, name):
    kw = MATERIALS[name]
    light = DirectionalLight((-0.5, -0.6, -1.0), (1.0, 0.95, 0.9), 0.8)
    frame = _render(renderer, PbrMaterial(**kw), [light])
    N, V, mask = _sphere_geometry()
    expected = srgb_encode(pbr_directional(N, V, light.direction,
                                           np.asarray(light.color) * light.intensity,
                                           kw["base_color"][:3], kw["metallic"],
                                           kw["roughness"]))
    got = frame.color[..., :3] / 255.0
    err = np.abs(got - expected)[mask]
    assert mask.sum() > 1000
    assert np.percentile(err, 99) <= 3 / 255, (name, err.max())
    assert err.max() <= 8 / 255, (name, err.max())
    assert got[mask].std() > 0.05  # lit, not flat


@pytest.mark.parametrize("name", MATERIALS)
@pytest.mark.parametrize("source", ["ambient", "environment"])
def test_sphere_under_uniform_light_from_everywhere(renderer, name, source):
    """Radiance 0.7 from every direction, as the scene's ambient intensity (the model's
    light without an environment) or as an environment map of that constant colour (the
    prefiltered-map path): both must give the exact hemisphere integral."""
    kw = MATERIALS[name]
    radiance = 0.7
    env = Environment(np.full((6, 32, 32, 3), radiance)) if source == "environment" else None
    frame = _render(renderer, PbrMaterial(**kw), ambient=radiance if env is None else 0.0,
                    environment=env)
    N, V, mask = _sphere_geometry()
    nv = np.sum(N * V, -1)
    table_nv = np.linspace(0.3, 1.0, 29)
    table = pbr_uniform_environment(table_nv, kw["base_color"][:3], kw["metallic"],
                                    kw["roughness"], radiance)
    expected = np.stack([np.interp(nv, table_nv, table[:, c]) for c in range(3)], -1)
    expected = srgb_encode(expected)
    err = np.abs(frame.color[..., :3] / 255.0 - expected)[mask]
    assert np.percentile(err, 99) <= 3 / 255, (name, source, err.max())
    assert err.max() <= 5 / 255, (name, source, err.max())


def test_base_colour_is_linear_and_output_encoded(renderer):
    """glTF's factors are linear: base colour 0.8 shows as sRGB 231, with and without
    --srgb (a Phong colour 0.8 stays 204 without it)."""
    quad = _quad()
    for srgb in (False, True):
        frame = _render(renderer, PbrMaterial(base_color=(0.8, 0.8, 0.8, 1), unlit=True),
                        mesh=quad, srgb=srgb)
        assert abs(int(frame.color[32, 32, 0]) - 231) <= 1, srgb
    # Drawn by Phong (--shading phong), the linear colour is still shown as 231.
    frame = _render(renderer, PbrMaterial(base_color=(0.8, 0.8, 0.8, 1)), mesh=quad,
                    shading="unlit")
    assert abs(int(frame.color[32, 32, 0]) - 231) <= 1


def _quad(uvs=((0, 0), (1, 0), (1, 1), (0, 1)), size=1.0, colors=None):
    s = size
    return Mesh([[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]], [[0, 1, 2], [0, 2, 3]],
                uvs=np.asarray(uvs, dtype=float), colors=colors)


QUAD_CAMERA = Camera.look_at((0, 0, 3), (0, 0, 0), ortho_height=2.0, near=1, far=10)


def _pixel_uv(size=SIZE):
    """The quad's uv at every pixel centre seen by QUAD_CAMERA (rows top to bottom)."""
    c = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(c, c[::-1])
    return u, v


def _checker(n=4):
    """An n x n image whose texel (row r, column c) has red = 40 c + 20, green = 40 r + 20
    (row 0 at the top: v = 1)."""
    r, c = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    px = np.zeros((n, n, 4), np.uint8)
    px[..., 0], px[..., 1], px[..., 3] = 40 * c + 20, 40 * r + 20, 255
    return Texture(px)


def _texel(u, v, n=4):
    """The checker texel (row, column) at texture coordinates already wrapped into [0, 1)."""
    col = np.clip(np.floor(u * n), 0, n - 1)
    row = np.clip(n - 1 - np.floor(v * n), 0, n - 1)
    return row, col


@pytest.mark.parametrize("wrap", ["repeat", "clamp", "mirror"])
def test_texture_transform_and_wrap_modes(renderer, wrap):
    """uv in [0, 1] scaled by 2.5 and offset by -0.7 (KHR_texture_transform), sampled with
    nearest filtering: each pixel shows the texel a numpy wrap of its uv names."""
    transform = texture_transform(offset=(-0.7, -0.7), scale=(2.5, 2.5))
    slot = TextureSlot(_checker(), transform=transform, wrap=(wrap, wrap),
                       filter=("nearest", "nearest"), mipmaps=False)
    frame = _render(renderer, PbrMaterial(base_color_texture=slot, unlit=True),
                    mesh=_quad(), camera=QUAD_CAMERA, srgb=True)
    u, v = _pixel_uv()
    tu, tv = 2.5 * u - 0.7, 2.5 * v - 0.7
    # Texel borders (multiples of 1/4 before wrapping) are ambiguous by half a pixel.
    edge = lambda t: np.abs(t * 4 - np.rint(t * 4)) < 0.05  # noqa: E731
    keep = ~(edge(tu) | edge(tv))
    if wrap == "repeat":
        tu, tv = tu % 1.0, tv % 1.0
    elif wrap == "clamp":
        tu, tv = np.clip(tu, 0, 1), np.clip(tv, 0, 1)
    else:
        tu, tv = 1 - np.abs(tu % 2.0 - 1), 1 - np.abs(tv % 2.0 - 1)
    row, col = _texel(tu, tv)
    assert keep.mean() > 0.6
    np.testing.assert_array_equal(frame.color[..., 0][keep], (40 * col + 20)[keep])
    np.testing.assert_array_equal(frame.color[..., 1][keep], (40 * row + 20)[keep])


def test_second_texture_coordinate_set(renderer):
    """A slot reading TEXCOORD_1 (uvs1) follows that set, not the first."""
    quad = _quad()
    swapped = Mesh(quad.positions, quad.faces, uvs=quad.uvs, uvs1=quad.uvs[:, ::-1])
    slot = TextureSlot(_checker(), texcoord=1, filter=("nearest", "nearest"), mipmaps=False)
    frame = _render(renderer, PbrMaterial(base_color_texture=slot, unlit=True), mesh=swapped,
                    camera=QUAD_CAMERA, srgb=True)
    u, v = _pixel_uv()
    row, col = _texel(v, u)  # the second set swaps u and v
    keep = (np.abs(u * 4 - np.rint(u * 4)) > 0.05) & (np.abs(v * 4 - np.rint(v * 4)) > 0.05)
    np.testing.assert_array_equal(frame.color[..., 0][keep], (40 * col + 20)[keep])


def _flat_normal_map(t):
    """A 4x4 normal map holding the tangent-space normal ``t`` everywhere."""
    px = np.zeros((4, 4, 4), np.uint8)
    px[..., :3] = np.rint((np.asarray(t) * 0.5 + 0.5) * 255)
    px[..., 3] = 255
    return Texture(px)


@pytest.mark.parametrize("rotated", [False, True])
@pytest.mark.parametrize("supplied", [False, True])
def test_normal_map_tilts_the_normal_along_the_tangent_frame(renderer, rotated, supplied):
    """Tangent-space normal (0.6, 0, 0.8) on a quad facing +z: the shading normal tilts
    towards +u, i.e. world +x, or world +y when the uvs are turned a quarter round; lit from
    that tilted direction the quad is brighter than without the map by the reference's
    amount. Tangents computed from the uvs, or supplied with the mesh."""
    t = np.array([0.6, 0.0, 0.8])
    uvs = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], dtype=float)
    if rotated:  # u now grows along world +y
        uvs = np.array([(0, 1), (0, 0), (1, 0), (1, 1)], dtype=float)
    quad = _quad(uvs)
    if supplied:
        tangent = (0.0, 1.0, 0.0, 1.0) if rotated else (1.0, 0.0, 0.0, 1.0)
        quad = Mesh(quad.positions, quad.faces, uvs=quad.uvs, tangents=np.tile(tangent, (4, 1)))
    tilted = np.array([0.0, 0.6, 0.8]) if rotated else np.array([0.6, 0.0, 0.8])
    light = DirectionalLight(-(tilted + np.array([0.0, 0.0, 0.3])), (1, 1, 1), 0.6)
    mat = dict(base_color=(0.7, 0.7, 0.7, 1), metallic=0.0, roughness=0.8)
    slot = TextureSlot(_flat_normal_map(t), filter=("nearest", "nearest"), mipmaps=False)
    frame = _render(renderer, PbrMaterial(normal_texture=slot, **mat), [light], mesh=quad,
                    camera=QUAD_CAMERA)
    V = np.array([0.0, 0.0, 1.0])
    n8 = np.rint((t * 0.5 + 0.5) * 255) / 255 * 2 - 1  # the 8-bit texel's normal
    n_world = (np.array([0.0, n8[0], n8[2]]) if rotated else np.array([n8[0], 0.0, n8[2]]))
    n_world /= np.linalg.norm(n_world)
    expected = srgb_encode(pbr_directional(n_world[None], V[None], light.direction,
                                           np.ones(3) * 0.6, mat["base_color"][:3], 0.0,
                                           0.8))[0]
    got = frame.color[32, 32, :3] / 255.0
    assert np.abs(got - expected).max() <= 3 / 255, (got, expected)
    flat = _render(renderer, PbrMaterial(**mat), [light], mesh=quad, camera=QUAD_CAMERA)
    assert frame.color[32, 32, 0] > flat.color[32, 32, 0] + 5


def test_alpha_mask_cuts_where_alpha_is_below_the_cutoff(renderer):
    """Alpha rising left to right (texture) times 0.9 (factor), cutoff 0.5: the left part is
    cut out of colour and of the exact channels; OPAQUE ignores alpha."""
    n = 8
    px = np.zeros((1, n, 4), np.uint8)
    px[..., :3] = 200
    px[0, :, 3] = np.rint((np.arange(n) + 0.5) / n * 255)
    slot = TextureSlot(Texture(px), filter=("nearest", "nearest"), mipmaps=False)
    mat = PbrMaterial(base_color=(1, 1, 1, 0.9), base_color_texture=slot, alpha_mode="MASK",
                      alpha_cutoff=0.5, unlit=True)
    frame = _render(renderer, mat, mesh=_quad(), camera=QUAD_CAMERA, srgb=True,
                    outputs=("color", "ids"))
    u, _ = _pixel_uv()
    alpha = np.rint((np.floor(u * n) + 0.5) / n * 255) / 255 * 0.9
    np.testing.assert_array_equal(frame.object_ids >= 0, alpha >= 0.5)
    np.testing.assert_array_equal(frame.color[..., 0] > 100, alpha >= 0.5)
    opaque = _render(renderer, PbrMaterial(base_color=(1, 1, 1, 0.9), base_color_texture=slot,
                                           unlit=True), mesh=_quad(), camera=QUAD_CAMERA,
                     outputs=("color", "ids"))
    assert (opaque.object_ids >= 0).all()


def test_alpha_blend_composites_over_the_background(renderer):
    """BLEND with alpha 0.4 over a grey background: 0.4 C + 0.6 background (linear light,
    --srgb), and the quad is not in the exact channels (as transparent objects are not)."""
    mat = PbrMaterial(base_color=(1.0, 0.0, 0.0, 0.4), alpha_mode="BLEND", unlit=True)
    scene = Scene(ambient=0.0, background=(0.5, 0.5, 0.5, 1))
    scene.add(_quad(), mat)
    frame = renderer(SIZE, SIZE).render(scene, QUAD_CAMERA, srgb=True, aa="none",
                                        outputs=("color", "ids"))
    bg = ((0.5 + 0.055) / 1.055) ** 2.4  # the sRGB-encoded background, linear
    expected = srgb_encode(np.array([0.4 + 0.6 * bg, 0.6 * bg, 0.6 * bg]))
    assert np.abs(frame.color[32, 32, :3] / 255.0 - expected).max() <= 2 / 255
    assert (frame.object_ids == -1).all()


def test_emissive_occlusion_and_vertex_colours(renderer):
    """Emissive (factor x strength x texture) adds to the light; occlusion darkens only the
    light from everywhere; vertex colours multiply the base colour (and the texture)."""
    quad = _quad()
    base = dict(base_color=(0.5, 0.5, 0.5, 1), metallic=0.0, roughness=1.0)
    plain = _render(renderer, PbrMaterial(**base), ambient=0.5, mesh=quad, camera=QUAD_CAMERA,
                    srgb=True).color[32, 32, :3].astype(int)
    glow = PbrMaterial(**base, emissive=(0.1, 0.0, 0.0), emissive_strength=2.0)
    lit = _render(renderer, glow, ambient=0.5, mesh=quad, camera=QUAD_CAMERA,
                  srgb=True).color[32, 32, :3].astype(int)
    linear = ((plain / 255 + 0.055) / 1.055) ** 2.4
    assert abs(lit[0] - 255 * srgb_encode(linear[0] + 0.2)) <= 2 and abs(lit[1] - plain[1]) <= 1
    half = Texture(np.full((2, 2, 4), (128, 255, 255, 255), np.uint8))
    occluded = _render(renderer, PbrMaterial(**base, occlusion_texture=TextureSlot(half)),
                       ambient=0.5, mesh=quad, camera=QUAD_CAMERA,
                       srgb=True).color[32, 32, :3].astype(int)
    expected = 255 * srgb_encode(linear * (128 / 255))
    assert np.abs(occluded - expected).max() <= 2
    red = np.tile([1.0, 0.0, 0.0, 1.0], (4, 1))
    tinted = _render(renderer, PbrMaterial(base_color=(1, 1, 1, 1), unlit=True),
                     mesh=_quad(colors=red), camera=QUAD_CAMERA)
    assert tuple(tinted.color[32, 32, :3]) == (255, 0, 0)


def test_single_sided_materials_hide_back_faces(renderer):
    back = Camera.look_at((0, 0, -3), (0, 0, 0), ortho_height=2.0, near=1, far=10)
    for double, seen in ((False, False), (True, True)):
        frame = _render(renderer, PbrMaterial(double_sided=double, unlit=True), mesh=_quad(),
                        camera=back, outputs=("color", "ids"))
        assert bool(frame.object_ids[32, 32] >= 0) == seen, double
        assert (frame.color[32, 32, 0] > 128) == seen


def test_occlusion_packed_with_metallic_roughness_reads_one_image(renderer):
    """glTF's common ORM packing (occlusion in the red channel of the metallic-roughness
    image) draws as the same occlusion given as an image of its own."""
    orm = np.zeros((2, 2, 4), np.uint8)
    orm[...] = (100, 200, 30, 255)  # occlusion 0.39, roughness 0.78, metallic 0.12
    packed = Texture(orm)
    alone = Texture(orm.copy())
    base = dict(base_color=(0.6, 0.5, 0.4, 1), metallic=1.0, roughness=1.0)
    one = PbrMaterial(**base, metallic_roughness_texture=TextureSlot(packed),
                      occlusion_texture=TextureSlot(packed))
    two = PbrMaterial(**base, metallic_roughness_texture=TextureSlot(packed),
                      occlusion_texture=TextureSlot(alone))
    light = DirectionalLight((0.3, -0.2, -1), (1, 1, 1), 0.5)
    a = _render(renderer, one, [light], ambient=0.6, mesh=_quad(), camera=QUAD_CAMERA)
    b = _render(renderer, two, [light], ambient=0.6, mesh=_quad(), camera=QUAD_CAMERA)
    np.testing.assert_array_equal(a.color, b.color)
    none = _render(renderer, PbrMaterial(**base, metallic_roughness_texture=TextureSlot(packed)),
                   [light], ambient=0.6, mesh=_quad(), camera=QUAD_CAMERA)
    assert int(none.color[32, 32, 0]) > int(a.color[32, 32, 0]) + 10  # occlusion applied


def test_alpha_mask_cut_outs_cast_no_shadow(renderer):
    """A MASK card whose left half is cut out, between a light and a floor: only its right
    half shades the floor (the shadow map cuts it out as the picture does)."""
    px = np.zeros((1, 2, 4), np.uint8)
    px[..., :3] = 255
    px[0, 1, 3] = 255  # left texel alpha 0, right texel alpha 1
    slot = TextureSlot(Texture(px), filter=("nearest", "nearest"), mipmaps=False)
    card = PbrMaterial(base_color_texture=slot, alpha_mode="MASK", double_sided=True)
    scene = Scene(ambient=0.0)
    floor = Mesh([[-3, 0, -3], [3, 0, -3], [3, 0, 3], [-3, 0, 3]], [[0, 2, 1], [0, 3, 2]])
    scene.add(floor, PbrMaterial(base_color=(0.8, 0.8, 0.8, 1), metallic=0, roughness=1))
    # The card 1 above the floor, facing down (its uv u runs along x).
    scene.add(Mesh([[-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1]], [[0, 1, 2], [0, 2, 3]],
                   uvs=[[0, 0], [1, 0], [1, 1], [0, 1]]), card)
    scene.add_light(DirectionalLight((0, -1, 0), (1, 1, 1), 1.0))
    # Looking straight down (camera x = world x): through the cut-out half the floor shows.
    cam = Camera.look_at((0, 6, 0.001), (0, 0, 0), up=(0, 0, -1), ortho_height=5, near=1,
                         far=20)
    frame = renderer(SIZE, SIZE).render(scene, cam, lights="scene", shadows=True, aa="none",
                                        outputs=("color", "ids"))
    x = (np.arange(SIZE) + 0.5) / SIZE * 5 - 2.5  # world x of each column
    rows = slice(SIZE // 2 - 4, SIZE // 2 + 4)
    cut = (x > -0.9) & (x < -0.1)  # under the cut-out half of the card
    assert (frame.object_ids[rows][:, cut] == 0).all()  # the floor, seen through it
    assert frame.color[rows][:, cut, 0].min() > 150  # and lit: the cut-out cast no shadow
    kept = (x > 0.1) & (x < 0.9)
    assert (frame.object_ids[rows][:, kept] == 1).all()  # the card's solid half

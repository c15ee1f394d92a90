"""Textures, vertex colours and the two colour modes, against numpy references."""

import numpy as np
import pytest
import trimesh
from PIL import Image

from facet.errors import InputError, SceneError
from facet.formats import load_scene
from facet.geometry.camera import Camera
from facet.image.colorspace import linear_to_srgb, srgb_to_linear
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, Material, Mesh, Scene
from facet.scene.texture import Texture

SIZE = 64
# An orthographic camera that sees exactly the square [-1, 1]^2 of the z = 0 plane.
CAMERA = Camera.look_at((0, 0, 2), (0, 0, 0), ortho_height=2.0, near=1, far=3)


def quad(colors=None):
    pos = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]
    return Mesh(pos, [[0, 1, 2], [0, 2, 3]], [[0, 0, 1]] * 4,
                [[0, 0], [1, 0], [1, 1], [0, 1]], colors=colors)


def bilinear_repeat(pixels, u, v):
    """GL_LINEAR sampling with GL_REPEAT of an image whose row 0 is the top (v = 1)."""
    img = pixels[::-1].astype(np.float64)  # row 0 = v = 0, as uploaded
    h, w = img.shape[:2]
    x, y = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]

    def at(yy, xx):
        return img[yy % h, xx % w]

    return ((at(y0, x0) * (1 - fx) + at(y0, x0 + 1) * fx) * (1 - fy)
            + (at(y0 + 1, x0) * (1 - fx) + at(y0 + 1, x0 + 1) * fx) * fy)


def render_unlit(renderer, mesh, material, srgb=False, size=SIZE, camera=CAMERA):
    scene = Scene()
    scene.add(mesh, material)
    if srgb:
        with Renderer(size, size, srgb=True) as r:
            return r.render(scene, camera, shading="unlit")
    return renderer(size, size).render(scene, camera, shading="unlit")


def test_textured_quad_samples_known_uvs(renderer):
    rng = np.random.default_rng(5)
    pixels = rng.integers(0, 256, (4, 4, 3), dtype=np.uint8)
    frame = render_unlit(renderer, quad(), Material(color=(1, 1, 1), texture=Texture(pixels)))
    j = np.arange(SIZE)
    u = ((j + 0.5) / SIZE)[None, :].repeat(SIZE, 0)
    v = (1 - (j + 0.5) / SIZE)[:, None].repeat(SIZE, 1)
    expected = bilinear_repeat(pixels, u, v)
    err = np.abs(frame.color[..., :3].astype(float) - expected)
    assert err.max() <= 1.5, err.max()
    # Orientation: near the centre of the top-left texel we see the image's top-left pixel.
    assert np.abs(frame.color[7, 7, :3].astype(int) - pixels[0, 0]).max() <= 12


def test_mipmaps_average_a_minified_checker(renderer):
    """A 1-pixel checker shrunk 16x: trilinear mipmapping gives the mean grey everywhere
    (point sampling would alias into stripes or a flat black/white)."""
    tex = Texture.checker(squares=256, size=256, colors=((1, 1, 1), (0, 0, 0)))
    frame = render_unlit(renderer, quad(), Material(color=(1, 1, 1), texture=tex), size=16)
    grey = frame.color[..., 0].astype(int)
    assert np.all(np.abs(grey - 128) <= 3), grey


def test_checker_texture():
    tex = Texture.checker(squares=2, size=4, colors=((1, 1, 1), (0, 0, 0)))
    # The bottom-left square (v = 0) has the first colour; row 0 is the top of the image.
    assert tex.pixels[3, 0, 0] == 255 and tex.pixels[0, 0, 0] == 0 and tex.pixels[0, 3, 0] == 255


def test_colour_modes():
    """Default mode writes the equation's value: a 50% diffuse term is 128. The sRGB mode
    lights in linear space and encodes: the same 50% becomes 188; an sRGB texture value of
    128 decodes to 0.216 and encodes back to 128."""
    scene = Scene(ambient=0.0)
    scene.add(quad(), Material(color=(1, 1, 1), ka=0, kd=1, ks=0))
    scene.add_light(DirectionalLight((0, np.sqrt(3), -1), intensity=1.0))  # N.L = 0.5
    with Renderer(8, 8) as r:
        plain = r.render(scene, CAMERA).color
    with Renderer(8, 8, srgb=True) as r:
        managed = r.render(scene, CAMERA).color
    assert np.all(np.abs(plain[..., :3].astype(int) - 128) <= 1)
    assert managed.dtype == np.uint8  # 8-bit unless float_color, in either mode
    assert np.all(np.abs(managed[..., :3] / 255 - linear_to_srgb(0.5)) <= 1 / 255)
    with Renderer(8, 8, srgb=True, float_color=True) as r:
        exact = r.render(scene, CAMERA).color
    assert exact.dtype == np.float32  # linear light: encoding is for 8-bit output only
    assert np.allclose(exact[..., :3], 0.5, atol=2e-3)
    flat = Texture(np.full((2, 2, 3), 128, np.uint8))
    with Renderer(8, 8, srgb=True) as r:
        scene2 = Scene()
        scene2.add(quad(), Material(color=(1, 1, 1), texture=flat))
        out = r.render(scene2, CAMERA, shading="unlit").color
    assert np.all(np.abs(out[..., :3].astype(int) - 128) <= 1)
    assert srgb_to_linear(128 / 255) == pytest.approx(0.2158, abs=1e-3)


@pytest.mark.parametrize("fmt", ["ply", "obj", "glb"])
def test_vertex_colours_from_files(tmp_path, renderer, fmt):
    box = trimesh.creation.box()
    cols = np.zeros((8, 4), np.uint8)
    cols[:, 3] = 255
    cols[box.vertices[:, 0] > 0, 0] = 255  # +x half red
    cols[box.vertices[:, 0] < 0, 2] = 255  # -x half blue
    box.visual.vertex_colors = cols
    box.export(tmp_path / f"box.{fmt}")
    mesh = Mesh.load(tmp_path / f"box.{fmt}")
    assert mesh.colors is not None
    scene = Scene()
    scene.add(mesh)
    cam = Camera.look_at((0, 0, 3), (0, 0, 0), ortho_height=1.2, near=1, far=5)
    frame = renderer(SIZE, SIZE).render(scene, cam, shading="unlit")
    c = frame.color[SIZE // 2]
    # Default material C = 0.8: the colours interpolate from blue (left) to red (right).
    assert c[12, 2] > 150 and c[12, 0] < 60 and c[-12, 0] > 150 and c[-12, 2] < 60


def test_map_kd_and_base_color_texture(tmp_path, renderer):
    pixels = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]], np.uint8)
    Image.fromarray(pixels).save(tmp_path / "tex.png")
    (tmp_path / "q.mtl").write_text("newmtl m\nKd 1 1 1\nmap_Kd tex.png\n")
    (tmp_path / "q.obj").write_text(
        "mtllib q.mtl\nusemtl m\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    mesh = Mesh.load(tmp_path / "q.obj")
    assert np.array_equal(mesh.material.texture.pixels[..., :3], pixels)
    frame = render_unlit(renderer, mesh, mesh.material)
    # At the texel centres: top-left red, top-right green, bottom-left blue, bottom-right
    # white (pixel 16 is 1/64 of a texel off the centre, hence the small tolerance).
    for (r, c), want in (((16, 16), pixels[0, 0]), ((16, 47), pixels[0, 1]),
                         ((47, 16), pixels[1, 0]), ((47, 47), pixels[1, 1])):
        assert np.abs(frame.color[r, c, :3].astype(int) - want).max() <= 8
    box = trimesh.creation.box()
    box.visual = trimesh.visual.TextureVisuals(
        uv=np.zeros((8, 2)), material=trimesh.visual.material.PBRMaterial(
            baseColorTexture=Image.fromarray(pixels)))
    box.export(tmp_path / "b.glb")
    tex = Mesh.load(tmp_path / "b.glb").material.texture
    assert tex is not None and np.array_equal(tex.pixels[..., :3], pixels)


def test_oversized_texture_is_downscaled_with_a_warning(renderer):
    r = renderer(16, 16)
    limit = int(r.ctx.info["GL_MAX_TEXTURE_SIZE"])
    tex = Texture(np.full((2, limit + 2, 3), 200, np.uint8), "wide")
    scene = Scene()
    scene.add(quad(), Material(color=(1, 1, 1), texture=tex))
    with pytest.warns(UserWarning, match="wide is .* larger than this GL's limit"):
        frame = r.render(scene, CAMERA, shading="unlit")
    assert np.all(np.abs(frame.color[..., 0].astype(int) - 200) <= 1)


def test_texture_errors(tmp_path):
    with pytest.raises(InputError, match="no such texture file"):
        Texture.load(tmp_path / "none.png")
    (tmp_path / "bad.png").write_text("not an image")
    with pytest.raises(InputError, match="cannot read the texture image"):
        Texture.load(tmp_path / "bad.png")
    (tmp_path / "s.toml").write_text('[materials.m]\ntexture = "gone.png"\n')
    with pytest.raises(SceneError, match=r"materials\.m\.texture: .*gone\.png: no such"):
        load_scene(tmp_path / "s.toml")
    (tmp_path / "c.toml").write_text('[materials.m]\ntexture = "checker"\n[[objects]]\n'
                                     'primitive = "plane"\nmaterial = "m"\n')
    assert load_scene(tmp_path / "c.toml").objects[0].material.texture.name == "checker8"


def test_cli_texture_needs_uvs(tmp_path, capsys):
    from facet.cli import main

    trimesh.creation.icosphere().export(tmp_path / "ball.ply")
    code = main(["render", str(tmp_path / "ball.ply"), "--texture", "checker", "-o",
                 str(tmp_path / "o.png")])
    assert code == 2 and "has no texture coordinates" in capsys.readouterr().err


def test_cli_srgb_and_texture(tmp_path):
    """--srgb lights in linear space: the same lit quad comes out brighter in the mid-tones;
    --texture checker maps a checkerboard onto a model with texture coordinates."""
    from facet.cli import main

    (tmp_path / "q.obj").write_text(
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    common = [str(tmp_path / "q.obj"), "--size", "32x32", "--eye", "0,0,3", "--light",
              "dir:0,0,-1:1,1,1:0.5", "--msaa", "0", "-q"]
    assert main(["render", *common, "-o", str(tmp_path / "a.png")]) == 0
    assert main(["render", *common, "--srgb", "-o", str(tmp_path / "b.png")]) == 0
    a = np.asarray(Image.open(tmp_path / "a.png"))[16, 16, 0]
    b = np.asarray(Image.open(tmp_path / "b.png"))[16, 16, 0]
    assert b > a + 20
    assert main(["render", *common, "--texture", "checker", "--shading", "unlit", "-o",
                 str(tmp_path / "c.png")]) == 0
    c = np.asarray(Image.open(tmp_path / "c.png"))[..., 0]
    assert len(np.unique(c)) >= 2 and c.max() - c.min() > 80

"""Environment maps: the sky as background and in a mirror, refraction with Fresnel, and the
cube-map inputs."""

import numpy as np
import pytest
from PIL import Image

from facet.errors import InputError
from facet.geometry.camera import Camera
from facet.scene import Material, Scene
from facet.scene.environment import Environment, face_directions, sky_color

from conftest import sphere_mesh
from reference import erode, pixel_rays

S = 96
CAMERA = Camera.look_at((0.0, 0.6, 4.0), (0, 0, 0), ortho_height=2.6, near=1, far=10)


def test_face_directions_follow_opengl():
    d = face_directions(4)
    assert np.allclose(np.linalg.norm(d, axis=-1), 1)
    # Each face looks along its axis at its centre, and the faces' major axes are right.
    major = np.argmax(np.abs(d.reshape(6, -1, 3)), axis=2)
    assert [int(np.bincount(m).argmax()) for m in major] == [0, 0, 1, 1, 2, 2]
    signs = [np.sign(d[i, 1, 1, i // 2]) for i in range(6)]
    assert signs == [1, -1, 1, -1, 1, -1]


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_background_and_mirror_reflect_the_sky(renderer, engine):
    """Background pixels show the sky along their view ray; a mirror sphere shows it along
    R = 2 (N.V) N - V (within the cube map's filtering): by environment lookups when
    rasterized, by reflection rays escaping to the sky when traced."""
    env = Environment.sky(size=128)
    scene = Scene(ambient=0.0)
    scene.environment = env
    scene.add(sphere_mesh(5), Material(color=(0, 0, 0), ka=0, kd=0, ks=0, reflectivity=1.0))
    frame = renderer(S, S).render(scene, CAMERA, outputs=("color", "ids", "normals"),
                                  engine=engine)
    img = frame.color[..., :3] / 255.0
    _, dirs = pixel_rays(CAMERA.view, CAMERA.projection(S, S), S, S)
    bg = frame.object_ids == -1
    assert np.abs(img - sky_color(dirs, *Environment.SKY))[bg].max() <= 6 / 255
    mirror = erode(frame.object_ids == 0, 2)
    n = frame.normals
    v = -dirs
    r = 2 * np.sum(n * v, axis=-1, keepdims=True) * n - v
    expected = sky_color(r, *Environment.SKY)
    err = np.abs(img - expected)[mirror]
    assert np.median(err) <= 3 / 255 and np.percentile(err, 95) <= 12 / 255
    assert img[mirror][:, 2].std() > 0.05  # the horizon and sky colours both show


def test_refraction_uses_the_fresnel_weight(renderer):
    """Glass (ior 1.5) looks different from a mirror and is more reflective at grazing
    angles (Schlick): its rim is closer to the mirror's colour than its centre."""
    env = Environment.sky(size=64)
    r = renderer(S, S)
    out = {}
    for name, ior in (("mirror", 0.0), ("glass", 1.5)):
        scene = Scene(ambient=0.0)
        scene.environment = env
        scene.add(sphere_mesh(5), Material(color=(0, 0, 0), ka=0, kd=0, ks=0,
                                           reflectivity=1.0, ior=ior))
        out[name] = r.render(scene, CAMERA, outputs=("color", "ids"))
    mask = erode(out["mirror"].object_ids == 0, 2)
    diff = np.abs(out["glass"].color[..., :3].astype(int) - out["mirror"].color[..., :3])
    yy, xx = np.mgrid[0:S, 0:S]
    radius = np.hypot(xx - S / 2, yy - S * 0.55)
    rim = mask & (radius > np.percentile(radius[mask], 90))
    centre = mask & (radius < np.percentile(radius[mask], 20))
    assert diff[centre].mean() > 10
    assert diff[rim].mean() < diff[centre].mean()


def test_cube_map_inputs(tmp_path):
    for i, name in enumerate(("px", "nx", "py", "ny", "pz", "nz")):
        Image.fromarray(np.full((8, 8, 3), 40 * i, np.uint8)).save(tmp_path / f"{name}.png")
    paths = [tmp_path / f"{n}.png" for n in ("px", "nx", "py", "ny", "pz", "nz")]
    env = Environment.from_faces(paths)
    assert env.faces.shape == (6, 8, 8, 3) and env.faces[5, 0, 0, 0] == pytest.approx(200 / 255)
    Image.fromarray(np.zeros((4, 8, 3), np.uint8)).save(tmp_path / "nz.png")
    with pytest.raises(InputError, match="square and all the same size: .*nz.png 8x4"):
        Environment.from_faces(paths)
    with pytest.raises(InputError, match="6 face images"):
        Environment.from_faces(paths[:5])
    equirect = np.zeros((32, 64, 3), np.uint8)
    equirect[:16] = (50, 100, 200)  # upper half: sky
    Image.fromarray(equirect).save(tmp_path / "pano.png")
    env = Environment.from_equirect(tmp_path / "pano.png", size=16)
    assert np.allclose(env.faces[2].mean(axis=(0, 1)), np.array([50, 100, 200]) / 255)  # +Y
    assert np.allclose(env.faces[3], 0)  # -Y: the dark lower half
    with pytest.raises(InputError, match="reflectivity must be in"):
        Material(reflectivity=2)
    with pytest.raises(InputError, match="ior must be"):
        Material(ior=0.5)


def test_cli_and_scene_file_environment(tmp_path, capsys):
    from facet.cli import main
    from facet.errors import SceneError
    from facet.formats import load_scene

    out = tmp_path / "e.png"
    assert main(["render", "--env", "sky", "--size", "32x24", "-q", "-o", str(out)]) == 0
    img = np.asarray(Image.open(out))
    assert img[0, 0, 2] > 150  # sky, not the black default background
    assert main(["render", "--env", str(tmp_path / "none.png"), "-o",
                 str(tmp_path / "x.png")]) == 2
    assert "no such texture file" in capsys.readouterr().err
    scene = tmp_path / "s.toml"
    scene.write_text('environment = "sky"\n[materials.chrome]\nreflectivity = 1\nior = 1.5\n'
                     '[[objects]]\nprimitive = "sphere"\nmaterial = "chrome"\n')
    loaded = load_scene(scene)
    assert loaded.environment is not None and loaded.objects[0].material.ior == 1.5
    scene.write_text('environment = "missing-folder-or-file"\n')
    with pytest.raises(SceneError, match="environment: .*no such texture file"):
        load_scene(scene)


def test_glossy_reflection_blurs_the_environment(renderer):
    """gloss > 0 spreads the reflected sky: the sharp horizon in a mirror sphere turns into a
    gradual transition (smaller steepest step down the sphere's middle column)."""
    env = Environment.sky(size=128)
    r = renderer(S, S)
    steep = {}
    for gloss in (0.0, 0.5):
        scene = Scene(ambient=0.0)
        scene.environment = env
        scene.add(sphere_mesh(5), Material(color=(0, 0, 0), ka=0, kd=0, ks=0,
                                           reflectivity=1.0, gloss=gloss))
        frame = r.render(scene, CAMERA, aa="ssaa:jittered:64", outputs=("color", "ids"))
        column = frame.color[:, S // 2, 2].astype(float)
        inside = erode(frame.object_ids == 0, 3)[:, S // 2]
        steep[gloss] = np.abs(np.diff(column))[inside[1:] & inside[:-1]].max()
    assert steep[0.5] < 0.6 * steep[0.0], steep
    with pytest.raises(InputError, match="gloss must be in"):
        Material(gloss=1.5)


def test_an_unchanged_sky_file_is_read_once(tmp_path):
    """A series of renders under one HDR sky reads and resamples the file once (a 2K sky
    took 0.13 s a render, and the path tracer's light textures made from it were made
    again each time); a changed file is read again; the shared arrays are read-only."""
    import os

    from facet.formats.environment_files import load_environment
    from facet.formats.hdr_image import write_hdr

    path = tmp_path / "sky.hdr"
    write_hdr(path, np.full((16, 32, 3), 0.5, np.float32))
    first = load_environment(path.name, tmp_path)
    assert load_environment(str(path)) is first
    with pytest.raises(ValueError):
        first.faces[0, 0, 0] = 1.0
    write_hdr(path, np.full((16, 32, 3), 2.0, np.float32))
    os.utime(path, ns=(1, 1))  # (a new modification time even on a coarse clock)
    again = load_environment(str(path))
    assert again is not first and again.equirect.mean() == pytest.approx(2.0)


def test_an_environment_of_one_colour_knows_it(tmp_path):
    """Environment.uniform_color: the one radiance of a constant environment, or of images
    of one colour; None as soon as one texel differs."""
    np.testing.assert_array_equal(Environment.constant((0.2, 0.4, 0.8)).uniform_color,
                                  np.float32([0.2, 0.4, 0.8]))
    assert Environment.sky().uniform_color is None
    faces = np.full((6, 4, 4, 3), 0.5, np.float32)
    grid = np.full((8, 16, 3), 0.5, np.float32)
    assert Environment(faces, equirect=grid).uniform_color is not None
    faces[3, 2, 1, 0] = 0.6  # (one texel of one face)
    assert Environment(faces, equirect=grid).uniform_color is None
    faces[3, 2, 1, 0] = 0.5
    grid[7, 15, 2] = 0.0  # (the grid the path tracer samples)
    assert Environment(faces, equirect=grid).uniform_color is None

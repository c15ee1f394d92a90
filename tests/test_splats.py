"""3D Gaussian splats (facet.Splats, the rasterizer's splat pass) against a numpy
transcription of the reference forward pass (tests/splat_reference.py): random anisotropic,
overlapping splats with view-dependent colour (SH degrees 0-3) at PSNR >= 40 dB on 8-bit
pictures; the file's splat order changes nothing; one isotropic splat's footprint is the
analytic Gaussian; splats and meshes hide each other (colour, depth, ids); the files (3DGS
PLY of every SH degree, .splat) read back what was written, and bad ones are one line;
the tracers say they leave splats out; ``facet render`` and ``facet info`` take a PLY."""

import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

import facet
import splat_reference as ref
from facet.errors import FacetWarning, InputError, MeshError

W, H = 96, 72
BG = (0.1, 0.2, 0.3)


def _cloud(n=300, degree=3, seed=1, spread=0.6):
    rng = np.random.default_rng(seed)
    sh = rng.normal(0, 0.4, (n, (degree + 1) ** 2, 3))
    sh[:, 0] = rng.normal(0, 1.2, (n, 3))
    return facet.Splats(rng.normal(0, spread, (n, 3)), np.exp(rng.normal(-2.6, 0.5, (n, 3))),
                        rng.normal(0, 1, (n, 4)), rng.uniform(0.3, 0.95, n), sh)


def _camera(eye=(0.5, 0.8, 3.2), fov=45):
    return facet.Camera.look_at(eye, (0, 0, 0), fov_y=fov, near=0.1, far=50)


def _facet(scene, camera, **kw):
    with facet.Renderer(W, H) as r:
        return r.render(scene, camera, aa="none", background=BG, **kw)


def _oracle(s: facet.Splats, camera, transform=None):
    means, cov_scale, rot = s.means.astype(np.float64), s.scales, s.rotations
    d = camera.describe(W, H)
    if transform is not None:  # (the oracle takes the cloud's world splats)
        a = transform[:3, :3]
        means = means @ a.T + transform[:3, 3]
        return ref.render_covariances(means, s.covariances(a), s.opacities, s.sh,
                                      d["world_to_camera"], d["K"], W, H, BG, near=0.1,
                                      to_local=np.linalg.inv(a))
    return ref.render(means, cov_scale, rot, s.opacities, s.sh, d["world_to_camera"], d["K"],
                      W, H, background=BG, near=0.1)


def _psnr(img8, oracle) -> float:
    o8 = np.clip(np.round(oracle * 255), 0, 255)
    mse = ((img8[..., :3].astype(np.float64) - o8) ** 2).mean()
    return float(10 * np.log10(255.0 ** 2 / max(mse, 1e-12)))


def _scene(*clouds, transform=None):
    scene = facet.Scene()
    for c in clouds:
        scene.add(c, transform=transform)
    return scene


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_the_forward_pass_is_the_references(degree):
    s = _cloud(degree=degree, seed=degree)
    cam = _camera()
    img = _facet(_scene(s), cam).color
    assert _psnr(img, _oracle(s, cam)) >= 40.0


def test_splats_beyond_the_view_are_clamped_as_the_reference_does():
    """A wide cloud seen close: many means lie outside the field of view, where the
    reference takes the Jacobian at 1.3 times the half field of view."""
    s = _cloud(n=400, spread=2.5, seed=7)
    cam = _camera(eye=(0.3, 0.2, 1.5), fov=35)
    assert _psnr(_facet(_scene(s), cam).color, _oracle(s, cam)) >= 40.0


def test_a_placed_cloud_is_the_cloud_of_its_world_splats():
    """A rotated, scaled and moved cloud: its covariances carried (A Sigma A^T) and its
    colours looked up in its own frame."""
    s = _cloud(n=200, degree=2, seed=3)
    m = facet.transforms.translate((0.2, -0.1, 0.3)) @ facet.transforms.rotate_y(40.0) @ \
        np.diag([1.3, 0.8, 1.1, 1.0])
    cam = _camera()
    img = _facet(_scene(s, transform=m), cam).color
    assert _psnr(img, _oracle(s, cam, transform=m)) >= 40.0


def test_the_files_splat_order_changes_nothing():
    s = _cloud(seed=5)
    shuffled = s.subset(np.random.default_rng(0).permutation(s.count))
    cam = _camera()
    a, b = _facet(_scene(s), cam).color, _facet(_scene(shuffled), cam).color
    assert np.array_equal(a, b)


def test_one_isotropic_splat_is_the_analytic_gaussian():
    """A splat of scale s at distance z straight ahead: alpha(r) = a exp(-r^2 / 2 var),
    var = (f s / z)^2 + 0.3 pixels^2, cut below 1/255 and beyond its 3-sigma box; white
    over black, so the picture is alpha."""
    scale, z, opacity = 0.05, 3.0, 0.7
    s = facet.Splats.from_colors([[0, 0, 0]], [[scale] * 3], [[1, 0, 0, 0]], [opacity],
                                 [[1.0, 1.0, 1.0]])
    cam = facet.Camera.look_at((0, 0, z), (0, 0, 0), fov_y=40, near=0.1, far=50)
    with facet.Renderer(W, H) as r:
        img = r.render(_scene(s), cam, aa="none", background=(0, 0, 0)).color[..., 0] / 255
    f = H / 2 / np.tan(np.radians(20))
    var = (f * scale / z) ** 2 + 0.3
    radius = np.ceil(3 * np.sqrt(var))
    x, y = np.meshgrid(np.arange(W) + 0.5 - W / 2, np.arange(H) + 0.5 - H / 2)
    alpha = np.minimum(0.99, opacity * np.exp(-(x * x + y * y) / (2 * var)))
    alpha[(alpha < 1 / 255) | (np.abs(x) > radius) | (np.abs(y) > radius)] = 0
    assert np.abs(img - alpha).max() <= 1.0 / 255 + 1e-6
    assert img.max() > 0.6  # (a splat, not an empty picture)


@pytest.mark.parametrize("aa", ["none", "msaa:4"])
def test_a_splat_and_a_mesh_hide_each_other(aa):
    """A red square between two splats: the near splat shows over it (colour, depth, id),
    the far one is hidden behind it and shows beside it; with MSAA (the default) too,
    where the exact channels come from a pass of their own."""
    near = facet.Splats.from_colors([[0.0, 0.0, 0.8]], [[0.12] * 3], [[1, 0, 0, 0]], [0.99],
                                    [[0.0, 1.0, 0.0]])
    far = facet.Splats.from_colors([[0.55, 0.0, -0.8]], [[0.12] * 3], [[1, 0, 0, 0]], [0.99],
                                   [[0.0, 0.0, 1.0]])
    scene = facet.Scene(ambient=1.0)
    plane = scene.add(facet.primitives.plane(1.2), facet.Material(color=(1, 0, 0), ka=1,
                                                                  kd=0, ks=0),
                      facet.transforms.rotate_x(90.0))
    id_near, id_far = scene.add(near), scene.add(far)
    assert (plane, id_near, id_far) == (0, 1, 2)
    cam = facet.Camera.look_at((0, 0, 3), (0, 0, 0), fov_y=45, near=0.1, far=50)
    with facet.Renderer(W, H) as r, pytest.warns(FacetWarning, match="ids of 2 splat clouds"):
        frame = r.render(scene, cam, aa=aa, background=(0, 0, 0), lights="scene",
                         outputs=("color", "depth", "ids"))
    k = np.array(cam.describe(W, H)["K"])
    v = int(round(k[1, 2]))

    def column(x, depth):  # the pixel column of world x at this depth from the camera
        return int(round(k[0, 0] * x / depth + k[0, 2]))

    c = column(0.0, 2.2)
    assert frame.color[v, c, 1] > 200 and frame.color[v, c, 0] < 10  # green over red
    assert frame.object_ids[v, c] == id_near
    assert frame.depth[v, c] == pytest.approx(2.2, abs=0.02)
    c = column(0.55, 3.8)  # the far splat's centre, behind the square: the square shows
    assert frame.color[v, c, 0] > 200 and frame.color[v, c, 2] < 10
    assert frame.object_ids[v, c] == plane
    assert frame.depth[v, c] == pytest.approx(3.0, abs=0.01)
    c = column(0.64, 3.0) + 1  # just beside the square: the far splat's edge, over black
    assert frame.color[v, c, 2] > 5 and frame.color[v, c, 0] < 5


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_a_ply_reads_back_what_was_written(tmp_path, degree):
    s = _cloud(n=50, degree=degree, seed=11)
    back = facet.Splats.load(s.save(tmp_path / "c.ply"))
    assert back.degree == degree and back.count == 50
    for name in ("means", "scales", "rotations", "opacities", "sh"):
        assert np.allclose(getattr(back, name), getattr(s, name), rtol=1e-5, atol=1e-6), name


def test_a_splat_file_of_the_web_viewers(tmp_path):
    rows = b"".join(struct.pack("<3f3f4B4B", x, 0.5, -1.0, 0.1, 0.2, 0.3, 255, 128, 0, 191,
                                255, 128, 128, 128) for x in (0.0, 1.0))
    (tmp_path / "c.splat").write_bytes(rows)
    s = facet.Splats.load(tmp_path / "c.splat")
    assert s.count == 2 and s.degree == 0
    assert np.allclose(s.means[1], [1.0, 0.5, -1.0]) and np.allclose(s.scales[0], [0.1, 0.2, 0.3])
    assert np.allclose(s.opacities, 191 / 255) and np.allclose(s.rotations[0], [1, 0, 0, 0])
    assert np.allclose(facet.Splats.colors(s, np.tile([0, 0, 1.0], (2, 1)))[0],
                       [1.0, 128 / 255, 0.0], atol=1e-6)
    scene = facet.load(tmp_path / "c.splat")
    assert len(scene.splats) == 1 and not scene.objects


def _ply(tmp_path, **change):
    s = _cloud(n=4, degree=1, seed=2)
    path = s.save(tmp_path / "c.ply")
    data = bytearray(path.read_bytes())
    end = data.index(b"end_header\n") + len(b"end_header\n")
    body = np.frombuffer(bytes(data[end:]), "<f4").reshape(4, -1).copy()
    for column, value in change.items():
        body[1, int(column[1:])] = value
    path.write_bytes(bytes(data[:end]) + body.tobytes())
    return path


@pytest.mark.parametrize("change, said", [
    ({"c0": np.nan}, "not finite"),
    ({f"c{6 + 3 + 9 + 1 + 3 + k}": 0.0 for k in range(4)}, "quaternion is zero"),
    ({"c19": 200.0}, "scale"),
])
def test_a_bad_splat_file_is_one_line(tmp_path, change, said):
    with pytest.raises(MeshError, match=said) as err:
        facet.Splats.load(_ply(tmp_path, **change))
    assert str(tmp_path / "c.ply") in str(err.value) and "\n" not in str(err.value)


def test_a_truncated_or_foreign_ply_is_one_line(tmp_path):
    path = _ply(tmp_path)
    path.write_bytes(path.read_bytes()[:-10])
    with pytest.raises(MeshError, match="truncated"):
        facet.Splats.load(path)
    (tmp_path / "m.ply").write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                    "property float y\nproperty float z\nproperty float "
                                    "opacity\nend_header\n0 0 0 1\n")
    with pytest.raises(MeshError, match="lack f_dc_0"):
        facet.Splats.load(tmp_path / "m.ply")
    with pytest.raises(InputError, match="opacity"):
        facet.Splats([[0, 0, 0]], [[1, 1, 1]], [[1, 0, 0, 0]], [1.5], [[[0, 0, 0]]])


def test_channels_splats_cannot_give_are_said():
    with pytest.warns(FacetWarning, match="Gaussian splats have no normals, uv"):
        _facet(_scene(_cloud(n=20)), _camera(), outputs=("color", "normals", "uv"))


@pytest.mark.parametrize("engine", ["trace", "path"])
def test_the_tracers_say_they_leave_splats_out(engine):
    scene = _scene(_cloud(n=20))
    scene.add(facet.primitives.cube(0.3))
    with warnings.catch_warnings(record=True) as caught, facet.Renderer(16, 16) as r:
        warnings.simplefilter("always")
        r.render(scene, _camera(), engine=engine, outputs=("color",), spp=1)
    lines = [str(w.message) for w in caught if issubclass(w.category, FacetWarning)]
    assert sum("leaves out the Gaussian splats (1 cloud, 20 splats)" in x for x in lines) == 1


def test_render_and_info_take_a_3dgs_ply(tmp_path):
    path = _cloud(n=100, degree=3).save(tmp_path / "scene.ply")
    out = tmp_path / "out.png"
    cmd = [sys.executable, "-m", "facet"]
    done = subprocess.run([*cmd, "render", str(path), "-o", str(out), "--size", "64x48"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and not done.stderr, done.stderr
    from PIL import Image

    assert np.asarray(Image.open(out)).std() > 5
    info = subprocess.run([*cmd, "info", str(path)], capture_output=True, text=True,
                          timeout=120)
    assert "100 (SH degree 3)" in info.stdout
    # A mesh's colour flag would be ignored without a word: refused in one line.
    colored = subprocess.run([*cmd, "render", str(path), "-o", str(tmp_path / "c.png"),
                              "--color", "1,0,0"], capture_output=True, text=True, timeout=120)
    assert colored.returncode == 2 and "carry their own colours" in colored.stderr
    assert len(colored.stderr.strip().splitlines()) == 1 and not (tmp_path / "c.png").exists()
    wire = subprocess.run([*cmd, "render", str(path), "-o", str(tmp_path / "w.png"),
                           "--wireframe"], capture_output=True, text=True, timeout=120)
    assert wire.returncode == 0 and "Gaussian splats have none" in wire.stderr


def test_the_viewers_session_orbits_a_splat_scene(tmp_path):
    """The window, the notebook widget and the served page share this session: a drag
    turns the splats, the status line counts them, and the still picture is the headless
    render of the session's camera."""
    from facet.viewing.session import Session

    path = _cloud(n=200, degree=2).save(tmp_path / "cloud.ply")
    with Session(path, size=(W, H)) as s:
        before = s.frame().copy()
        assert "200 splats" in s.status()
        for kind, x in (("pointer_down", 20), ("pointer_move", 50), ("pointer_up", 50)):
            s.handle({"type": kind, "x": x, "y": 30, "button": 1})
        after = s.frame()
        while s.refining:
            after = s.frame()
        assert np.abs(after.astype(int) - before).mean() > 1
        ref_frame = s.renderer.render(s.shown_scene(), s.camera(),
                                      s.options(outputs=("color",))).color[..., :3]
        assert np.abs(after.astype(int) - ref_frame).max() <= 1


def test_a_scene_file_places_a_splat_file_and_refuses_a_material(tmp_path):
    s = _cloud(n=60, degree=1)
    s.save(tmp_path / "cloud.ply")
    (tmp_path / "s.toml").write_text(
        '[[objects]]\nmesh = "cloud.ply"\ntransform = [{translate = [0.5, 0, 0]}]\n\n'
        '[[objects]]\nprimitive = "cube"\nsize = 0.5\n')
    scene = facet.load(tmp_path / "s.toml")
    assert len(scene.splats) == 1 and len(scene.objects) == 1
    assert np.allclose(scene.splats[0].transform[:3, 3], [0.5, 0, 0])
    (tmp_path / "bad.toml").write_text('[[objects]]\nmesh = "cloud.ply"\n'
                                       'material = {color = [1, 0, 0]}\n')
    with pytest.raises(facet.SceneError, match="give no material"):
        facet.load(tmp_path / "bad.toml")


def test_an_ascii_ply_reads_as_the_binary_one(tmp_path):
    s = _cloud(n=5, degree=1, seed=4)
    binary = s.save(tmp_path / "b.ply")
    data = binary.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().replace("binary_little_endian", "ascii")
    rows = np.frombuffer(data[end:], "<f4").reshape(5, -1)
    text = header + "\n".join(" ".join(f"{v:.9g}" for v in row) for row in rows) + "\n"
    (tmp_path / "a.ply").write_text(text)
    a, b = facet.Splats.load(tmp_path / "a.ply"), facet.Splats.load(binary)
    assert np.allclose(a.sh, b.sh) and np.allclose(a.means, b.means)
    assert np.allclose(a.scales, b.scales, rtol=1e-6)


def test_the_served_page_orbits_a_splat_scene(tmp_path):
    """``facet view cloud.ply --serve`` in headless Chromium: a drag turns the splats and
    the still picture is the headless render of the page's camera."""
    pytest.importorskip("websockets", reason="the serve extra (websockets) is not installed")
    import json

    from selenium.webdriver import ActionChains

    from facet.viewing.session import Session
    from test_serve import Served, _settled

    from browser import camera_from, canvas_pixels, chromium, quit_chromium, wait_for

    path = _cloud(n=3000, degree=3, spread=0.4).save(tmp_path / "cloud.ply")
    driver = chromium()
    try:
        with Served(model=str(path), cwd=tmp_path) as served:
            driver.get(served.url)
            canvas = driver.find_element("id", "canvas")
            first = _settled(driver, canvas, 0)
            before = json.loads(canvas.get_attribute("data-camera"))
            ActionChains(driver).move_to_element_with_offset(canvas, -40, 0).click_and_hold() \
                .move_by_offset(40, 10).release().perform()
            _settled(driver, canvas, first)

            def turned():
                if canvas.get_attribute("data-lossless") != "1":
                    return None
                cam = json.loads(canvas.get_attribute("data-camera"))
                changed = cam["world_to_camera_opengl"] != before["world_to_camera_opengl"]
                return (canvas_pixels(driver, canvas), cam) if changed else None
            shown, camera = wait_for(turned, "the turned, still picture")
    finally:
        quit_chromium(driver)
    with Session(path) as s:
        s.resize(shown.shape[1], shown.shape[0])
        ref_img = s.renderer.render(s.shown_scene(), camera_from(camera),
                                    s.options(outputs=("color",))).color[..., :3]
    assert shown.std() > 5 and np.abs(shown.astype(int) - ref_img).max() <= 2

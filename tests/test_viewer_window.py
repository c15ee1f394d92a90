"""The viewer in a real window under Xvfb, driven with xdotool, seen with xwd.

The suite starts its own Xvfb; without the Debian packages xvfb, xdotool and x11-apps (CI
installs them) these tests skip with a reason.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from PIL import Image

from window_tools import ROOT, H, W, Window, files, start_display, until


@pytest.fixture(scope="module")
def display():
    name, proc = start_display()
    yield name
    proc.terminate()
    proc.wait(timeout=10)


@pytest.fixture
def window(display, tmp_path):
    opened = []

    def open_(*args, command="view"):
        w = Window(display, list(args), tmp_path, command)
        opened.append(w)
        return w

    yield open_
    for w in opened:
        w.kill()


def test_drag_scroll_keys_and_quit(window):
    w = window()
    before = w.screen()
    assert before.std() > 10  # the bundled model is drawn
    w.xdotool("mousemove", "160", "120", "mousedown", "1", "mousemove", "200", "130",
              "mousemove", "240", "140", "mouseup", "1")
    dragged = w.screen(changed_from=before)
    assert w.proc.poll() is None, w.proc.stderr.read()
    assert np.abs(dragged - before).mean() > 3
    w.xdotool("click", "4", "click", "4", "click", "4")
    zoomed = w.screen(changed_from=dragged)
    assert np.abs(zoomed - dragged).mean() > 3
    assert (zoomed.sum(axis=2) > 0).mean() > (dragged.sum(axis=2) > 0).mean()  # bigger
    assert "facet - default.obj - 9,600 triangles" in w.title()
    w.key("b")
    assert np.abs(w.screen(changed_from=zoomed) - zoomed).mean() > 3  # background changed
    assert w.quit() == 0


def _shot_and_headless(path, msaa=0, **render_kwargs):
    """A viewer screenshot of the bundled model, and a headless render through the camera
    its JSON records (same lights: the rig follows the camera)."""
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer
    from facet.scene import Mesh, Scene
    from facet.scene.light import camera_rig

    shot = np.asarray(Image.open(path))
    info = json.loads(path.with_suffix(".json").read_text())
    assert shot.shape == (H, W, 3) and (info["width"], info["height"]) == (W, H)
    camera = Camera(info["world_to_camera_opengl"], fov_y=info["fov_y"], near=info["near"],
                    far=info["far"])
    scene = Scene()
    scene.add(Mesh.load(ROOT / "models" / "default.obj"))
    for light in camera_rig(camera.view):
        scene.add_light(light)
    with Renderer(W, H, msaa=msaa) as r:
        return shot, r.render(scene, camera, **render_kwargs).color[..., :3]


def test_screenshot_matches_the_headless_render(window, tmp_path):
    """`s` saves the window's picture and its camera into the --screenshots folder (nothing
    in the working one); a headless render through that camera gives the same image (edge
    pixels may differ by rasterisation order)."""
    folder = tmp_path / "shots"
    folder.mkdir()
    w = window("--screenshots", str(folder))
    w.key("s")
    shots = files(folder, "facet-*.png")
    assert w.quit() == 0
    assert not list(tmp_path.glob("facet-*"))
    shot, ref = _shot_and_headless(shots[0], msaa=4)
    from test_golden import CHANNEL_TOL, MAX_DIFFERING  # the one tolerance table

    diff = np.abs(shot.astype(int) - ref).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()
    assert np.median(diff) <= 1


def test_reload_on_change_and_errors_survive(window, tmp_path):
    path = tmp_path / "model.ply"
    trimesh.creation.box().export(path)
    w = window(str(path))
    box = w.screen()
    trimesh.creation.icosphere(subdivisions=3, radius=0.6).export(path)
    ball = w.screen(changed_from=box)
    assert np.abs(ball - box).mean() > 2  # new geometry, same camera
    path.write_bytes(b"ply\nformat garbage\n")
    w.wait_title(lambda t: "error" in t)
    assert w.proc.poll() is None  # shown, survived
    assert np.abs(w.screen() - ball).mean() < 1  # still the last good picture
    assert w.quit() == 0
    assert "cannot read the file" in w.proc.stderr.read()


def test_idle_viewer_uses_almost_no_cpu(window):
    w = window()
    w.screen()  # drawn and settled
    share = w.cpu_share()
    assert share < 0.05, f"idle viewer used {share:.1%} of a core"
    assert w.quit() == 0


def test_no_display_is_one_line_and_exit_2(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["PYTHONPATH"] = str(ROOT / "app")
    res = subprocess.run([sys.executable, "-m", "facet", "view"], env=env, capture_output=True,
                         text=True, cwd=tmp_path)
    assert res.returncode == 2
    assert res.stderr.strip().splitlines() == [
        "facet: error: no display to open a window on (DISPLAY is not set); use 'facet "
        "render' for headless images"]


def test_more_keys_help_2x_screenshot_turntable_cameras(window, tmp_path):
    scene = tmp_path / "two.toml"
    scene.write_text('[[objects]]\nprimitive = "cube"\n[cameras.front]\ntype = "perspective"\n'
                     'eye = [0, 0, 4]\n[cameras.side]\ntype = "orthographic"\n'
                     'eye = [4, 1, 0]\nheight = 3\n')
    w = window(str(scene))
    front = w.screen()
    w.key("2")
    side = w.screen(changed_from=front)
    assert np.abs(side - front).mean() > 2  # the second named camera
    w.key("1")
    assert np.abs(w.screen(changed_from=side) - front).mean() < 1
    w.key("shift+s")
    big = files(tmp_path, "facet-*-2x.png")
    assert big and np.asarray(Image.open(big[0])).shape == (2 * H, 2 * W, 3)
    w.key("t")
    gif = files(tmp_path, "facet-turntable-*.gif", timeout=60)
    w.key("h")
    for key in ("w", "m", "o", "a", "l"):  # every toggle redraws without failing
        w.key(key)
        assert w.screen().std() > 1
    assert w.quit() == 0
    out = w.proc.stdout.read()
    assert "facet view keys:" in out and "wireframe overlay" in out
    import imageio.v3 as iio

    frames = iio.imread(gif[0], index=None)
    assert frames.shape == (36, H, W, 3)


def test_resize_redraws_at_the_new_size(window):
    w = window()
    w.xdotool("windowsize", "--sync", w.id, "400", "300")
    w.size = (400, 300)

    def middle(img):
        cols = np.nonzero((img.sum(axis=2) > 0).any(axis=0))[0]
        return (cols.min() + cols.max()) / 2 if cols.size else 0.0

    # The model is drawn about the middle of the larger window (x = 200), not about the old
    # middle (x = 160): the viewport and projection follow the new size.
    img = w.screen(until_=lambda img: abs(middle(img) - 200) < 15)
    assert img.std() > 10 and w.quit() == 0


def test_python_viewer_api(display, tmp_path, capsys):
    """Scripting: a Viewer with a camera set from Python saves what it shows, and returns
    the path without printing it (a library call writes nothing to stdout)."""
    os.environ["DISPLAY"] = display
    import facet
    from facet.geometry.camera import Camera

    scene = facet.Scene()
    scene.add(facet.primitives.sphere(1.0))
    from facet.errors import FacetWarning

    with facet.Viewer(scene, size=(W, H), msaa=8) as v:  # the MSAA policy holds here too
        if v.ctx.max_samples < 8:
            with pytest.warns(FacetWarning, match="msaa:8 is more than .* using msaa:"):
                v.draw()
    with facet.Viewer(scene, size=(W, H), msaa=0) as v:
        v.set_camera(Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=30))
        capsys.readouterr()
        path = v.save(tmp_path / "shot.png")
        assert capsys.readouterr().out == ""
        image = np.asarray(Image.open(path))
        # A file dropped on the window opens framed; a bad one is reported and survived.
        trimesh.creation.box(extents=(4, 1, 1)).export(tmp_path / "long.stl")
        v._on_drop(v.window, [str(tmp_path / "long.stl")])
        assert v.path.name == "long.stl" and v.triangles == 12 and v.error == ""
        v._on_drop(v.window, [str(tmp_path / "missing.obj")])
        assert "no such file" in v.error and v.path.name == "long.stl"
        v.draw()
        assert (v.grab().sum(axis=2) > 0).mean() > 0.05
    assert image.shape == (H, W, 3)
    hit = image.sum(axis=2) > 0
    rows, cols = np.nonzero(hit)
    assert abs(rows.mean() - H / 2) < 2 and abs(cols.mean() - W / 2) < 2  # centred sphere
    assert json.loads(path.with_suffix(".json").read_text())["fov_y"] == pytest.approx(30)


def test_shader_window_survives_a_broken_save(window, tmp_path):
    """`facet shader FILE` in a window: a broken save keeps the last picture inside a red
    frame with the error in the title; the fix brings the clean picture back."""
    shader = tmp_path / "live.frag"
    good = ("void mainImage(out vec4 c, in vec2 p) { c = vec4(p / iResolution.xy, 0.0, 1.0);"
            " }\n")
    shader.write_text(good)
    w = window(str(shader), "--size", f"{W}x{H}", command="shader")
    clean = w.screen(until_=lambda img: img[H // 2, W // 2, 0] > 100)
    assert clean[2, 2, 0] < 20  # the uv gradient
    shader.write_text(good.replace("p / iResolution.xy", "q / iResolution.xy"))
    w.wait_title(lambda t: "error: " in t and "live.frag:1:" in t)
    red = lambda img: (img[..., 0] > 180) & (img[..., 1] < 60) & (img[..., 2] < 60)  # noqa: E731
    broken = w.screen(until_=lambda img: red(img)[:4].all())
    assert red(broken)[:, :4].all()  # the red frame
    assert np.abs(broken[H // 2, W // 2] - clean[H // 2, W // 2]).max() <= 2  # last good
    shader.write_text(good)
    w.wait_title(lambda t: "error" not in t)
    fixed = w.screen(until_=lambda img: not red(img)[:4].all())
    assert np.abs(fixed - clean).max() <= 2
    assert w.quit() == 0
    assert "live.frag:1:" in w.proc.stderr.read()


def test_viewer_mesh_shader_hot_reload(window, tmp_path):
    """`facet view MODEL --frag FILE`: saving a broken shader keeps the last picture in a red
    frame with the error in the title; the fix brings the new picture."""
    frag = tmp_path / "mine.frag"
    body = ("#version 330 core\nout vec4 c;\nvoid main() {{ c = vec4({}, 1.0); }}\n")
    frag.write_text(body.format("0.0, 1.0, 0.0"))
    w = window("--frag", str(frag), "--msaa", "0")
    green = w.screen()
    assert green[..., 1].max() == 255 and green[..., 0].max() == 0
    frag.write_text(body.format("nothing"))
    w.wait_title(lambda t: "mine.frag:3:" in t)
    broken = w.screen(until_=lambda img: (img[:4, :, 0] > 180).all())
    assert (broken[:4, :, 0] > 180).all() and (broken[:4, :, 1] < 60).all()  # red frame
    assert broken[H // 2, W // 2, 1] == 255  # the last good program still draws
    frag.write_text(body.format("0.0, 0.0, 1.0"))
    w.wait_title(lambda t: "error" not in t)
    blue = w.screen(until_=lambda img: img[..., 2].max() == 255)
    assert blue[..., 2].max() == 255 and blue[..., 1].max() == 0
    assert w.quit() == 0


def test_progressive_supersampling_matches_headless(window, tmp_path):
    """`a` cycles to ssaa:jittered:16: with the camera still the window refines to the same
    picture as a headless render with aa="ssaa:jittered:16" (golden tolerance)."""
    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    w = window()
    w.key("a")
    w.key("a")
    w.wait_title(lambda t: "16/16 samples" in t)
    w.key("s")
    shots = files(tmp_path, "facet-*.png")
    assert w.quit() == 0 and "aa: ssaa:jittered:16" in w.proc.stdout.read()
    shot, ref = _shot_and_headless(shots[0], aa="ssaa:jittered:16")
    diff = np.abs(shot.astype(int) - ref).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()


LENS_SCENE = """
[render]
background = [0.1, 0.1, 0.15]

[[objects]]
primitive = "plane"
size = 6
material = {color = [0.8, 0.8, 0.8]}

[[objects]]
primitive = "sphere"
radius = 0.5
material = {color = [0.9, 0.4, 0.2]}
transform = [{translate = [-0.9, 0.5, -1.0]}]

[[objects]]
primitive = "cube"
size = 0.6
material = {color = [0.9, 0.2, 0.4], opacity = 0.5}
transform = [{translate = [0.8, 0.4, 1.0]}]

[[lights]]
type = "directional"
direction = [-0.4, -1, -0.6]

[cameras.main]
type = "perspective"
eye = [0, 2.0, 4.5]
target = [0, 0.3, 0]
fov = 40
aperture = 0.5
focus_distance = 4.6
"""


def test_depth_of_field_refines_in_msaa_mode(window, tmp_path):
    """A scene camera with a lens, opened in the default MSAA mode: while the view is still
    the window refines to the headless supersampled render (depth of field and a transparent
    object included), and the camera keeps its lens."""
    from facet.formats.scenefile import load_scene
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer

    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    path = tmp_path / "lens.toml"
    path.write_text(LENS_SCENE)
    w = window(str(path))
    w.wait_title(lambda t: "16/16 samples" in t)
    w.key("s")
    shots = files(tmp_path, "facet-*.png")
    assert w.quit() == 0
    shot = np.asarray(Image.open(shots[0]))
    info = json.loads(shots[0].with_suffix(".json").read_text())
    scene = load_scene(path)
    camera = Camera(info["world_to_camera_opengl"], fov_y=info["fov_y"], near=info["near"],
                    far=info["far"])
    camera.aperture, camera.focus_distance = 0.5, 4.6
    with Renderer(W, H) as r:
        ref = r.render(scene, camera, aa="ssaa:jittered:16").color[..., :3]
        pinhole = r.render(scene, Camera(camera.view, fov_y=camera.fov_y, near=camera.near,
                                         far=camera.far), aa="msaa:4").color[..., :3]
    diff = np.abs(shot.astype(int) - ref).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()
    blur = np.abs(pinhole.astype(int) - ref).max(axis=2)
    assert (blur > CHANNEL_TOL).mean() > 5 * MAX_DIFFERING  # the lens shows


def test_lights_key_keeps_the_model_lit_and_turntables_too(window, tmp_path):
    """`l` on a scene lit by the default rig freezes the rig where the camera is: the model
    stays lit (not only ambient), the light stays put while the camera orbits, and a
    turntable recorded in that state is lit too."""
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer
    from facet.scene import Mesh, Scene
    from facet.scene.light import camera_rig

    w = window()
    w.key("s")
    first = files(tmp_path, "facet-*.png")[0]
    start = json.loads(first.with_suffix(".json").read_text())
    first.rename(tmp_path / "start.png")
    first.with_suffix(".json").rename(tmp_path / "start.json")
    before = w.screen()
    w.key("l")
    w.xdotool("mousemove", "160", "120", "mousedown", "1", "mousemove", "220", "120",
              "mousemove", "260", "120", "mouseup", "1")
    w.screen(changed_from=before)  # orbited
    w.key("s")
    shot = files(tmp_path, "facet-*.png")[0]
    w.key("t")
    gif = files(tmp_path, "facet-turntable-*.gif", timeout=60)
    assert w.quit() == 0 and "lights: fixed in the scene" in w.proc.stdout.read()
    info = json.loads(shot.with_suffix(".json").read_text())
    camera = Camera(info["world_to_camera_opengl"], fov_y=info["fov_y"], near=info["near"],
                    far=info["far"])
    start_view = np.asarray(start["world_to_camera_opengl"])
    scene = Scene()
    scene.add(Mesh.load(ROOT / "models" / "default.obj"))
    with Renderer(W, H, msaa=4) as r:  # the viewer's default, like the window
        fixed = r.render(scene.view(lights=camera_rig(start_view)), camera).color[..., :3]
        unlit = r.render(scene, camera, lights="scene").color[..., :3].astype(int)
        following = r.render(scene, camera).color[..., :3]
    picture = np.asarray(Image.open(shot)).astype(int)
    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    diff = np.abs(picture - fixed).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()
    moved = np.abs(following.astype(int) - fixed).max(axis=2) > CHANNEL_TOL
    assert moved.mean() > 5 * MAX_DIFFERING  # the light really stayed behind
    model = picture.max(axis=2) > 0
    assert picture[model].mean() > 60  # lit, not just the ambient term
    import imageio.v3 as iio

    ambient = unlit.max()  # the brightest the bug's ambient-only picture gets
    frames = iio.imread(gif[0], index=None).astype(int)
    for frame in frames[::3]:  # directly lit in every frame, from behind in some
        on = frame.max(axis=2) > 0
        lit = (frame[on].max(axis=1) > 1.5 * ambient).mean()
        assert on.mean() > 0.05 and lit > 0.1, lit


FRONTS_SCENE = """
[render]
size = [160, 120]
background = [0.15, 0.2, 0.3]
shading = "blinn"
srgb = true
shadows = true
aa = "ssaa:jittered:8"

[[objects]]
primitive = "plane"
size = 6
material = {color = [0.8, 0.8, 0.75]}

[[objects]]
primitive = "sphere"
radius = 0.6
material = {color = [0.9, 0.35, 0.2], ks = 0.6, shininess = 40}
transform = [{translate = [0, 0.7, 0]}]

[[lights]]
type = "directional"
direction = [-0.3, -1, -0.4]

[cameras.main]
type = "perspective"
eye = [2.5, 2.2, 3.2]
target = [0, 0.4, 0]
fov = 40
"""


def _transforms_of(scene_path, out):
    """A transforms.json holding the scene file's camera (what `facet batch` renders from
    with plan = "cameras")."""
    from facet.formats import load_scene

    scene = load_scene(scene_path)
    w, h = scene.options["size"]
    camera = scene.camera()
    K = camera.K(w, h)
    out.write_text(json.dumps({
        "w": w, "h": h, "fl_x": K[0, 0], "fl_y": K[1, 1], "cx": K[0, 2] + 0.5,
        "cy": K[1, 2] + 0.5, "frames": [{"file_path": "images/0000.png",
                                        "transform_matrix": np.linalg.inv(camera.view).tolist()}]}))
    return out


def test_every_front_draws_the_same_first_frame(window, tmp_path):
    """One scene file through every front: `facet render` to a PNG, frame 0 of a turntable,
    frame 0 of a dataset (single and turntable), a `facet batch` job from the file's
    camera, a screenshot of `facet view` once it has refined, and one of `facet view`
    given the file's [render] settings as flags over a file without them: the same pixels
    within the golden tolerance, with shadows, supersampling, sRGB, shading and background
    all on (so every front honours them)."""
    from facet.cli import main

    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    path = tmp_path / "fronts.toml"
    path.write_text(FRONTS_SCENE)
    assert main(["render", str(path), "-o", str(tmp_path / "single.png"), "-q"]) == 0
    assert main(["render", str(path), "--turntable", "4", "-o",
                 str(tmp_path / "tt-{:02d}.png"), "-q"]) == 0
    assert main(["render", str(path), "--out-dir", str(tmp_path / "ds"), "-q"]) == 0
    assert main(["render", str(path), "--turntable", "2", "--out-dir",
                 str(tmp_path / "tds"), "-q"]) == 0
    manifest = tmp_path / "jobs.jsonl"
    manifest.write_text(json.dumps({"model": "fronts.toml", "outputs": ["color"], "views": {
        "plan": "cameras", "file": str(_transforms_of(path, tmp_path / "cams.json"))}}) + "\n")
    assert main(["batch", str(manifest), "-o", str(tmp_path / "batch"), "-q"]) == 0
    single = np.asarray(Image.open(tmp_path / "single.png")).astype(int)
    assert single.shape == (120, 160, 3)
    w = window(str(path), "--scene-size")
    w.wait_title(lambda t: "8/8 samples" in t)
    w.key("s")
    shot = files(tmp_path, "facet-*.png")
    assert w.quit() == 0
    shot[0].rename(tmp_path / "viewer.png")
    # The same settings as flags, over a file that has none of them.
    plain = tmp_path / "plain.toml"
    plain.write_text(FRONTS_SCENE[FRONTS_SCENE.index("[[objects]]"):])
    w = window(str(plain), "--size", "160x120", "--background", "0.15,0.2,0.3", "--shading",
               "blinn", "--srgb", "--shadows", "--aa", "ssaa:jittered:8")
    w.wait_title(lambda t: "8/8 samples" in t)
    w.key("s")
    flagged = files(tmp_path, "facet-*.png")
    assert w.quit() == 0
    fronts = {"turntable": tmp_path / "tt-00.png", "dataset": tmp_path / "ds" / "color.png",
              "turntable dataset": tmp_path / "tds" / "0000_color.png",
              "batch": tmp_path / "batch" / "fronts" / "images" / "0000.png",
              "viewer": tmp_path / "viewer.png", "viewer flags": flagged[0]}
    for name, file in fronts.items():
        image = np.asarray(Image.open(file).convert("RGB")).astype(int)
        assert image.shape == single.shape, name
        diff = np.abs(image - single).max(axis=2)
        assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (name, (diff > CHANNEL_TOL).mean())
    # The settings are really on: the background as written (sRGB mode takes it as
    # sRGB-encoded), and the ball's shadow.
    assert np.allclose(single[2, 2], np.rint(255 * np.array([0.15, 0.2, 0.3])), atol=1)
    from facet.formats import load_scene
    from facet.render.renderer import Renderer

    with Renderer() as r:
        flat = r.render(load_scene(path), shadows=False).color[..., :3].astype(int)
    assert ((flat - single).max(axis=2) > 30).sum() > 100  # the shadow


def test_shader_window_opens_at_its_documented_size(display, tmp_path):
    from facet.cli.shader import DEFAULT_SIZE

    shader = tmp_path / "s.frag"
    shader.write_text("void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n")
    env = {**os.environ, "DISPLAY": display, "PYTHONPATH": str(ROOT / "app")}
    proc = subprocess.Popen([sys.executable, "-m", "facet", "shader", str(shader)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wid = subprocess.run(["xdotool", "search", "--sync", "--onlyvisible", "--name",
                              "^facet shader"], env=env, capture_output=True, text=True,
                             timeout=60, check=True).stdout.split()[0]
        geometry = subprocess.run(["xdotool", "getwindowgeometry", wid], env=env,
                                  capture_output=True, text=True, check=True).stdout
        assert f"Geometry: {DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]}" in geometry, geometry
    finally:
        proc.kill()
        proc.wait()


def _refined_engine_view(window, tmp_path, engine: str, presses: int):
    """`e` pressed ``presses`` times, the view refined (4 samples: the Whitted tracer's
    default msaa:4; the path tracer given --spp 4, which otherwise refines to VIEW_PATHS)
    and screenshotted: (the screenshot, the headless render of ``engine`` from the same
    camera and sample count, the rasterizer's)."""
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer
    from facet.scene import Mesh, Scene

    given = {"spp": 4} if engine == "path" else {}
    w = window(*(["--spp", "4"] if given else []))
    for _ in range(presses):
        w.key("e")
    w.wait_title(lambda t: "4/4 samples" in t and
                 (engine == "trace" or f"engine {engine}" in t), timeout=60)
    w.key("s")
    shots = files(tmp_path, "facet-*.png")
    assert w.quit() == 0 and f"engine: {engine}" in w.proc.stdout.read()
    info = json.loads(shots[0].with_suffix(".json").read_text())
    camera = Camera(info["world_to_camera_opengl"], fov_y=info["fov_y"], near=info["near"],
                    far=info["far"])
    scene = Scene()
    scene.add(Mesh.load(ROOT / "models" / "default.obj"))
    with Renderer(W, H) as r:
        drawn = r.render(scene, camera, engine=engine, outputs=("color",),
                         **given).color[..., :3]
        raster = r.render(scene, camera, outputs=("color",)).color[..., :3]
    return np.asarray(Image.open(shots[0])).astype(int), drawn, raster


def test_the_engine_key_refines_the_traced_picture(window, tmp_path):
    """`e` switches to the ray tracer: with the camera still the window refines to the
    headless traced render of the same camera."""
    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    shot, traced, raster = _refined_engine_view(window, tmp_path, "trace", 1)
    diff = np.abs(shot - traced).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()
    # Really the tracer: its shadow rays darken the knot where it hides itself.
    assert (np.abs(traced.astype(int) - raster).max(axis=2) > 30).mean() > 0.01


def test_a_gltf_opens_framed_with_its_cameras_on_the_number_keys(display, tmp_path):
    """`facet view model.glb`: the parts keep their materials, the first view frames the
    model (not the file's camera), and key 1 switches to the file's first camera."""
    os.environ["DISPLAY"] = display
    import facet

    from gltf_files import GltfBuilder, quad

    b = GltfBuilder()
    red = b.material(pbrMetallicRoughness={"baseColorFactor": [1, 0, 0, 1],
                                           "metallicFactor": 0.0}, doubleSided=True)
    quad(b, red)
    b.node(mesh=0)
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]
    b.node(camera=0, name="far", translation=[0.5, 0.5, 9])
    path = b.write_glb(tmp_path / "cam.glb")
    with facet.Viewer(path, size=(W, H), msaa=0) as v:
        framed = v.camera().eye.copy()
        assert np.linalg.norm(framed - [0.5, 0.5, 9]) > 1  # framed, not the file's camera
        v.draw()
        img = v.grab()
        assert ((img[..., 0] > 100) & (img[..., 1] < 60)).mean() > 0.05  # its red material
        v.use_camera(0)
        np.testing.assert_allclose(v.camera().eye, [0.5, 0.5, 9], atol=1e-6)


def test_shader_window_reloads_when_a_missing_include_appears(window, tmp_path):
    """Saving a shader that includes a file that does not exist yet shows the error; creating
    that file brings the new picture without touching the shader. With a keyboard channel
    the keys go to the shader (Shadertoy's keyboard texture)."""
    shader = tmp_path / "live.frag"
    shader.write_text("void mainImage(out vec4 c, in vec2 p) {\n"
                      "  c = vec4(0.0, 0.0, texelFetch(iChannel0, ivec2(65, 0), 0).x, 1.0);\n}\n")
    w = window(str(shader), "--size", f"{W}x{H}", "--channel", "0=keyboard", command="shader")
    assert w.screen()[H // 2, W // 2, 2] < 20  # 'a' is not held
    w.xdotool("keydown", "a")
    # held: the keyboard texture says so
    w.screen(until_=lambda img: img[H // 2, W // 2, 2] > 200)
    w.xdotool("keyup", "a")
    shader.write_text('#include "later.glsl"\n'
                      "void mainImage(out vec4 c, in vec2 p) { c = vec4(later(), 1.0); }\n")
    w.wait_title(lambda t: 'cannot find include "later.glsl"' in t)
    (tmp_path / "later.glsl").write_text("vec3 later() { return vec3(1.0, 0.0, 0.0); }\n")
    w.wait_title(lambda t: "error" not in t)
    fixed = w.screen(until_=lambda img: img[H // 2, W // 2, 0] > 200)
    assert fixed[H // 2, W // 2, 2] < 20
    assert w.quit("Escape") == 0


@pytest.mark.parametrize("command,animated", [("shader", False), ("shader", True),
                                              ("view", False), ("view", True)])
def test_windows_draw_only_when_something_changes(window, tmp_path, command, animated):
    """A program that reads no time input (a static Shadertoy shader, a mesh shader without
    u_time) leaves the window idle once drawn; one that reads the time keeps drawing."""
    if command == "shader":
        body = "sin(iTime) * 0.5 + 0.5" if animated else "p.x / iResolution.x"
        path = tmp_path / "s.frag"
        path.write_text(f"void mainImage(out vec4 c, in vec2 p) {{ c = vec4({body}); }}\n")
        w = window(str(path), "--size", f"{W}x{H}", command="shader")
    else:
        path = tmp_path / "m.frag"
        path.write_text("#version 330 core\nuniform float u_time;\nout vec4 c;\n"
                        f"void main() {{ c = vec4({'fract(u_time)' if animated else '0.5'}); }}"
                        "\n")
        w = window("--frag", str(path))
    if animated:  # it moves by itself: two grabs differ
        first = w.grab()
        until(lambda: np.abs(w.grab() - first).mean() > 0.5, 20, "the picture to move")
    else:
        w.screen()  # drawn, and then still
    if animated:
        share = w.cpu_share(2.0)
        assert share > 0.2, f"an animated window used only {share:.1%} of a core"
    else:  # the quieter of two spans: a one-off wake-up (Mesa's cache thread, the X
        # server's events) is not a window that keeps drawing
        share = min(w.cpu_share(2.0), w.cpu_share(2.0))
        assert share < 0.05, f"an idle window used {share:.1%} of a core"
    assert w.quit() == 0


def test_the_engine_key_refines_the_path_traced_picture(window, tmp_path):
    """`e` twice: the path tracer. With the camera still the window refines to the headless
    path-traced render of the same camera (its paths are the same: one random stream per
    pixel and sample index), and the picture is not the rasterizer's."""
    from test_golden import CHANNEL_TOL, MAX_DIFFERING

    shot, path, raster = _refined_engine_view(window, tmp_path, "path", 2)
    diff = np.abs(shot - path).max(axis=2)
    assert (diff > CHANNEL_TOL).mean() <= MAX_DIFFERING, (diff > CHANNEL_TOL).mean()
    assert (np.abs(path.astype(int) - raster).max(axis=2) > 30).mean() > 0.01


def test_a_refined_path_traced_view_is_the_offscreen_picture(display):
    """In-process: the viewer's refined path-traced frame equals the offscreen render of
    the same camera and options (each pixel's random stream counted from the picture's top
    row, whichever way the target is drawn), and frames drawn after it is refined do not
    add the last sample again (they weighed it twice)."""
    os.environ["DISPLAY"] = display
    import facet

    with facet.Viewer(ROOT / "models" / "default.obj", size=(W, H),
                      options={"engine": "path", "spp": 4}) as v:
        for _ in range(9):  # a preview, 4 samples, then 4 frames of a refined view
            v.draw()
        shown = v.grab()[..., :3].astype(int)
        with facet.Renderer(W, H) as r:
            offscreen = r.render(v.shown_scene(), v.camera(), v.options()).color[..., :3]
    # The same paths: a few pixels round differently (float sums in other targets); a
    # sample weighed twice, or other random streams, change a fifth of them.
    diff = np.abs(shown - offscreen).max(axis=2)
    assert diff.max() <= 4 and (diff > 1).mean() < 1e-3, ((diff > 1).mean(), diff.max())


def test_the_viewer_plays_pauses_and_steps_an_animation(window, tmp_path):
    """An animated glTF plays in the window (the picture keeps changing, the title shows
    the time); p pauses it (the picture settles), '.' steps one frame on (it changes and
    settles again); p plays on."""
    from test_animation import skinned_strip

    path = skinned_strip(tmp_path)
    w = window(str(path))
    first = w.grab()
    until(lambda: np.abs(w.grab() - first).mean() > 0.2, 20, "the animation to move")
    assert " s" in w.title() and "paused" not in w.title()
    w.key("p")
    title = w.wait_title(lambda t: "paused" in t)
    paused = w.screen()
    shown = float(title.split(" - ")[-1].split(" s")[0])
    w.key("period")
    stepped_title = w.wait_title(lambda t: "paused" in t and t != title)
    stepped = float(stepped_title.split(" - ")[-1].split(" s")[0])
    assert abs((stepped - shown) % 1.0 - 1 / 30) < 0.011
    w.screen(changed_from=paused)
    w.key("p")
    w.wait_title(lambda t: "paused" not in t)
    assert w.quit() == 0


def test_the_window_shows_gaussian_splats_as_the_headless_render(window, tmp_path):
    """`facet view cloud.ply` (a 3DGS PLY): the window's screenshot equals a headless
    render of the splats through the camera its JSON records."""
    import facet
    from facet.geometry.camera import Camera
    from facet.render.renderer import Renderer

    rng = np.random.default_rng(4)
    n = 2000
    cloud = facet.Splats(rng.normal(0, 0.5, (n, 3)), np.exp(rng.normal(-3, 0.4, (n, 3))),
                         rng.normal(0, 1, (n, 4)), rng.uniform(0.3, 0.9, n),
                         rng.normal(0, 0.6, (n, 4, 3)))
    cloud.save(tmp_path / "cloud.ply")
    w = window("cloud.ply")
    assert "2,000 splats" in w.title()
    w.key("s")
    shots = files(tmp_path, "facet-*.png")
    assert w.quit() == 0
    shot = np.asarray(Image.open(shots[0]))
    info = json.loads(shots[0].with_suffix(".json").read_text())
    camera = Camera(info["world_to_camera_opengl"], fov_y=info["fov_y"], near=info["near"],
                    far=info["far"])
    with Renderer(W, H) as r:
        ref = r.render(facet.load(tmp_path / "cloud.ply"), camera).color[..., :3]
    diff = np.abs(shot.astype(int) - ref).max(axis=2)
    assert shot.std() > 5 and np.median(diff) <= 1 and (diff > 3).mean() <= 0.01


CHECKER = ("void mainImage(out vec4 c, in vec2 p) {{\n"
           "  float s = 0.0;\n"
           "  for (int i = 0; i < {loop}; i++) s += sin(s + {time} * float(i));\n"
           "  c = vec4(vec3(mod(floor(p.x) + floor(p.y), 2.0)) + 1e-9 * s, 1.0);\n}}\n")


def _crisp(img) -> float:
    """The share of horizontal neighbours a 1-pixel checker keeps apart (1 at full size)."""
    return (np.abs(np.diff(img[:, :, 0], axis=1)) > 200).mean()


@pytest.mark.parametrize("animated", [False, True])
def test_the_shader_window_previews_small_then_draws_the_size_it_can(window, tmp_path,
                                                                     animated):
    """The first frame is drawn at a quarter size; a still picture then refines to the
    window's size (the 1-pixel checker exact), and an animation keeps the size whose frames
    keep up, said in the title with what a full frame costs (on llvmpipe a 2000-step loop
    a pixel: a preview; on a fast GPU the full size), and the picture agrees with the title;
    f asks for the full size."""
    path = tmp_path / "slow.frag"
    path.write_text(CHECKER.format(loop=2000, time="iTime" if animated else "1.0"))
    w = window(str(path), "--size", f"{W}x{H}", command="shader")
    if not animated:
        w.screen(until_=lambda img: _crisp(img) > 0.99, timeout=60)
        assert " at 1/" not in w.title()
        assert w.quit() == 0
        return
    title = w.wait_title(lambda t: " at 1/" in t or "error" in t or
                         (_crisp(w.grab()) > 0.99), timeout=60)
    assert "error" not in title
    if " at 1/" in title:  # a preview: it says so, and the picture is smaller than the window
        assert "a full-size frame takes about" in title and "f: full size" in title
        assert _crisp(w.grab()) < 0.5
        w.key("f")
        w.wait_title(lambda t: " at 1/" not in t)
        until(lambda: _crisp(w.grab()) > 0.99, 60, "the full-size picture")
    assert w.quit() == 0

"""Shadow maps: no acne on lit surfaces, and the shadow of a sphere on a plane against the
analytic shadow (ray from each plane point towards the light), for directional and spot
lights."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import DirectionalLight, Material, PointLight, Scene, SpotLight, primitives

from conftest import sphere_mesh

SIZE = 128
CENTRE, RADIUS = np.array([0.2, 1.0, -0.1]), 0.5


def test_a_lit_sphere_does_not_shadow_itself(renderer):
    """Shadow acne would darken the lit side: with shadows on it must equal the render
    without them wherever N.L is clearly positive."""
    scene = Scene(ambient=0.1)
    scene.add(sphere_mesh(5), Material(color=(0.8, 0.8, 0.8)))
    light = DirectionalLight((-0.5, -1.0, -0.7))
    scene.add_light(light)
    camera = Camera.look_at((0.5, 1.5, 3.5), (0, 0, 0), fov_y=40, near=1, far=10)
    r = renderer(SIZE, SIZE)
    outputs = ("color", "normals", "ids")
    plain = r.render(scene, camera, outputs=outputs)
    shadowed = r.render(scene, camera, outputs=outputs, shadows=True)
    n_dot_l = plain.normals @ -light.direction
    lit = (plain.object_ids == 0) & (n_dot_l > 0.1)
    assert lit.sum() > 2000
    diff = np.abs(plain.color[..., :3].astype(int) - shadowed.color[..., :3])[lit]
    assert diff.max() <= 1, f"{(diff > 1).mean():.2%} of lit pixels darkened"


@pytest.mark.parametrize("engine", ["raster", "trace"])
@pytest.mark.parametrize("kind", ["directional", "spot", "point"])
def test_shadow_of_a_sphere_on_a_plane(renderer, kind, engine):
    """Shadow maps and shadow rays both cast the analytic shadow (IoU >= 0.95)."""
    scene = Scene(ambient=0.2)
    scene.add(primitives.plane(8), Material(color=(1, 1, 1), ka=1, kd=0.8, ks=0))
    scene.add(sphere_mesh(5, RADIUS), Material(color=(0.9, 0.2, 0.1)), T.translate(CENTRE))
    if kind == "directional":
        light = DirectionalLight((0.3, -1.0, 0.2))
    elif kind == "spot":
        light = SpotLight((-0.3, 4.0, 0.2), (0.1, -1.0, -0.05), inner_angle=35,
                          outer_angle=40)
    else:
        light = PointLight((-0.6, 2.6, 0.5), attenuation=(1, 0, 0))
    scene.add_light(light)
    camera = Camera.look_at((0.0, 6.0, 2.5), (0.0, 0.0, 0.0), fov_y=45, near=1, far=20)
    frame = renderer(SIZE, SIZE).render(scene, camera, outputs=("color", "ids", "position"),
                                        shadows=True, engine=engine)
    plane = frame.object_ids == 0
    p = frame.position[plane]
    # Analytic: does the segment from the plane point towards the light hit the sphere?
    if kind == "directional":
        to_light = np.broadcast_to(-np.asarray(light.direction), p.shape)
        limit = np.full(len(p), np.inf)
    else:
        v = np.asarray(light.position) - p
        limit = np.linalg.norm(v, axis=1)
        to_light = v / limit[:, None]
    oc = p - CENTRE
    b = np.sum(oc * to_light, axis=1)
    c = np.sum(oc * oc, axis=1) - RADIUS**2
    disc = b * b - c
    t = -b - np.sqrt(np.maximum(disc, 0))
    expected = (disc > 0) & (t > 0) & (t < limit)
    # Measured: a shadowed plane point only has the ambient term (0.2), a lit one much more.
    measured = frame.color[..., 0][plane] < 0.2 * 255 + 20
    if kind == "spot":  # only where the spot reaches; outside its cone all is ambient
        cone = np.sum(-to_light * np.asarray(light.direction), axis=1) > np.cos(
            np.radians(light.inner_angle))
        expected, measured = expected[cone], measured[cone]
    assert expected.sum() > 150  # the shadow is a sizeable disc in the image
    iou = (expected & measured).sum() / (expected | measured).sum()
    assert iou >= 0.95, iou


def test_cli_and_scene_file_shadows(tmp_path):
    from PIL import Image

    from facet.cli import main
    from facet.formats import load_scene

    scene = tmp_path / "s.toml"
    scene.write_text('[render]\nsize = [64, 48]\nmsaa = 0\n[[objects]]\nprimitive = "plane"\n'
                     'size = 6\n[[objects]]\nprimitive = "sphere"\nradius = 0.5\n'
                     'transform = [{translate = [0, 1, 0]}]\n[[lights]]\ntype = "directional"\n'
                     'direction = [0, -1, 0]\n[cameras.top]\ntype = "perspective"\n'
                     'eye = [0, 5, 3]\ntarget = [0, 0, 0]\n')
    assert main(["render", str(scene), "-q", "-o", str(tmp_path / "a.png")]) == 0
    assert main(["render", str(scene), "--shadows", "-q", "-o", str(tmp_path / "b.png")]) == 0
    a = np.asarray(Image.open(tmp_path / "a.png")).astype(int)
    b = np.asarray(Image.open(tmp_path / "b.png")).astype(int)
    darker = (a - b).sum(axis=2) > 60
    assert darker.sum() > 30 and (b - a).max() <= 1  # shadows only ever darken
    scene.write_text(scene.read_text().replace("msaa = 0", "msaa = 0\nshadows = true"))
    assert load_scene(scene).options["shadows"] is True


def test_pcf_kernel_softens_the_edge(renderer):
    """A wider PCF kernel spreads the shadow edge over more pixel values; 0 gives the
    hardware's 2 x 2 filter only."""
    scene = Scene(ambient=0.2)
    scene.add(primitives.plane(8), Material(color=(1, 1, 1), ks=0))
    scene.add(sphere_mesh(4, RADIUS), Material(), T.translate(CENTRE))
    scene.add_light(DirectionalLight((0.3, -1.0, 0.2)))
    camera = Camera.look_at((0.0, 6.0, 2.5), (0.0, 0.0, 0.0), fov_y=45, near=1, far=20)
    r = renderer(SIZE, SIZE)
    edges = {}
    for pcf in (0, 2):
        frame = r.render(scene, camera, outputs=("color", "ids"), shadows=True, pcf=pcf)
        red = frame.color[..., 0][frame.object_ids == 0].astype(int)
        edges[pcf] = ((red > 0.2 * 255 + 20) & (red < 255 * 0.95)).sum()  # penumbra pixels
    assert edges[2] > edges[0]
    with pytest.raises(InputError, match="pcf: expected one of 0, 1, 2, got 5"):
        r.render(scene, camera, shadows=True, pcf=5)


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_area_light_penumbra_grows_with_its_size(renderer, engine):
    """An area light's shadow has a penumbra as wide as similar triangles say:
    w = L (d_receiver - d_occluder) / d_occluder, measured across the shadow's edge."""
    from facet.scene import AreaLight

    r = renderer(SIZE, SIZE)
    camera = Camera.look_at((0.0, 6.0, 0.001), (0.0, 0.0, 0.0), ortho_height=4.0, near=1,
                            far=10)
    widths = {}
    for size in (0.0001, 0.8):
        scene = Scene(ambient=0.0)
        scene.add(primitives.plane(8), Material(color=(1, 1, 1), ka=0, kd=1, ks=0))
        # A wide thin slab at height 1 casts a straight edge along x = 0 on the plane.
        scene.add(primitives.cube((2.0, 0.02, 4.0)), Material(), T.translate((-1.0, 1.0, 0)))
        scene.add_light(AreaLight((0, 3.0, 0), (0, -1, 0), (size, size), attenuation=(1, 0, 0)))
        frame = r.render(scene, camera, shadows=True, aa="ssaa:jittered:64",
                         outputs=("color", "ids", "position"), engine=engine)
        open_ = r.render(scene, camera, aa="ssaa:jittered:64", engine=engine,
                         shadows=False).color
        row = frame.color[SIZE // 2, :, 0].astype(float)
        visible = row / np.maximum(open_[SIZE // 2, :, 0].astype(float), 1.0)
        x = frame.position[SIZE // 2, :, 0]
        plane = frame.object_ids[SIZE // 2] == 0
        ramp = plane & (visible > 0.1) & (visible < 0.9)
        widths[size] = (x[ramp].max() - x[ramp].min()) if ramp.any() else 0.0
    # Similar triangles from the light (height 3): occluder at distance 2, plane at 3, so
    # the penumbra is L (3 - 2) / 2 = 0.4 wide, centred on the edge's point-light shadow
    # (x = 0). Seen from above the slab hides its inner half; the outer half rises linearly
    # from visibility 1/2 at x = 0 to 1 at x = 0.2, so 0.1 < v < 0.9 spans 0.8 x 0.2 = 0.16.
    assert widths[0.0001] < 0.05
    assert abs(widths[0.8] - 0.16) < 0.04, widths


def test_area_light_in_a_scene_file(tmp_path):
    from facet.errors import SceneError
    from facet.formats import load_scene
    from facet.scene import AreaLight

    path = tmp_path / "a.toml"
    path.write_text('[[objects]]\nprimitive = "sphere"\n[[lights]]\ntype = "area"\n'
                    "position = [0, 3, 0]\nnormal = [0, -1, 0]\nsize = [1, 0.5]\n")
    light = load_scene(path).lights[0]
    assert isinstance(light, AreaLight) and light.size == (1.0, 0.5)
    path.write_text('[[lights]]\ntype = "area"\nsize = [1, 0]\n')
    with pytest.raises(SceneError, match=r"lights\[0\]: area light size must be"):
        load_scene(path)


@pytest.mark.parametrize("opacity", [0.25, 0.5, 0.75, 1.0])
def test_transparent_casters_let_light_through(renderer, opacity):
    """A pane of opacity a (out of view) between a directional light and the ground: the
    ground in its shadow keeps (1 - a) of the direct light (screen-door shadow map, within
    0.06 with the 3 x 3 PCF), and an opaque pane blocks all of it."""
    scene = Scene(ambient=0.0)
    scene.add(primitives.plane(12), Material(color=(1, 1, 1), ka=0, kd=1, ks=0))
    # Light travels along (1, -1, 0): the pane at x = -3, y = 3 shades x in [-1, 1] at y = 0.
    scene.add(primitives.plane((2.0, 1.0)), Material(color=(0.2, 0.9, 0.2), opacity=opacity),
              T.translate((-3.0, 3.0, 0.0)))
    scene.add_light(DirectionalLight((1.0, -1.0, 0.0)))
    camera = Camera.look_at((0, 5, 0), (0, 0, 0), up=(0, 0, -1), ortho_height=2.0, near=1,
                            far=10)
    frame = renderer(SIZE, SIZE).render(scene, camera, outputs=("color", "position"),
                                        shadows=True)
    grey = frame.color[..., 0].astype(float)
    z = frame.position[..., 2]
    inside, outside = np.abs(z) < 0.35, np.abs(z) > 0.65
    assert inside.sum() > 2000 and outside.sum() > 2000
    lit = grey[outside].mean()
    assert lit > 150
    assert abs(grey[inside].mean() / lit - (1.0 - opacity)) <= 0.06


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_one_sided_plate_shadows_from_either_side(renderer, engine):
    """glTF's doubleSided = false culls what the camera sees; for light a surface is
    opaque from both sides (Mitsuba, Cycles). A one-sided plate between a point light and
    the floor shadows the floor whichever way it faces (facing up, the floor's shadow rays
    meet its back: the tracers let the light through, 1.4x Mitsuba's floor under four
    glossy plates); the camera above sees its front, and through its back to the floor
    (its id), as the rasterizer culls it."""
    from facet.scene.pbr import PbrMaterial

    for turn, seen in ((np.eye(4), "plate"), (T.rotate_x(180.0), "floor")):
        scene = Scene(ambient=0.0)
        grey = dict(base_color=(0.8, 0.8, 0.8, 1), metallic=0.0)
        floor = scene.add(primitives.plane(6.0), material=PbrMaterial(**grey))
        plate = scene.add(primitives.plane(1.0),
                          material=PbrMaterial(**grey, double_sided=False),
                          transform=T.translate((0, 1, 0)) @ turn)
        scene.add_light(PointLight(position=(0, 3, 0), color=(1, 1, 1), intensity=20.0))
        camera = Camera.look_at((0.3, 5, 0.001), (0.3, 0, 0), fov_y=40)
        opts = dict(engine=engine, lights="scene", shadows=True, aa="none",
                    outputs=("color", "ids"), float_color=True)
        if engine != "raster":
            opts["max_depth"] = 0
        frame = renderer(32, 32).render(scene, camera, **opts)
        ids = frame.object_ids
        assert ids[16, 13] == (plate if seen == "plate" else floor), (turn, ids[16, 13])
        # Straight under the light, past the plate's edge as the camera sees it: the
        # floor beside the plate's shadow is lit, the floor in it is dark.
        camera_under = Camera.look_at((0, 0.5, 0.001), (0, 0, 0), fov_y=30)
        under = renderer(8, 8).render(scene.view(objects=[scene.objects[0]]), camera_under,
                                      **{**opts, "outputs": ("color",)}).color
        shadowed = renderer(8, 8).render(scene, camera_under,
                                         **{**opts, "outputs": ("color",)}).color
        assert shadowed[..., :3].mean() < 0.02 * under[..., :3].mean(), \
            (turn, shadowed[..., :3].mean(), under[..., :3].mean())

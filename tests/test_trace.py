"""The ray tracer over real GL, against the equations: exact depth of analytic shapes
(closed-form roots), agreement with the rasterizer where both should agree, mirrors and glass
against a numpy Whitted tracer (Snell, Fresnel, total internal reflection), transparency,
self-shadowing offsets, determinism and errors."""

import numpy as np
import pytest

from facet.errors import InputError
from facet.geometry import transforms as T
from facet.geometry.camera import Camera
from facet.scene import (
    DirectionalLight,
    Material,
    PointLight,
    Scene,
    SpotLight,
    Texture,
    primitives,
    shapes,
)

from conftest import sphere_mesh
from reference import (
    erode,
    linear_depth,
    object_rays,
    pixel_rays,
    ray_box,
    ray_cone,
    ray_cylinder,
    ray_disk,
    ray_sphere_object,
)

S = 64
CAMERAS = {
    "perspective": Camera.look_at((1.8, 2.2, 4.0), (0, 0.1, 0), fov_y=40, near=0.5, far=20),
    "orthographic": Camera.look_at((1.8, 2.2, 4.0), (0, 0.1, 0), ortho_height=3.0, near=0.5,
                                   far=20),
}
PLACE = T.compose(T.scale((1.0, 0.8, 1.2)), T.rotate_x(25), T.rotate_y(30),
                  T.translate((0.1, 0.2, -0.1)))
SHAPES = {
    "sphere": (shapes.Sphere(0.9), lambda o, d: ray_sphere_object(o, d, 0.9)),
    "cone": (shapes.Cone(0.8, 1.6), lambda o, d: ray_cone(o, d, 0.8, 1.6)),
    "cylinder": (shapes.Cylinder(0.6, 1.4), lambda o, d: ray_cylinder(o, d, 0.6, 1.4)),
    "box": (shapes.Box((1.2, 0.8, 1.0)), lambda o, d: ray_box(o, d, (1.2, 0.8, 1.0))),
    "disk": (shapes.Disk(1.1), lambda o, d: ray_disk(o, d, 1.1)),
    "plane": (shapes.Plane((2.0, 1.5)), lambda o, d: ray_disk(o, d, 0, half=(1.0, 0.75))),
}


@pytest.mark.parametrize("projection", list(CAMERAS))
@pytest.mark.parametrize("kind", list(SHAPES))
def test_exact_depth_of_analytic_shapes(renderer, kind, projection):
    """Depth of a sheared, scaled, rotated shape from the tracer equals the closed-form
    root (sphere: the quadratic in s; cone: the notes' equation) within 1e-4 relative."""
    shape, reference = SHAPES[kind]
    camera = CAMERAS[projection]
    scene = Scene()
    scene.add(shape, Material(), PLACE)
    frame = renderer(S, S).render(scene, camera, engine="trace", outputs=("depth", "ids"))
    origins, dirs = pixel_rays(camera.view, camera.projection(S, S), S, S)
    t = reference(*object_rays(origins, dirs, PLACE))
    hit = np.isfinite(t)
    points = origins + np.where(hit, t, 0.0)[..., None] * dirs
    expected = np.where(hit, linear_depth(camera.view, points), 0.0)
    traced = frame.object_ids == 0
    assert hit.sum() > 200
    assert (hit != traced).mean() < 0.003  # silhouette pixels may round either way
    both = hit & traced
    rel = np.abs(frame.depth[both] - expected[both]) / expected[both]
    assert rel.max() < 1e-4, rel.max()


def _mesh_scenes():
    dir_light = DirectionalLight((-0.4, -1.0, -0.6))
    point = PointLight((1.5, 2.5, 2.0), intensity=1.5, attenuation=(1, 0, 0.1))
    spot = SpotLight((0.5, 3.0, 1.5), (-0.1, -1, -0.4), inner_angle=20, outer_angle=28)
    torus = primitives.torus(0.8, 0.3)
    yield "sphere", sphere_mesh(4), [dir_light], "phong"
    yield "torus", torus, [point, dir_light], "blinn"
    yield "cube", primitives.cube(1.2), [spot, point], "phong"


@pytest.mark.parametrize("projection", list(CAMERAS))
def test_traced_and_rasterized_agree_without_effects(renderer, projection):
    """Without shadows, reflection or transparency, the same triangles give the same colour
    from both engines (interior pixels within 2/255) and the same depth (1e-4 relative)."""
    camera = CAMERAS[projection]
    r = renderer(S, S)
    for name, mesh, lights, shading in _mesh_scenes():
        scene = Scene(ambient=0.15)
        scene.add(mesh, Material(color=(0.8, 0.5, 0.3), ks=0.5, shininess=40),
                  T.rotate_y(20))
        for light in lights:
            scene.add_light(light)
        kw = dict(outputs=("color", "depth", "ids"), shading=shading, shadows=False)
        raster = r.render(scene, camera, msaa=0, **kw)
        traced = r.render(scene, camera, engine="trace", aa="none", **kw)
        inner = erode(raster.object_ids == 0, 2) & erode(traced.object_ids == 0, 2)
        assert inner.sum() > 300, name
        diff = np.abs(raster.color[..., :3].astype(int) - traced.color[..., :3])[inner]
        assert diff.max() <= 2, (name, diff.max())
        both = (raster.depth > 0) & (traced.depth > 0)
        rel = np.abs(raster.depth - traced.depth)[both] / raster.depth[both]
        assert np.percentile(rel, 99) < 1e-4 and rel.max() < 1e-3, (name, rel.max())


def test_gltf_materials_are_traced_by_their_phong_stand_ins(renderer):
    """The tracer shades a PbrMaterial by the Phong stand-ins the rasterizer's phong model
    uses (facet.scene.pbr): the two engines agree, in both colour modes."""
    from facet.scene.pbr import PbrMaterial

    scene = Scene(ambient=0.15)
    scene.add(sphere_mesh(4), PbrMaterial(base_color=(0.6, 0.3, 0.2, 1), metallic=0.2,
                                          roughness=0.5), T.rotate_y(20))
    scene.add_light(DirectionalLight((-1, -0.8, -1.2), (1, 0.95, 0.9), 0.9))
    r = renderer(S, S)
    for srgb in (False, True):
        kw = dict(outputs=("color", "ids"), shading="phong", shadows=False, srgb=srgb)
        raster = r.render(scene, CAMERAS["perspective"], msaa=0, **kw)
        traced = r.render(scene, CAMERAS["perspective"], engine="trace", aa="none", **kw)
        inner = erode(raster.object_ids == 0, 2) & erode(traced.object_ids == 0, 2)
        assert inner.sum() > 300
        diff = np.abs(raster.color[..., :3].astype(int) - traced.color[..., :3])[inner]
        assert diff.max() <= 2, (srgb, diff.max())
        assert raster.color[..., :3][inner].std() > 5  # lit, not flat


SQUARES = np.kron((np.indices((8, 8)).sum(axis=0) % 2), np.ones((16, 16)))  # 128 x 128


def _checker(p):
    """The floor's colour at world points p: the texture below, by the plane's texture
    coordinates (u = (x + 2) / 4, v = (2 - z) / 4; image row 0 is v = 1)."""
    u = np.clip((p[..., 0] + 2.0) / 4.0, 0, 0.9999)
    v = np.clip((2.0 - p[..., 2]) / 4.0, 1e-4, 1)
    return SQUARES[((1 - v) * 128).astype(int), (u * 128).astype(int)]


def _checker_floor(scene):
    """A 4 x 4 floor at y = -1 with an 8 x 8 black and white checker texture (unlit)."""
    pixels = np.repeat((SQUARES * 255).astype(np.uint8)[..., None], 3, axis=2)
    scene.add(shapes.Plane((4.0, 4.0)), Material(color=(1, 1, 1), texture=Texture(pixels)),
              T.translate((0, -1, 0)))


def whitted(o, d, spheres, depth, max_depth):
    """A numpy Whitted tracer for glass spheres (ior, reflectivity 1, no local colour) over
    the unlit checker floor (white/black), black background: the colour per ray."""
    t_floor = ray_disk(o, d, 0, y=-1.0, half=(2.0, 2.0))
    best = t_floor.copy()
    which = np.full(best.shape, -1)
    for i, (centre, radius, _) in enumerate(spheres):
        t = ray_sphere_object(o - np.asarray(centre), d, radius)  # from inside too
        which = np.where(t < best, i, which)
        best = np.minimum(best, t)
    p = o + np.where(np.isfinite(best), best, 0)[..., None] * d
    out = np.where(np.isfinite(t_floor) & (which == -1), _checker(p), 0.0)
    for i, (centre, radius, ior) in enumerate(spheres):
        sel = which == i
        if not sel.any() or depth >= max_depth:
            continue
        dd, pp = d[sel], p[sel]
        n = (pp - centre) / radius
        front = np.sum(dd * n, axis=-1) < 0
        n = np.where(front[:, None], n, -n)
        cos_i = -np.sum(dd * n, axis=-1)
        eta = np.where(front, 1 / ior, ior)
        k = 1 - eta ** 2 * (1 - cos_i ** 2)
        tir = k < 0
        t_dir = eta[:, None] * dd + (eta * cos_i - np.sqrt(np.maximum(k, 0)))[:, None] * n
        f0 = ((ior - 1) / (ior + 1)) ** 2
        cos_f = np.where(front, cos_i, -np.sum(t_dir * n, axis=-1))
        fresnel = np.where(tir, 1.0, f0 + (1 - f0) * (1 - np.clip(cos_f, 0, 1)) ** 5)
        r_dir = dd + 2 * cos_i[:, None] * n
        eps = 1e-4
        reflected = whitted(pp + eps * n, r_dir, spheres, depth + 1, max_depth)
        refracted = whitted(pp - eps * n, t_dir / np.linalg.norm(t_dir, axis=-1,
                                                                  keepdims=True),
                            spheres, depth + 1, max_depth)
        out[sel] = fresnel * reflected + (1 - fresnel) * np.where(tir, 0, refracted)
    return out


@pytest.mark.parametrize("case", ["mirror", "glass", "inside glass"])
def test_reflection_and_refraction_follow_snell_and_fresnel(renderer, case):
    """A mirror sphere and a glass sphere (ior 1.5) over a checkerboard, and a camera inside
    a glass sphere (where rays meet the surface beyond the critical angle and reflect
    totally): the traced colour equals a numpy Whitted tracer's per pixel (interior pixels
    away from the checker's edges; 97% within 3/255)."""
    camera = Camera.look_at((0.3, 0.9, 3.0), (0, -0.4, 0), fov_y=45, near=0.1, far=20)
    if case == "mirror":
        spheres = [((0.0, -0.2, 0.0), 0.7, 1e9)]  # reflection only: Fresnel = 1
        material = Material(color=(0, 0, 0), ka=0, kd=0, ks=0, reflectivity=1.0)
    else:
        spheres = [((0.0, -0.2, 0.0), 0.7, 1.5)]
        material = Material(color=(0, 0, 0), ka=0, kd=0, ks=0, reflectivity=1.0, ior=1.5)
    if case == "inside glass":
        camera = Camera.look_at((0.72, 0.1, 0.0), (0.5, -0.5, -1.0), fov_y=70, near=0.01,
                                far=20)
        spheres = [((0.0, 0.0, 0.0), 0.9, 1.5)]
    scene = Scene(ambient=1.0, background=(0, 0, 0))
    _checker_floor(scene)
    for centre, radius, _ in spheres:
        scene.add(shapes.Sphere(radius), material, T.translate(centre))
    depth = 4
    frame = renderer(S, S).render(scene, camera, engine="trace", aa="none", max_depth=depth,
                                  shading="unlit", float_color=True)
    origins, dirs = pixel_rays(camera.view, camera.projection(S, S), S, S)
    expected = whitted(origins, dirs, spheres, 0, depth)
    got = frame.color[..., 0]
    # Pixels whose neighbours agree in the reference: away from checker edges, where a
    # tiny difference in the ray's path flips the square.
    calm = np.ones_like(expected, bool)
    for axis in (0, 1):
        for shift in (1, -1):
            calm &= np.abs(np.roll(expected, shift, axis) - expected) < 0.02
    close = np.abs(got - expected) <= 3 / 255
    assert calm.sum() > 0.4 * S * S and close[calm].mean() > 0.97, close[calm].mean()
    if case == "inside glass":  # where the eye rays meet the surface beyond the critical
        centre, radius, ior = spheres[0]  # angle, all their light is reflected
        t = ray_sphere_object(origins - np.asarray(centre), dirs, radius)
        n = (origins + t[..., None] * dirs - centre) / radius
        sin2 = 1 - np.sum(dirs * n, axis=-1) ** 2
        tir = ior ** 2 * sin2 > 1
        assert tir.sum() > 100 and close[tir & calm].mean() > 0.97


def test_a_reflective_highlight_is_clamped_as_a_pixel_not_before_it_is_shared(renderer):
    """A red Phong sphere with reflectivity 0.3 over a black background, lit so that its
    highlight's red is far above 1: the notes' Whitted equation gives (1 - r) I_local +
    r I_reflected, clamped once as a pixel; the traced colour equals a numpy tracer of it
    (the reflections see the black background). The old tracer clamped I_local first, so
    red stopped at 1 - r = 0.70 across the highlight (17/255 and more off)."""
    from reference import phong, ray_sphere

    camera = Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=35, near=0.5, far=20)
    material = Material(color=(1.0, 0.3, 0.2), ka=0.2, kd=0.9, ks=0.9, shininess=12,
                        reflectivity=0.3)
    light = DirectionalLight(direction=(-0.3, -0.4, -1.0), intensity=1.4)
    scene = Scene(ambient=0.3, background=(0, 0, 0))
    scene.add_light(light)
    scene.add(shapes.Sphere(1.0), material)
    frame = renderer(S, S).render(scene, camera, engine="trace", aa="none", shadows=False,
                                  float_color=True)
    origins, dirs = pixel_rays(camera.view, camera.projection(S, S), S, S)
    t = ray_sphere(origins, dirs, (0, 0, 0), 1.0)
    hit = np.isfinite(t)
    p = origins + np.where(hit, t, 0)[..., None] * dirs
    local = phong(p, p, -dirs, material.color, material, [light], 0.3, clamp=False)
    expected = np.clip((1 - material.reflectivity) * local, 0, 1)
    inside = erode(hit, 1)
    got = frame.color[..., :3]
    assert local[inside][:, 0].max() > 1.6  # the highlight is saturated in the local colour
    assert np.abs(got - expected)[inside].max() <= 2 / 255


def test_transparency_passes_light_through(renderer):
    """A pane of opacity a over the background gives a C + (1 - a) background, exactly
    where it covers (unlit), and its shadow keeps (1 - a) of the light."""
    camera = Camera.look_at((0, 0, 3), (0, 0, 0), ortho_height=2.0, near=1, far=5)
    scene = Scene(ambient=1.0, background=(0.2, 0.4, 0.6))
    scene.add(shapes.Plane((1.0, 1.0)), Material(color=(1.0, 0.0, 0.0), opacity=0.25),
              T.rotate_x(90))
    img = renderer(S, S).render(scene, camera, engine="trace", shading="unlit",
                                float_color=True, aa="none").color
    covered = img[S // 2, S // 2, :3]
    assert np.allclose(covered, 0.25 * np.array([1, 0, 0]) + 0.75 * np.array([0.2, 0.4, 0.6]),
                       atol=1 / 255)
    assert np.allclose(img[2, 2, :3], [0.2, 0.4, 0.6], atol=1 / 255)


@pytest.mark.parametrize("surface", ["flat", "curved"])
def test_shadow_rays_do_not_shadow_their_own_surface(renderer, surface):
    """Self-shadowing acne would darken lit pixels: with shadow rays every pixel facing the
    light keeps the unshadowed value, on a grazing-lit plane and on a fine sphere mesh."""
    scene = Scene(ambient=0.1)
    if surface == "flat":
        scene.add(shapes.Plane((50.0, 50.0)), Material(color=(0.8, 0.8, 0.8), ks=0))
        light = DirectionalLight((-1.0, -0.08, -0.3))  # grazing: 4.6 degrees
        camera = Camera.look_at((0.3, 3.0, 3.0), (0, 0, 0), fov_y=40, near=0.5, far=60)
    else:
        scene.add(sphere_mesh(5), Material(color=(0.8, 0.8, 0.8)))
        light = DirectionalLight((-0.5, -1.0, -0.7))
        camera = Camera.look_at((0.5, 1.5, 3.5), (0, 0, 0), fov_y=40, near=1, far=10)
    scene.add_light(light)
    r = renderer(S, S)
    kw = dict(engine="trace", aa="none", outputs=("color", "normals", "ids"))
    plain = r.render(scene, camera, shadows=False, **kw)
    shadowed = r.render(scene, camera, shadows=True, **kw)
    lit = (plain.object_ids == 0) & (plain.normals @ -light.direction > 0.02)
    assert lit.sum() > 500
    assert np.array_equal(plain.color[lit], shadowed.color[lit])


def test_contact_shadows_stay_attached(renderer):
    """A box standing on the floor, lit from the side: the floor right at the box's foot on
    the far side is in shadow (no gap from the ray offset)."""
    camera = Camera.look_at((0, 6, 0.001), (0, 0, 0), ortho_height=2.0, near=1, far=10)
    scene = Scene(ambient=0.0)
    scene.add(shapes.Plane((4.0, 4.0)), Material(color=(1, 1, 1), ks=0))
    scene.add(shapes.Box((0.5, 0.5, 0.5)), Material(), T.translate((0, 0.25, 0)))
    scene.add_light(DirectionalLight((1.0, -1.0, 0.0)))  # shadow towards +x
    frame = renderer(S, S).render(scene, camera, engine="trace", aa="none",
                                  outputs=("color", "ids", "position"))
    row = S // 2
    floor = frame.object_ids[row] == 0
    x = frame.position[row, :, 0]
    beside = floor & (x > 0.25) & (x < 0.3)  # within one pixel of the box's edge
    assert beside.any() and np.all(frame.color[row, beside, 0] == 0)
    far_lit = floor & (x > 0.8)
    assert np.all(frame.color[row, far_lit, 0] > 100)


def test_traced_images_are_deterministic(renderer):
    scene = Scene()
    scene.add(shapes.Sphere(1.0), Material(reflectivity=0.3, gloss=0.3))
    scene.add_light(DirectionalLight((-1, -1, -1)))
    r = renderer(S, S)
    a = r.render(scene, CAMERAS["perspective"], engine="trace", spp=8).color
    b = r.render(scene, CAMERAS["perspective"], engine="trace", spp=8).color
    assert np.array_equal(a, b)


def test_bad_tracer_options_and_a_scene_too_big(renderer):
    scene = Scene()
    scene.add(sphere_mesh(3))
    r = renderer(16, 16)
    for kwargs, message in ((dict(spp=0), "spp must be an integer >= 1"),
                            (dict(max_depth=-1), "max_depth: expected an integer in"),
                            (dict(max_depth=1000), "max_depth: expected an integer in"),
                            (dict(engine="photon"), "unknown engine 'photon'")):
        with pytest.raises(InputError, match=message):
            r.render(scene, engine=kwargs.pop("engine", "trace"), **kwargs)
    r.render(scene, engine="trace", outputs=("ids",))  # the tracer exists now
    tracer = r._engine("trace")
    limit, tracer.rays.max_texels = tracer.rays.max_texels, 100
    bigger = Scene()
    bigger.add(sphere_mesh(4))
    try:
        with pytest.raises(InputError, match="more than the ray tracer can hold"):
            r.render(bigger, engine="trace", outputs=("color",))
    finally:
        tracer.max_texels = limit


def test_an_infinite_plane_in_a_scene_file(tmp_path, renderer):
    """plane with size = inf: left out of the scene's bounds (framing a ball on it works),
    traced to the horizon, drawn by the rasterizer as a large square; both engines agree on
    the floor's depth in front of the camera."""
    from facet.formats import load_scene

    path = tmp_path / "inf.toml"
    path.write_text('[[objects]]\nprimitive = "plane"\nsize = inf\n[[objects]]\n'
                    'primitive = "disk"\nradius = 0.4\n'
                    'transform = [{translate = [1.2, 0.02, 0.5]}]\n'
                    '[[objects]]\nprimitive = "sphere"\nradius = 0.5\n'
                    'transform = [{translate = [0, 0.5, 0]}]\n')
    scene = load_scene(path)
    assert scene.objects[0].infinite and np.allclose(scene.bounds, [[-0.5, 0, -0.5],
                                                                    [1.6, 1.0, 0.9]])
    camera = Camera.look_at((0, 1.0, 4.0), (0, 0.3, 0), fov_y=60, near=0.1, far=100)
    r = renderer(S, S)
    traced = r.render(scene, camera, engine="trace", outputs=("depth", "ids"), aa="none")
    raster = r.render(scene, camera, outputs=("depth", "ids"), msaa=0)
    floor = (traced.object_ids == 0) & (raster.object_ids == 0)
    assert floor.sum() > 0.25 * S * S
    rel = np.abs(traced.depth - raster.depth)[floor] / raster.depth[floor]
    assert rel.max() < 1e-3
    assert set(np.unique(traced.object_ids)) == {-1, 0, 1, 2}


def test_a_million_triangles_fit_and_stay_exact(renderer):
    """A 1.3M-triangle icosphere: the hierarchy builds, the scene uploads, and the traced
    depth is the sphere's own within 1e-4 (its facets are a micrometre off the sphere)."""
    import trimesh

    from facet.scene import Mesh

    ico = trimesh.creation.icosphere(subdivisions=8)
    v = np.asarray(ico.vertices)
    scene = Scene()
    scene.add(Mesh(v, np.asarray(ico.faces), v), Material())
    assert scene.objects[0].mesh.face_count == 1_310_720
    camera = CAMERAS["perspective"]
    frame = renderer(32, 32).render(scene, camera, engine="trace", outputs=("depth",))
    origins, dirs = pixel_rays(camera.view, camera.projection(32, 32), 32, 32)
    t = ray_sphere_object(origins, dirs, 1.0)
    hit = np.isfinite(t) & (frame.depth > 0)
    expected = linear_depth(camera.view, origins + np.where(hit, t, 0)[..., None] * dirs)
    assert hit.sum() > 200
    assert (np.abs(frame.depth - expected)[hit] / expected[hit]).max() < 1e-4


@pytest.mark.parametrize("make,message", [
    (lambda: shapes.Sphere(-1), "sphere radius must be a number > 0"),
    (lambda: shapes.Box((1, 0, 1)), "box size must be"),
    (lambda: shapes.Cone(0.5, float("nan")), "cone height must be a number > 0"),
    (lambda: shapes.Plane((1, -2)), "plane size must be"),
])
def test_bad_shapes(make, message):
    with pytest.raises(InputError, match=message):
        make()

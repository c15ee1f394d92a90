"""OpenUSD stages (facet.formats.usd): geometry placed exactly (facet's depth against a ray
caster over the triangles and shapes pxr gives, through the same explicit camera, in the
rasterizer and the Whitted tracer), composition (sublayers, references, payloads, variants,
inherits, active, visibility, purpose, instancing), UsdPreviewSurface and UsdLux against
the same scene built with facet's API, cameras against the pinhole model, the guard on
everything a stage reaches, and the command line. Stages are written here with pxr."""

from __future__ import annotations

import subprocess
import sys
import warnings
import zipfile

import numpy as np
import pytest

import facet
from facet.errors import FacetWarning, MeshError
from facet.geometry.camera import Camera

pxr = pytest.importorskip("pxr", reason="OpenUSD needs usd-core (the usd extra)")
from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade  # noqa: E402

W, H = 64, 48


def _stage(path):
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    return stage


def _xform(prim, translate=(0, 0, 0), rotate=(0, 0, 0), scale=(1, 1, 1)):
    x = UsdGeom.Xformable(prim)
    x.AddTranslateOp().Set(Gf.Vec3d(*translate))
    x.AddRotateXYZOp().Set(Gf.Vec3f(*rotate))
    x.AddScaleOp().Set(Gf.Vec3f(*scale))


def geometry_stage(path):
    """Polygons of 3, 4 and 5 corners with a hole face, left-handed, moved by an xformOp
    stack; a Cube, a Sphere and a Cylinder along x."""
    stage = _stage(path)
    mesh = UsdGeom.Mesh.Define(stage, "/World/Poly")
    mesh.CreatePointsAttr([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0), (0, 2, 0),
                           (2, 0, 0), (3, 1, 0), (2, 2, 0), (-3, 0, 0), (-2, 0, 0),
                           (-2.5, 1, 0)])
    mesh.CreateFaceVertexCountsAttr([5, 3, 3])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 4, 3, 5, 6, 7, 8, 9, 10])
    mesh.CreateHoleIndicesAttr([2])  # the last triangle is a hole
    mesh.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    mesh.CreateDoubleSidedAttr(True)
    _xform(mesh.GetPrim(), (0.2, 0.1, -1.0), (10, 25, 5), (0.8, 0.8, 0.8))
    cube = UsdGeom.Cube.Define(stage, "/World/Cube")
    cube.CreateSizeAttr(1.0)
    _xform(cube.GetPrim(), (-1.6, -1.2, 0.5), (0, 30, 0))
    sphere = UsdGeom.Sphere.Define(stage, "/World/Sphere")
    sphere.CreateRadiusAttr(0.6)
    _xform(sphere.GetPrim(), (1.5, -1.0, 0.6))
    cyl = UsdGeom.Cylinder.Define(stage, "/World/Cyl")
    cyl.CreateRadiusAttr(0.3)
    cyl.CreateHeightAttr(1.6)
    cyl.CreateAxisAttr("X")
    _xform(cyl.GetPrim(), (0.0, 1.9, 0.3))
    stage.Save()
    return path


def _rays(camera: Camera, w: int, h: int):
    """World origins and unit directions through pixel centres (row 0 at the top)."""
    inv = np.linalg.inv(camera.view)
    t = np.tan(np.radians(camera.fov_y) / 2)
    xs = ((np.arange(w) + 0.5) / w * 2 - 1) * t * w / h
    ys = (1 - (np.arange(h) + 0.5) / h * 2) * t
    d = np.stack([*np.meshgrid(xs, ys), -np.ones((h, w))], -1)
    d = d @ inv[:3, :3].T
    return np.broadcast_to(inv[:3, 3], d.shape), d / np.linalg.norm(d, axis=-1,
                                                                    keepdims=True)


def _world(prim):
    return np.array(UsdGeom.XformCache().GetLocalToWorldTransform(prim)).T  # row -> column


def _triangles(prim):
    """pxr's points and faces, fanned here, holes left out, in world space."""
    mesh = UsdGeom.Mesh(prim)
    pts = np.array(mesh.GetPointsAttr().Get(), float)
    counts, idx = list(mesh.GetFaceVertexCountsAttr().Get()), list(
        mesh.GetFaceVertexIndicesAttr().Get())
    holes = set(mesh.GetHoleIndicesAttr().Get() or [])
    tris, at = [], 0
    for f, c in enumerate(counts):
        if f not in holes:
            tris += [(idx[at], idx[at + k], idx[at + k + 1]) for k in range(1, c - 1)]
        at += c
    m = _world(prim)
    world = pts @ m[:3, :3].T + m[:3, 3]
    return world[np.array(tris)]


def _hit_triangles(o, d, tris):
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(d[..., None, :], e2)
    det = np.einsum("...ij,ij->...i", p, e1)
    inv = 1 / np.where(np.abs(det) > 1e-12, det, np.nan)
    s = o[..., None, :] - tris[:, 0]
    u = np.einsum("...ij,...ij->...i", s, p) * inv
    q = np.cross(s, e1)
    v = np.einsum("...j,...ij->...i", d, q) * inv
    t = np.einsum("ij,...ij->...i", e2, q) * inv
    ok = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return np.where(ok, t, np.inf).min(axis=-1)


def _hit_object(o, d, m, test):
    """Nearest t of a shape ``test(o, d) -> t`` in object space placed by ``m``."""
    inv = np.linalg.inv(m)
    oo = o @ inv[:3, :3].T + inv[:3, 3]
    dd = d @ inv[:3, :3].T
    return test(oo, dd)  # (t is the same parameter in both spaces: affine map)


def _sphere(r):
    def test(o, d):
        b = np.einsum("...i,...i", o, d)
        a = np.einsum("...i,...i", d, d)
        c = np.einsum("...i,...i", o, o) - r * r
        disc = b * b - a * c
        t = (-b - np.sqrt(np.maximum(disc, 0))) / a
        return np.where((disc >= 0) & (t > 0), t, np.inf)
    return test


def _box(half):
    def test(o, d):
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (-half - o) / d, (half - o) / d
        near = np.nanmax(np.minimum(t1, t2), axis=-1)
        far = np.nanmin(np.maximum(t1, t2), axis=-1)
        return np.where((near <= far) & (near > 0), near, np.inf)
    return test


def _cylinder_x(r, h):
    def test(o, d):  # x^2-free: y^2 + z^2 = r^2, |x| <= h / 2, with caps
        a = d[..., 1] ** 2 + d[..., 2] ** 2
        b = o[..., 1] * d[..., 1] + o[..., 2] * d[..., 2]
        c = o[..., 1] ** 2 + o[..., 2] ** 2 - r * r
        disc = b * b - a * c
        t = (-b - np.sqrt(np.maximum(disc, 0))) / np.where(a > 0, a, np.nan)
        x = o[..., 0] + t * d[..., 0]
        side = np.where((disc >= 0) & (t > 0) & (np.abs(x) <= h / 2), t, np.inf)
        caps = []
        for end in (-h / 2, h / 2):
            with np.errstate(divide="ignore", invalid="ignore"):
                tc = (end - o[..., 0]) / d[..., 0]
            y, z = o[..., 1] + tc * d[..., 1], o[..., 2] + tc * d[..., 2]
            caps.append(np.where((tc > 0) & (y * y + z * z <= r * r), tc, np.inf))
        return np.nanmin(np.stack([side, *caps]), axis=0)
    return test


CAMERA = Camera.look_at((0.5, 0.8, 6.0), (0.0, 0.2, 0.0), fov_y=50, near=0.5, far=20)


@pytest.mark.parametrize("engine", ["raster", "trace"])
def test_geometry_lands_where_a_ray_caster_over_pxrs_triangles_and_shapes_says(tmp_path,
                                                                                 engine):
    path = geometry_stage(tmp_path / "geo.usda")
    stage = Usd.Stage.Open(str(path))
    o, d = _rays(CAMERA, W, H)
    ts = [_hit_triangles(o, d, _triangles(stage.GetPrimAtPath("/World/Poly"))),
          _hit_object(o, d, _world(stage.GetPrimAtPath("/World/Cube")), _box(0.5)),
          _hit_object(o, d, _world(stage.GetPrimAtPath("/World/Sphere")), _sphere(0.6)),
          _hit_object(o, d, _world(stage.GetPrimAtPath("/World/Cyl")), _cylinder_x(0.3, 1.6))]
    t = np.min(ts, axis=0)
    which = np.argmin(ts, axis=0)
    forward = -CAMERA.view[2, :3]
    want = np.where(np.isfinite(t), t * (d @ forward), 0.0)  # depth along the view axis
    scene = facet.load(path)
    assert sorted(o.name for o in scene.objects) == ["Cube", "Cyl", "Poly", "Sphere"]
    with facet.Renderer(W, H) as r:
        got = r.render(scene, CAMERA, engine=engine, outputs=("depth",), aa="none").depth
    covered_both = (want > 0) & (got > 0)
    # Away from silhouettes (a pixel whose neighbours hit the same thing).
    inside = covered_both.copy()
    for axis in (0, 1):
        for s in (1, -1):
            inside &= np.roll(want > 0, s, axis) & (np.roll(which, s, axis) == which)
    assert ((want > 0) != (got > 0)).mean() < 0.02  # coverage: silhouettes only
    tol = 1e-3 if engine == "raster" else 1e-4  # the rasterizer tessellates the shapes
    err = np.abs(got - want)[inside] / want[inside]
    assert inside.sum() > 250 and np.quantile(err, 0.99) < tol, err.max()
    # Each piece is seen: the pentagon, the left-handed triangle, not the hole.
    for k in range(4):
        assert ((which == k) & inside).sum() > 10, k


def _variants(stage, path: str, name: str, kinds: dict) -> None:
    """A prim at ``path`` whose variant set ``name`` holds one gprim per variant (named
    after it, of ``kinds[variant]``); the first variant selected."""
    sets = stage.DefinePrim(path).GetVariantSets().AddVariantSet(name)
    for variant, kind in kinds.items():
        sets.AddVariant(variant)
        sets.SetVariantSelection(variant)
        with sets.GetVariantEditContext():
            kind.Define(stage, f"{path}/{variant}")
    sets.SetVariantSelection(next(iter(kinds)))


def test_composition_as_usd_defines_it(tmp_path):
    (tmp_path / "parts").mkdir()
    part = _stage(tmp_path / "parts" / "part.usda")
    UsdGeom.Cube.Define(part, "/Part/Box")
    part.SetDefaultPrim(part.GetPrimAtPath("/Part"))
    part.Save()
    heavy = _stage(tmp_path / "parts" / "heavy.usda")
    UsdGeom.Sphere.Define(heavy, "/Heavy/Ball")
    heavy.SetDefaultPrim(heavy.GetPrimAtPath("/Heavy"))
    heavy.Save()
    under = _stage(tmp_path / "under.usda")
    UsdGeom.Cone.Define(under, "/Under/Cone")
    under.Save()
    stage = _stage(tmp_path / "root.usda")
    stage.GetRootLayer().subLayerPaths.append("under.usda")
    ref = stage.DefinePrim("/World/Ref")
    ref.GetReferences().AddReference("parts/part.usda")
    pay = stage.DefinePrim("/World/Pay")
    pay.GetPayloads().AddPayload("parts/heavy.usda")
    _variants(stage, "/World/V", "shape", {"box": UsdGeom.Cube, "ball": UsdGeom.Sphere})
    off = UsdGeom.Cube.Define(stage, "/World/Off")
    off.GetPrim().SetActive(False)
    hidden = UsdGeom.Cube.Define(stage, "/World/Hidden")
    hidden.CreateVisibilityAttr("invisible")
    guide = UsdGeom.Cube.Define(stage, "/World/Guide")
    guide.CreatePurposeAttr("guide")
    proto = UsdGeom.Xform.Define(stage, "/Protos/Thing")
    UsdGeom.Mesh.Define(stage, "/Protos/Thing/Tri").CreatePointsAttr(
        [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    tri = UsdGeom.Mesh(stage.GetPrimAtPath("/Protos/Thing/Tri"))
    tri.CreateFaceVertexCountsAttr([3])
    tri.CreateFaceVertexIndicesAttr([0, 1, 2])
    stage.GetPrimAtPath("/Protos").SetSpecifier(Sdf.SpecifierClass)
    for k in range(2):
        inst = stage.DefinePrim(f"/World/Inst{k}")
        inst.GetReferences().AddInternalReference(proto.GetPath())
        inst.SetInstanceable(True)
        UsdGeom.Xformable(inst).AddTranslateOp().Set(Gf.Vec3d(3 * k, 0, 0))
    stage.Save()
    path = tmp_path / "root.usda"

    def names(**kw):
        return sorted(o.name for o in facet.load(path, **kw).objects)

    assert names() == ["Ball", "Box", "Cone", "Tri", "Tri", "box"]
    assert names(payloads=False) == ["Box", "Cone", "Tri", "Tri", "box"]
    assert names(variants={"shape": "ball"}) == ["Ball", "Box", "Cone", "Tri", "Tri", "ball"]
    assert "Guide" in names(purposes=("default", "render", "guide"))
    scene = facet.load(path)
    tris = [o for o in scene.objects if o.name == "Tri"]
    assert tris[0].mesh is tris[1].mesh  # one prototype, two placements
    assert not np.allclose(tris[0].transform, tris[1].transform)
    with pytest.raises(MeshError, match="no variant set 'colour'; the stage has shape: "
                                        "ball, box"):
        facet.load(path, variants={"colour": "red"})
    with pytest.raises(MeshError, match="variant set 'shape' has no variant 'cone'"):
        facet.load(path, variants={"shape": "cone"})
    with pytest.raises(facet.errors.InputError, match="not one"):
        facet.load(_obj(tmp_path), variants={"a": "b"})


def _obj(tmp_path):
    p = tmp_path / "t.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return p


def test_the_guard_holds_for_everything_a_stage_reaches(tmp_path):
    inside = tmp_path / "in"
    inside.mkdir()
    outside = _stage(tmp_path / "secret.usda")
    UsdGeom.Cube.Define(outside, "/S")
    outside.Save()
    stage = _stage(inside / "a.usda")
    stage.DefinePrim("/R").GetReferences().AddReference("../secret.usda", "/S")
    stage.Save()
    with pytest.raises(MeshError, match="secret.usda"):
        facet.load(inside / "a.usda", confine=inside)
    facet.load(inside / "a.usda")  # unconfined: read
    # a device named as a layer: refused, never opened
    dev = _stage(tmp_path / "dev.usda")
    dev.GetRootLayer().subLayerPaths.append("/dev/zero")
    dev.Save()
    with pytest.raises(MeshError, match="/dev/zero"):
        facet.load(tmp_path / "dev.usda")
    # a reference cycle: composed as pxr composes it, said in one line each
    a, b = _stage(tmp_path / "ca.usda"), _stage(tmp_path / "cb.usda")
    a.DefinePrim("/X").GetReferences().AddReference("cb.usda", "/X")
    b.DefinePrim("/X").GetReferences().AddReference("ca.usda", "/X")
    UsdGeom.Cube.Define(a, "/Y")
    a.Save()
    b.Save()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        scene = facet.load(tmp_path / "ca.usda")
    assert [o.name for o in scene.objects] == ["Y"]
    assert any("cycle" in str(w.message).lower() for w in said), [str(w.message)
                                                                    for w in said]
    # a .usdz whose member is compressed: refused (USDZ stores its members)
    with zipfile.ZipFile(tmp_path / "bad.usdz", "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("a.usda", "#usda 1.0\n" + "\n" * 1000)
    with pytest.raises(MeshError, match="compressed"):
        facet.load(tmp_path / "bad.usdz")


def test_a_missing_usd_extra_is_one_line(tmp_path):
    """Without usd-core: one line naming the extra (run in a fresh interpreter that cannot
    import pxr)."""
    path = geometry_stage(tmp_path / "g.usda")
    code = ("import sys; sys.modules['pxr'] = None\n"
            "from facet.cli import main\n"
            f"sys.exit(main(['render', {str(path)!r}, '-o', {str(tmp_path / 'o.png')!r}]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 2
    assert "pip install 'facet-render[usd]'" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o.png").exists()


def _surface_stage(path, light: str):
    """A plane facing +z with a UsdPreviewSurface, lit by one light."""
    stage = _stage(path)
    plane = UsdGeom.Mesh.Define(stage, "/World/Plane")
    plane.CreatePointsAttr([(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)])
    plane.CreateFaceVertexCountsAttr([4])
    plane.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    plane.CreateSubdivisionSchemeAttr("none")
    mat = UsdShade.Material.Define(stage, "/World/Mat")
    shader = UsdShade.Shader.Define(stage, "/World/Mat/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set((0.6, 0.3, 0.1))
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.7)
    shader.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(0.0)
    mat.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(plane.GetPrim()).Bind(mat)
    if light == "distant":
        lt = UsdLux.DistantLight.Define(stage, "/World/Sun")
        lt.CreateIntensityAttr(3.0)
        lt.CreateNormalizeAttr(True)
        lt.CreateColorAttr((1.0, 0.9, 0.8))
        UsdGeom.Xformable(lt).AddRotateXYZOp().Set(Gf.Vec3f(-20, 0, 0))
    else:
        lt = UsdLux.SphereLight.Define(stage, "/World/Bulb")
        lt.CreateIntensityAttr(40.0)
        lt.CreateRadiusAttr(0.1)
        lt.CreateExposureAttr(1.0)
        UsdGeom.Xformable(lt).AddTranslateOp().Set(Gf.Vec3d(0.5, 0.3, 2.0))
    stage.Save()
    return path


@pytest.mark.parametrize("light", ["distant", "sphere"])
def test_preview_surface_and_lights_match_the_same_scene_built_with_facets_api(tmp_path,
                                                                              light):
    """The loader's material and light against facet's own: base colour = diffuseColor,
    a normalized distant light's irradiance E = intensity (facet I = E / pi, along its -z
    turned by -20 degrees about x), a sphere light of radiance L = 40 x 2^1 and radius r a
    facet SphereLight of I = L r^2 with inverse-square falloff (the path tracer's emitting
    sphere, the others' points of it); the three engines agree."""
    from facet.scene.light import DirectionalLight, SphereLight
    from facet.scene.pbr import PbrMaterial

    scene = facet.load(_surface_stage(tmp_path / "s.usda", light))
    built = facet.Scene()
    built.add(facet.Mesh(np.array([(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0.0)]),
                         np.array([[0, 1, 2], [0, 2, 3]])),
              PbrMaterial(base_color=(0.6, 0.3, 0.1, 1), roughness=0.7, metallic=0.0))
    if light == "distant":
        a = np.radians(-20)
        built.add_light(DirectionalLight(direction=(0, -np.sin(a) * -1, -np.cos(a)),
                                         color=(1, 0.9, 0.8), intensity=3.0 / np.pi))
    else:
        built.add_light(SphereLight(position=(0.5, 0.3, 2.0), intensity=80.0 * 0.01,
                                    attenuation=(0, 0, 1), radius=0.1))
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=30)
    pictures = {}
    with facet.Renderer(32, 32) as r:
        for e in ("raster", "trace", "path"):
            kw = dict(spp=16) if e == "path" else {}
            got = r.render(scene, cam, engine=e, lights="scene", float_color=True, **kw)
            want = r.render(built, cam, engine=e, lights="scene", float_color=True, **kw)
            np.testing.assert_allclose(got.color, want.color, rtol=1e-4, atol=1e-5)
            pictures[e] = got.color[..., :3]
    assert pictures["raster"].mean() > 0.05  # lit
    np.testing.assert_allclose(pictures["trace"], pictures["raster"], rtol=0.02, atol=0.01)
    if light == "sphere":  # without facet's ambient term (each engine's own): the path
        scene.ambient = np.zeros(3)  # tracer's emitting sphere lights the plane as the
        with facet.Renderer(32, 32) as r:  # rasterizer's point at its centre does
            a, b = (np.median(r.render(scene, cam, engine=e, lights="scene", float_color=True,
                                       **kw).color[..., :3])
                    for e, kw in (("raster", {}), ("path", dict(spp=64))))
        assert b == pytest.approx(a, rel=0.03)


def test_a_camera_is_the_pinhole_its_focal_length_and_aperture_make(tmp_path):
    stage = _stage(tmp_path / "c.usda")
    cam = UsdGeom.Camera.Define(stage, "/Cam")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateVerticalApertureAttr(20.25)
    cam.CreateHorizontalApertureAttr(36.0)
    cam.CreateClippingRangeAttr(Gf.Vec2f(0.5, 50))
    UsdGeom.Xformable(cam).AddTranslateOp().Set(Gf.Vec3d(0, 0, 8))
    ball = UsdGeom.Sphere.Define(stage, "/Ball")
    ball.CreateRadiusAttr(0.1)
    UsdGeom.Xformable(ball).AddTranslateOp().Set(Gf.Vec3d(1.2, 0.7, 0))
    stage.Save()
    scene = facet.load(tmp_path / "c.usda")
    c = scene.cameras["Cam"]
    assert c.fov_y == pytest.approx(np.degrees(2 * np.arctan(20.25 / 2 / 35.0)), rel=1e-9)
    assert (c.near, c.far) == pytest.approx((0.5, 50))
    w, h = 128, 72  # the aperture's 16:9
    with facet.Renderer(w, h) as r:
        ids = r.render(scene, c, outputs=("ids",), aa="none").object_ids
    rows, cols = np.nonzero(ids >= 0)
    f = h / 2 / np.tan(np.radians(c.fov_y) / 2)  # pixels
    u, v = w / 2 + f * 1.2 / 8, h / 2 - f * 0.7 / 8  # the ball's centre, projected
    assert abs(cols.mean() + 0.5 - u) < 0.3 and abs(rows.mean() + 0.5 - v) < 0.3


def test_the_command_line_renders_describes_and_chooses_variants(tmp_path, capsys):
    from facet.cli import main

    stage = _stage(tmp_path / "v.usda")
    _variants(stage, "/V", "look", {"cube": UsdGeom.Cube, "ball": UsdGeom.Sphere})
    UsdLux.DistantLight.Define(stage, "/Sun")
    stage.Save()
    path = tmp_path / "v.usda"
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "usd variant sets       look = cube of ball, cube" in out
    assert "usd lights             /Sun" in out
    from PIL import Image

    shots = []
    for variant in ("look=cube", "look=ball"):
        png = tmp_path / f"{variant}.png"
        assert main(["render", str(path), "--variant", variant, "--size", "48x48", "-o",
                     str(png), "-q"]) == 0
        shots.append(np.asarray(Image.open(png).convert("L")) > 10)
    assert shots[0].mean() > 0.05 and shots[1].mean() > 0.05  # something drawn, each
    assert (shots[0] != shots[1]).mean() > 0.02  # a cube's outline is not a ball's
    assert main(["render", str(path), "--variant", "look=cone", "-o",
                 str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "variant set 'look' has no variant 'cone'; it has ball, cube" in err
    assert "Traceback" not in err and not (tmp_path / "x.png").exists()
    assert main(["render", str(path), "--purpose", "everything", "-o",
                 str(tmp_path / "y.png")]) == 2


def test_every_shared_stage_opens_or_is_refused_in_one_line():
    """The USD Working Group's 119 stages: each opens (its problems said in warning lines)
    or is refused in one line naming why (two author an invalid framesPerSecond; two draw
    nothing, as any other empty model: a mesh without points or faces, and a layer of
    materials alone, made to be sublayered)."""
    from conftest import ROOT

    folder = ROOT.parent / "shared" / "usd"
    if not folder.is_dir():
        pytest.skip("../shared/usd is not here")
    files = sorted(p for p in folder.rglob("*") if p.suffix in (".usd", ".usda", ".usdc",
                                                                ".usdz"))
    assert len(files) >= 119
    refused = []
    for p in files:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FacetWarning)
            try:
                facet.load(p)
            except MeshError as exc:
                assert "\n" not in str(exc) and "Traceback" not in str(exc)
                refused.append(p.name)
    assert sorted(refused) == ["empty.usda", "framesPerSecond_-1.usda",
                               "framesPerSecond_0.usda", "hardware.shading.usda"], refused


def test_time_samples_move_parts_and_cameras_through_time(tmp_path):
    """translate {0: 0, 48: 4} at 24 codes a second: 2 units at t = 1 s (``Scene.at``, the
    renderers' ``time``); a camera's samples move it likewise; what does not move stays."""
    stage = _stage(tmp_path / "t.usda")
    stage.SetTimeCodesPerSecond(24)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(48)
    box = UsdGeom.Cube.Define(stage, "/Box")
    op = UsdGeom.Xformable(box).AddTranslateOp()
    op.Set(Gf.Vec3d(0, 0, 0), 0)
    op.Set(Gf.Vec3d(4, 0, 0), 48)
    still = UsdGeom.Sphere.Define(stage, "/Still")
    UsdGeom.Xformable(still).AddTranslateOp().Set(Gf.Vec3d(0, 3, 0))
    cam = UsdGeom.Camera.Define(stage, "/Cam")
    cop = UsdGeom.Xformable(cam).AddTranslateOp()
    cop.Set(Gf.Vec3d(0, 0, 10), 0)
    cop.Set(Gf.Vec3d(0, 0, 20), 48)
    stage.Save()
    scene = facet.load(tmp_path / "t.usda")
    at = scene.at(1.0)
    moved = {o.name: o.transform[:3, 3] for o in at.objects}
    np.testing.assert_allclose(moved["Box"], [2, 0, 0], atol=1e-9)
    np.testing.assert_allclose(moved["Still"], [0, 3, 0], atol=1e-9)
    np.testing.assert_allclose(at.cameras["Cam"].eye, [0, 0, 15], atol=1e-9)
    wide = Camera.look_at((2, 0, 12), (2, 0, 0), fov_y=50)
    with facet.Renderer(32, 32) as r:  # the renderers pose it by their time option
        a = r.render(scene, wide, time=0.0, outputs=("ids",)).object_ids
        b = r.render(scene, wide, time=2.0, outputs=("ids",)).object_ids
    box_id = next(o.id for o in scene.objects if o.name == "Box")
    assert np.nonzero(b == box_id)[1].mean() > np.nonzero(a == box_id)[1].mean() + 4


def test_planes_point_instancers_domes_and_cameras_by_name(tmp_path):
    """A Plane gprim is a bounded plane facing its axis; a PointInstancer places one
    prototype (made once) at each position; a DomeLight is the environment (a constant
    dome of its emission, or its latitude-longitude texture times it); --camera picks a
    stage camera by name."""
    from PIL import Image

    from facet.cli import main

    stage = _stage(tmp_path / "p.usda")
    plane = UsdGeom.Plane.Define(stage, "/Floor")
    plane.CreateWidthAttr(4.0)
    plane.CreateLengthAttr(2.0)
    plane.CreateAxisAttr("Y")
    inst = UsdGeom.PointInstancer.Define(stage, "/Many")
    UsdGeom.Sphere.Define(stage, "/Many/Protos/Ball").CreateRadiusAttr(0.2)
    inst.CreatePrototypesRel().SetTargets(["/Many/Protos/Ball"])
    inst.CreateProtoIndicesAttr([0, 0, 0])
    inst.CreatePositionsAttr([(-1, 0.5, 0), (0, 0.5, 0), (1, 0.5, 0)])
    dome = UsdLux.DomeLight.Define(stage, "/Sky")
    dome.CreateIntensityAttr(0.5)
    dome.CreateColorAttr((1.0, 0.5, 0.25))
    cam = UsdGeom.Camera.Define(stage, "/Top")
    UsdGeom.Xformable(cam).AddTranslateOp().Set(Gf.Vec3d(0, 0, 6))
    stage.Save()
    scene = facet.load(tmp_path / "p.usda")
    floor = next(o for o in scene.objects if o.name == "Floor")
    lo, hi = floor.mesh.bounds
    assert np.allclose(hi - lo, [4, 0, 2], atol=1e-6)  # width along x, length along z
    balls = [o for o in scene.objects if o.name.startswith("Ball")]
    assert len(balls) == 3 and balls[0].mesh is balls[2].mesh
    assert sorted(round(b.transform[0, 3], 6) for b in balls) == [-1, 0, 1]
    np.testing.assert_allclose(scene.environment.faces[0, 0, 0, :3], [0.5, 0.25, 0.125])
    Image.fromarray(np.full((8, 16, 3), [255, 0, 0], np.uint8)).save(tmp_path / "red.png")
    dome.CreateTextureFileAttr("red.png")
    stage.Save()
    textured = facet.load(tmp_path / "p.usda").environment
    np.testing.assert_allclose(textured.faces[..., :3].mean(axis=(0, 1, 2)), [0.5, 0, 0],
                               atol=1e-3)
    png = tmp_path / "top.png"
    assert main(["render", str(tmp_path / "p.usda"), "--camera", "Top", "--size", "32x32",
                 "-q", "-o", str(png)]) == 0
    top = np.asarray(Image.open(png).convert("RGB")).astype(int)
    # From (0, 0, 6) down -z through USD's default 50 mm lens (17.4 degrees): the middle
    # ball, above the image's centre (the others are outside the view).
    drawn = np.abs(top - top[0, 0]).sum(axis=-1) > 30
    rows, cols = np.nonzero(drawn)
    assert drawn.sum() > 6 and rows.mean() < 14 and abs(cols.mean() - 15.5) < 1


def test_subdivision_surfaces_refine_on_request():
    """Catmull-Clark's first level of a cube of side 2, by its rules: face points at the
    faces' centres, edge point (0.75, 0.75, 0), corner (5/9, 5/9, 5/9); 24 quads. A stage's
    catmullClark mesh is its cage by default and refined with subdivide=N (the Loop scheme
    on triangles through trimesh)."""
    from facet.formats.subdivide import catmull_clark

    corners = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1.0)])
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4],
             [1, 5, 7, 3]]
    pts, out = catmull_clark(corners, np.full(6, 4), np.array(quads).reshape(-1))
    assert out.shape == (24, 4) and len(pts) == 8 + 12 + 6
    found = {tuple(np.round(p, 6)) for p in pts}
    assert (1.0, 0.0, 0.0) in found and (0.75, 0.75, 0.0) in found
    assert tuple(np.round([5 / 9] * 3, 6)) in found


CUBE_MESH = """#usda 1.0
def Mesh "{name}"
{{
    int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
    int[] faceVertexIndices = [0, 1, 3, 2, 4, 6, 7, 5, 0, 4, 5, 1, 2, 3, 7, 6, 0, 2, 6, 4,
                               1, 5, 7, 3]
    point3f[] points = [(-1, -1, -1), (-1, -1, 1), (-1, 1, -1), (-1, 1, 1), (1, -1, -1),
                        (1, -1, 1), (1, 1, -1), (1, 1, 1)]
    {scheme}
}}
"""


def test_a_stage_subdivides_its_catmull_clark_meshes_when_asked(tmp_path):
    (tmp_path / "s.usda").write_text(CUBE_MESH.format(name="Box", scheme=""))
    cage = facet.load(tmp_path / "s.usda").objects[0].mesh
    smooth = facet.load(tmp_path / "s.usda", subdivide=3).objects[0].mesh
    assert cage.face_count == 12 and smooth.face_count == 6 * 4 ** 3 * 2
    r = np.linalg.norm(smooth.positions, axis=1)
    assert r.max() < np.sqrt(3) - 0.3 and r.min() > 0.75  # rounder than the cage


def test_mesh_load_merges_a_stages_meshes_and_shapes(tmp_path):
    """Mesh.load of a stage: its meshes and its exact shapes (tessellated) in one mesh."""
    path = geometry_stage(tmp_path / "geo.usda")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FacetWarning)  # (their materials differ: said)
        mesh = facet.Mesh.load(path)
    scene = facet.load(path)
    assert mesh.face_count == sum(o.mesh.face_count for o in scene.objects)


def test_a_stage_of_zero_time_codes_per_second_is_drawn_still(tmp_path):
    """timeCodesPerSecond = 0 with time samples (pxr's time-sample queries never return
    on such a stage: facet does not ask them): drawn at its default time, said."""
    stage = _stage(tmp_path / "z.usda")
    stage.SetTimeCodesPerSecond(0)
    box = UsdGeom.Cube.Define(stage, "/Box")
    op = UsdGeom.Xformable(box).AddTranslateOp()
    op.Set(Gf.Vec3d(0, 0, 0), 0)
    op.Set(Gf.Vec3d(4, 0, 0), 10)
    stage.Save()
    with pytest.warns(FacetWarning, match="timeCodesPerSecond is 0: the stage is drawn at "
                                          "its default time"):
        scene = facet.load(tmp_path / "z.usda")
    assert scene.animations == [] and len(scene.objects) == 1


def test_a_dome_turns_with_its_prim_and_its_pole_follows_a_z_up_stage(tmp_path):
    """A dome's texture (red where x < 0 in its frame) turned 180 degrees about y: red on
    +x, times its intensity, in the cube every engine draws and in the grid the path
    tracer samples alike (the grid once kept the texture's unscaled values). A
    DomeLight_1 on a z-up stage (poleAxis "scene", its default): the texture's upper half
    (its +y) lies on +z."""
    from PIL import Image

    half = np.zeros((16, 32, 3), np.uint8)
    half[:, :16] = (255, 0, 0)  # u < 0.5: x < 0
    Image.fromarray(half).save(tmp_path / "half.png")
    top = np.zeros((16, 32, 3), np.uint8)
    top[:8] = (0, 0, 255)  # v < 0.5: y > 0
    Image.fromarray(top).save(tmp_path / "top.png")
    stage = _stage(tmp_path / "d.usda")
    UsdGeom.Cube.Define(stage, "/Box")
    dome = UsdLux.DomeLight.Define(stage, "/Sky")
    dome.CreateTextureFileAttr("half.png")
    dome.CreateIntensityAttr(0.5)  # the cube and the grid both carry it
    UsdGeom.Xformable(dome).AddRotateYOp().Set(180.0)
    stage.Save()
    env = facet.load(tmp_path / "d.usda").environment
    assert env.faces[0, ..., 0].mean() == pytest.approx(0.5) and env.faces[1, ..., 0].max() == 0
    h, w = env.equirect.shape[:2]
    assert env.equirect[:, 3 * w // 4, 0].mean() == pytest.approx(0.5)  # u = 0.75: +x
    assert env.equirect[:, w // 4, 0].max() == 0
    zup = Usd.Stage.CreateNew(str(tmp_path / "z.usda"))
    UsdGeom.SetStageUpAxis(zup, UsdGeom.Tokens.z)
    UsdGeom.Cube.Define(zup, "/Box")
    d1 = UsdLux.DomeLight_1.Define(zup, "/Sky")
    d1.CreateTextureFileAttr("top.png")
    zup.Save()
    env = facet.load(tmp_path / "z.usda").environment
    assert env.faces[4, ..., 2].mean() > 0.99 and env.faces[5, ..., 2].mean() < 0.01  # +z


def test_rect_light_textures_and_specular_colour_textures(tmp_path):
    """A textured RectLight is a rectangle of its texture's mean linear colour (said); a
    specular-workflow surface's specularColor texture fills KHR_materials_specular's
    colour slot (F0 = the texture: 0.04 x 25)."""
    from PIL import Image

    from facet.srgb import srgb_to_linear

    tex = np.zeros((4, 4, 3), np.uint8)
    tex[:, :2] = (200, 100, 0)
    Image.fromarray(tex).save(tmp_path / "glow.png")
    stage = _stage(tmp_path / "r.usda")
    UsdGeom.Cube.Define(stage, "/Box")
    rect = UsdLux.RectLight.Define(stage, "/Panel")
    rect.CreateTextureFileAttr("glow.png")
    rect.CreateIntensityAttr(2.0)
    box = stage.GetPrimAtPath("/Box")
    mat = UsdShade.Material.Define(stage, "/Mat")
    shader = UsdShade.Shader.Define(stage, "/Mat/S")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("useSpecularWorkflow", Sdf.ValueTypeNames.Int).Set(1)
    t = UsdShade.Shader.Define(stage, "/Mat/T")
    t.CreateIdAttr("UsdUVTexture")
    t.CreateInput("file", Sdf.ValueTypeNames.Asset).Set("glow.png")
    shader.CreateInput("specularColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        t.ConnectableAPI(), "rgb")
    mat.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(box).Bind(mat)
    stage.Save()
    with pytest.warns(FacetWarning, match="uniform rectangle of its texture's mean colour"):
        scene = facet.load(tmp_path / "r.usda")
    mean = srgb_to_linear(np.array([200, 100, 0]) / 255.0) / 2
    light = scene.lights[0]
    np.testing.assert_allclose(light.color * light.intensity * np.pi,
                               2.0 * mean, rtol=1e-5)  # I = L w h / pi, 1 x 1
    m = scene.objects[0].material
    assert m.specular_color_texture is not None and m.metallic == 0
    np.testing.assert_allclose(m.specular_color, 25.0)


def test_time_sampled_points_move_as_usd_interpolates_them(tmp_path):
    """A quad whose points are sampled at codes 0 and 24 (24 a second): halfway at 0.5 s
    (a morph target per code, weighed by the time rig), at the last sample after it."""
    stage = _stage(tmp_path / "p.usda")
    stage.SetTimeCodesPerSecond(24)
    quad = UsdGeom.Mesh.Define(stage, "/Quad")
    quad.CreateFaceVertexCountsAttr([4])
    quad.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    points = quad.CreatePointsAttr()
    flat = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    points.Set(flat, 0)
    points.Set([(0, 0, 0), (1, 0, 0), (1, 1, 2), (0, 1, 2)], 24)
    stage.Save()
    with pytest.warns(FacetWarning, match="time-sampled points move with their normals at "
                                          "rest"):
        scene = facet.load(tmp_path / "p.usda")
    assert scene.animations == ["stage"]
    for t, z in ((0.0, 0.0), (0.5, 1.0), (1.0, 2.0), (3.0, 2.0)):
        mesh = scene.at(t).objects[0].mesh
        top = mesh.positions[mesh.positions[:, 1] > 0.5]
        np.testing.assert_allclose(top[:, 2], z, atol=1e-6)


def test_cubic_curves_and_varying_point_widths_are_said(tmp_path):
    """What facet draws more simply than the file asks is one warning line each: cubic
    curves as lines through their control points, points of varying widths at the
    first width."""
    stage = _stage(tmp_path / "c.usda")
    curves = UsdGeom.BasisCurves.Define(stage, "/Hair")
    curves.CreatePointsAttr([(0, 0, 0), (1, 1, 0), (2, 0, 0), (3, 1, 0)])
    curves.CreateCurveVertexCountsAttr([4])
    curves.CreateTypeAttr("cubic")
    pts = UsdGeom.Points.Define(stage, "/Dust")
    pts.CreatePointsAttr([(0, 2, 0), (1, 2, 0)])
    pts.CreateWidthsAttr([0.1, 0.3])
    stage.Save()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        scene = facet.load(tmp_path / "c.usda")
    lines = [str(w.message) for w in said]
    assert any("/Hair: cubic curves are drawn as lines through their control points" in x
               for x in lines)
    assert any("/Dust: its points' widths vary; all are drawn at the first, 0.1" in x
               for x in lines)
    hair = next(o for o in scene.objects if o.name == "Hair")
    assert len(hair.mesh.segments) == 3


def test_time_sampled_visibility_shows_and_hides_parts_through_time(tmp_path):
    """visibility {0: invisible, 24: inherited} on a parent and {0: inherited, 48:
    invisible} on another prim: hidden, then shown at t = 1 s, then hidden at 2 s (held
    between codes, as USD holds a token); a render at its default time draws the start."""
    stage = _stage(tmp_path / "v.usda")
    stage.SetTimeCodesPerSecond(24)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(48)
    group = UsdGeom.Xform.Define(stage, "/Late")
    UsdGeom.Cube.Define(stage, "/Late/Box")
    vis = UsdGeom.Imageable(group).CreateVisibilityAttr()
    vis.Set(UsdGeom.Tokens.invisible, 0)
    vis.Set(UsdGeom.Tokens.inherited, 24)
    ball = UsdGeom.Sphere.Define(stage, "/Gone")
    UsdGeom.Xformable(ball).AddTranslateOp().Set(Gf.Vec3d(3, 0, 0))
    gone = ball.CreateVisibilityAttr()
    gone.Set(UsdGeom.Tokens.inherited, 0)
    gone.Set(UsdGeom.Tokens.invisible, 48)
    stage.Save()
    scene = facet.load(tmp_path / "v.usda")
    cam = Camera.look_at((1.5, 0, 12), (1.5, 0, 0), fov_y=40)
    ids = {o.name: o.id for o in scene.objects}
    seen = {}
    with facet.Renderer(48, 32) as r:
        for t in (None, 0.0, 0.5, 1.0, 1.9, 2.0, 3.0):
            kw = {} if t is None else {"time": t}
            got = r.render(scene, cam, outputs=("ids",), **kw).object_ids
            seen[t] = {name for name, i in ids.items() if (got == i).any()}
    assert seen == {None: {"Gone"}, 0.0: {"Gone"}, 0.5: {"Gone"}, 1.0: {"Box", "Gone"},
                    1.9: {"Box", "Gone"}, 2.0: {"Box"}, 3.0: {"Box"}}
    with facet.Renderer(48, 32, engine="trace") as r:
        got = r.render(scene, cam, outputs=("ids",), time=1.0).object_ids
    assert {name for name, i in ids.items() if (got == i).any()} == {"Box", "Gone"}


@pytest.mark.parametrize("ortho", [False, True])
def test_aperture_offsets_shift_the_window_as_pxrs_frustum_does(tmp_path, ortho):
    """A camera with horizontal and vertical aperture offsets projects every point where
    pxr's own frustum (Gf.Camera.frustum) does, and a ball lands in the pixel its shifted
    pinhole (K's cx, cy) gives, in the rasterizer and the Whitted tracer."""
    stage = _stage(tmp_path / "o.usda")
    cam = UsdGeom.Camera.Define(stage, "/Cam")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateHorizontalApertureAttr(36.0)
    cam.CreateVerticalApertureAttr(20.25)
    cam.CreateHorizontalApertureOffsetAttr(4.0)
    cam.CreateVerticalApertureOffsetAttr(-2.5)
    if ortho:
        cam.CreateProjectionAttr(UsdGeom.Tokens.orthographic)
    cam.CreateClippingRangeAttr(Gf.Vec2f(0.5, 50))
    _xform(cam.GetPrim(), (0.3, 0.2, 8), (5, 10, 0))
    ball = UsdGeom.Sphere.Define(stage, "/Ball")
    ball.CreateRadiusAttr(0.15)
    UsdGeom.Xformable(ball).AddTranslateOp().Set(Gf.Vec3d(0.9, 0.1, 0))
    stage.Save()
    c = facet.load(tmp_path / "o.usda").cameras["Cam"]
    w, h = 128, 72  # the aperture's 16:9, as pxr's frustum's window
    frustum = cam.GetCamera(Usd.TimeCode.Default()).frustum
    theirs = np.array(frustum.ComputeViewMatrix() * frustum.ComputeProjectionMatrix()).T
    ours = c.projection(w, h) @ c.view
    pts = np.array([[0.9, 0.1, 0, 1], [-1, 1, -2, 1], [2, 0.5, 3, 1], [0, 0, 0, 1.0]])

    def ndc(m):
        clip = pts @ m.T
        return clip[:, :3] / clip[:, 3:]

    np.testing.assert_allclose(ndc(ours), ndc(theirs), atol=1e-6)
    centre = ((ndc(ours)[0, :2] * [1, -1] + 1) / 2) * [w, h]  # the ball, in pixels
    if not ortho:
        k = c.K(w, h)
        cv = (facet.geometry.intrinsics.CV_TO_GL @ c.view @ pts[0])[:3]
        np.testing.assert_allclose((k @ cv)[:2] / cv[2] + 0.5, centre, atol=1e-6)
    for engine in ("raster", "trace"):
        with facet.Renderer(w, h, engine=engine) as r:
            ids = r.render(facet.load(tmp_path / "o.usda"), c, outputs=("ids",),
                           aa="none").object_ids
        rows, cols = np.nonzero(ids >= 0)
        assert abs(cols.mean() + 0.5 - centre[0]) < 0.3, engine
        assert abs(rows.mean() + 0.5 - centre[1]) < 0.3, engine


def test_a_skinned_stage_is_drawn_at_its_bind_pose_with_one_line(tmp_path):
    """UsdSkel is not applied: the skinned mesh is drawn where its points are authored,
    and one warning line says so (not one per skeleton or mesh)."""
    from pxr import UsdSkel

    stage = _stage(tmp_path / "skel.usda")
    for name in ("A", "B"):
        root = UsdSkel.Root.Define(stage, f"/{name}")
        skel = UsdSkel.Skeleton.Define(stage, f"/{name}/Skel")
        skel.CreateJointsAttr(["hip"])
        skel.CreateBindTransformsAttr([Gf.Matrix4d(1)])
        skel.CreateRestTransformsAttr([Gf.Matrix4d(1)])
        mesh = UsdGeom.Mesh.Define(stage, f"/{name}/Body")
        mesh.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
        mesh.CreateFaceVertexCountsAttr([3])
        mesh.CreateFaceVertexIndicesAttr([0, 1, 2])
        binding = UsdSkel.BindingAPI.Apply(mesh.GetPrim())
        binding.CreateSkeletonRel().SetTargets([skel.GetPath()])
        assert root
    stage.Save()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = facet.load(tmp_path / "skel.usda")
    said = [str(w.message) for w in caught if "UsdSkel" in str(w.message)]
    assert len(said) == 1 and "bind pose" in said[0]
    np.testing.assert_allclose(scene.objects[0].mesh.positions.max(0), [1, 1, 0])


def test_points_of_another_type_than_point3f_are_left_out_as_hydra_leaves_them(tmp_path):
    """A mesh whose points are authored as int[] or double3[] (not the schema's point3f[];
    float3[] and color3f[] hold the same floats) is left out with a line naming the type,
    as usdrecord draws only the float-triple ones (schemaTests' pointsTypes)."""
    cube = ("int[] faceVertexCounts = [3, 3]\n        int[] faceVertexIndices = [0, 1, 2, 0, 2, "
            "3]\n        {kind} points = {value}\n")
    square = "[(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]"
    meshes = {"good": ("point3f[]", square), "colour": ("color3f[]", square),
              "ints": ("int[]", "[0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]"),
              "doubles": ("double3[]", square)}
    text = "#usda 1.0\n" + "".join(
        f'def Mesh "{name}"\n{{\n        {cube.format(kind=k, value=v)}}}\n'
        for name, (k, v) in meshes.items())
    (tmp_path / "p.usda").write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = facet.load(tmp_path / "p.usda")
    assert [o.name for o in scene.objects] == ["good", "colour"]
    said = [str(w.message) for w in caught]
    assert any("/ints: its points are authored as IntArray" in m for m in said)
    assert any("/doubles: its points are authored as Vec3dArray" in m for m in said)


def test_meshes_without_normals_shade_as_hydra_shades_them(tmp_path):
    """No authored normals: a subdivision surface's cage (catmullClark, the schema's
    default, or loop) is shaded smooth, a polygonal mesh (none, bilinear) flat, as Storm
    does (schemaTests' subdiv screenshots); the tracers bend the cage's far-leaning normals
    continuously (no edge where the bend begins)."""
    normals = {}
    for name, scheme in (("cage", ""), ("poly", 'uniform token subdivisionScheme = "none"')):
        (tmp_path / f"{name}.usda").write_text(CUBE_MESH.format(name=name, scheme=scheme))
        mesh = facet.load(tmp_path / f"{name}.usda").objects[0].mesh
        normals[name] = np.asarray(mesh.normals)
        positions = np.asarray(mesh.positions)
    cage = facet.load(tmp_path / "cage.usda").objects[0].mesh
    np.testing.assert_allclose(normals["cage"], np.asarray(cage.positions) / np.sqrt(3),
                               atol=1e-6)  # each corner's normal along its diagonal
    assert np.allclose(np.abs(normals["poly"]).max(axis=1), 1.0)  # one axis each
    assert len(positions) == 36  # (a vertex a triangle corner: flat)
    with facet.Renderer(160, 120, engine="trace") as r:  # framed from the front-right
        frame = r.render(facet.load(tmp_path / "cage.usda"), aa="none",
                         outputs=("color", "position", "ids"))
    grey = frame.color[..., :3].astype(float).mean(axis=2)
    front = (frame.object_ids >= 0) & (np.abs(frame.position[..., 2] - 1) < 1e-3)
    for _ in range(3):  # (away from the face's edges)
        front &= np.roll(front, 1, 1) & np.roll(front, -1, 1) & np.roll(front, 1, 0) & \
            np.roll(front, -1, 0)
    step = np.maximum(np.abs(np.diff(grey, axis=1, append=grey[:, -1:])),
                      np.abs(np.diff(grey, axis=0, append=grey[-1:])))
    # (the stepwise bend left a ring of 21 levels where it began; now a gradient)
    assert front.sum() > 2000 and step[front].max() < 8, step[front].max()


def test_a_crease_angle_given_for_a_stage_says_where_it_applies(tmp_path):
    """--crease / crease= does not change how a stage's meshes without normals shade
    (Storm's rule decides): one line says so, not a silently ignored option."""
    (tmp_path / "c.usda").write_text(CUBE_MESH.format(name="cage", scheme=""))
    with pytest.warns(FacetWarning, match="crease angle applies to meshes refined"):
        scene = facet.load(tmp_path / "c.usda", crease=10)
    np.testing.assert_allclose(np.abs(scene.objects[0].mesh.normals), 1 / np.sqrt(3),
                               atol=1e-6)  # (still the smooth cage)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        facet.load(tmp_path / "c.usda", crease=10, subdivide=1)  # (used there: no line)

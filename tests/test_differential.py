"""The differential harness: every model of ../shared/gltf through every engine, comparing
what must agree, so that "never silent" is mechanical.

* First-hit channels: coverage, object ids, depth and normals of the rasterizer, the
  Whitted tracer and the path tracer agree away from silhouettes; the base colour (each
  engine's "unlit" picture: factor x texture x vertex colour) of the rasterizer and the
  Whitted tracer too.
* Direct light: the path tracer at max_depth 0 (light straight from the lights, with
  shadow rays) against the rasterizer's BRDF under the same punctual lights (with shadow
  maps), on opaque surfaces: the two evaluate one layered BRDF (glsl/lib/layers.glsl).
* Features: a material feature of the file that changes the rasterizer's picture when it
  is taken away must change each tracer's too, or that tracer names it in a warning line;
  and every feature an engine's capability table leaves out is named when present.

Small pictures, one sample: the harness checks agreement, not beauty. Each model's row of
what it caught is in the failure message.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

import facet
from facet.render.capabilities import CAPABILITIES, material_features

from conftest import SHARED_GLTF

MODELS = sorted(p.parent.name for p in SHARED_GLTF.glob("*/*.gl*")) if SHARED_GLTF.is_dir() \
    else []
REFUSED = {"IridescenceSuzanne"}  # requires KHR_materials_iridescence (test_gltf_corpus)
ENGINES = ("raster", "trace", "path")
SIZE = 40
needs_models = pytest.mark.skipif(not MODELS, reason=f"the shared glTF models are absent "
                                                     f"({SHARED_GLTF})")


def _load(name):
    path = next(p for p in sorted((SHARED_GLTF / name).glob("*.gl*")))
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        scene = facet.load(path)
    return scene, [str(w.message) for w in said]


def _render(r, scene, engine, aa="none", **opts):
    """A render and the warning lines it said."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        r._warned.clear()
        frame = r.render(scene, engine=engine, aa=aa, **opts)
        frame.settle()
    return frame, [str(w.message) for w in said]


def _interior(covered: np.ndarray) -> np.ndarray:
    """Covered pixels whose four neighbours are covered too (away from silhouettes)."""
    inside = covered.copy()
    for axis in (0, 1):
        for shift in (1, -1):
            inside &= np.roll(covered, shift, axis)
    return inside


def _blurred(image: np.ndarray) -> np.ndarray:
    """The 3 x 3 box mean of (H, W, C) ``image``: texture detail finer than a pixel, which the
    rasterizer filters (mipmaps) and the tracers point-sample, compared by its mean."""
    x = image.astype(np.float64)
    return sum(np.roll(np.roll(x, dy, 0), dx, 1) for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9


def _same_ids(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Pixels whose id and whose eight neighbours' ids are the same in both pictures."""
    same = a == b
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            same &= (np.roll(np.roll(a, dy, 0), dx, 1) == a) & \
                (np.roll(np.roll(b, dy, 0), dx, 1) == b)
    return same


@needs_models
@pytest.mark.parametrize("name", [m for m in MODELS if m not in REFUSED])
def test_first_hit_channels_agree_across_engines(name):
    """Coverage and ids agree on 97% of the pixels (silhouettes differ by a pixel: the
    rasterizer's coverage rule, the tracers' ray through the centre); where the ids agree
    with their neighbours, depth agrees within 0.5% of the scene's depth range and normals
    within 8 degrees on 95% of the pixels; the unlit base colour of the rasterizer and the
    Whitted tracer (3 x 3 means: texture detail finer than a pixel is sampled otherwise)
    within 8/255 on average (a wrong image, slot or colour space is tens away)."""
    scene, _ = _load(name)
    meshes = [o.id for o in scene.objects if o.mesh.kind == "mesh"]
    outputs = ("color", "depth", "ids", "normals")
    caught = []
    with facet.Renderer(SIZE, SIZE) as r:
        frames = {e: _render(r, scene, e, outputs=outputs, shading="unlit",
                             lights="camera", shadows=False)[0] for e in ENGINES}
        ref = frames["raster"]
        depth_range = float(np.ptp(ref.depth[ref.object_ids >= 0])) if \
            (ref.object_ids >= 0).any() else 1.0
        for e in ("trace", "path"):
            f = frames[e]
            ids_agree = (f.object_ids == ref.object_ids).mean()
            if ids_agree < 0.97:
                caught.append(f"{e}: ids agree on {ids_agree:.1%} of pixels")
            # (points and lines: the tracers' spheres and capsules, said in a warning line)
            same = _same_ids(f.object_ids, ref.object_ids) & np.isin(ref.object_ids, meshes)
            if same.sum() < 20:
                continue
            depth_ok = (np.abs(f.depth - ref.depth)[same] <= 0.005 * max(depth_range, 1e-6))
            cos = np.sum(f.normals[same] * ref.normals[same], axis=-1)
            normal_ok = cos >= np.cos(np.radians(8))
            if depth_ok.mean() < 0.95:
                caught.append(f"{e}: depth agrees on {depth_ok.mean():.1%}")
            if normal_ok.mean() < 0.95:
                caught.append(f"{e}: normals agree on {normal_ok.mean():.1%}")
        trace = frames["trace"]
        same = _same_ids(trace.object_ids, ref.object_ids) & (ref.object_ids >= 0)
        diff = np.abs(_blurred(trace.color[..., :3]) - _blurred(ref.color[..., :3]))
        if same.sum() >= 20 and diff[same].mean() > 8:
            caught.append(f"trace: base colour {diff[same].mean():.1f}/255 away on average")
    assert not caught, (name, caught)


def _opaque_ids(scene) -> set[int]:
    """Ids of objects whose material lets no light through (what direct light compares)."""
    out = set()
    for o in scene.objects:
        m = o.material
        if o.mesh.kind == "mesh" and not getattr(m, "transmission", 0.0) and \
                getattr(m, "alpha_mode", "OPAQUE") == "OPAQUE" and not getattr(m, "unlit", False):
            out.add(o.id)
    return out


@needs_models
@pytest.mark.parametrize("name", [m for m in MODELS if m not in REFUSED])
def test_direct_light_of_the_path_tracer_is_the_rasterizers(name):
    """The default punctual lights, no ambient light, no environment: the path tracer at
    max_depth 0 and the rasterizer with shadow maps give the same linear colour on opaque
    surfaces (within 0.03 + 10% on 90% of the interior pixels: shadow-map edges and the
    path tracer's bent normal maps are the rest)."""
    scene, _ = _load(name)
    opaque = _opaque_ids(scene)
    if not opaque:
        pytest.skip(f"{name} has no opaque surface to compare")
    # What lets light through goes: its shadows differ by design (the rasterizer's maps let
    # glass pass some light, the path tracer finds no caustics from delta lights).
    scene = scene.view(objects=[o for o in scene.objects if o.id in opaque])
    scene.ambient = np.zeros(3)
    opts = dict(lights="camera", float_color=True, outputs=("color", "ids"), shadows=True)
    with facet.Renderer(SIZE, SIZE) as r:
        raster, _ = _render(r, scene, "raster", **opts)
        path, _ = _render(r, scene, "path", max_depth=0, **opts)
    mask = _same_ids(raster.object_ids, path.object_ids) & np.isin(raster.object_ids,
                                                                   list(opaque))
    if mask.sum() < 20:
        pytest.skip(f"{name}: too few opaque pixels in view ({mask.sum()})")
    a, b = _blurred(raster.color[..., :3])[mask], _blurred(path.color[..., :3])[mask]
    ok = np.abs(a - b) <= 0.03 + 0.1 * np.maximum(a, b)
    assert ok.all(axis=-1).mean() >= 0.9, (name, ok.all(axis=-1).mean())


def dish_twin(folder):
    """A file like the IridescentDishWithOlives sample, written here: a single-sided glass
    dish (a sphere, KHR_materials_transmission and _volume, as glTF glass is) over an
    alpha-masked gold leaf (a metal quad) on a plate; its path."""
    from gltf_files import USHORT, GltfBuilder, quad

    b = GltfBuilder()
    b.doc["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_volume"]
    sphere = facet.primitives.sphere(0.5, segments=48, rings=24)
    glass = b.material(pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1],
                                             "metallicFactor": 0.0, "roughnessFactor": 0.05},
                       extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                   "KHR_materials_volume": {"thicknessFactor": 0.1}})
    gold = b.material(pbrMetallicRoughness={"baseColorFactor": [1.0, 0.77, 0.34, 1],
                                            "metallicFactor": 1.0, "roughnessFactor": 0.3},
                      alphaMode="MASK", doubleSided=True)
    plate = b.material(pbrMetallicRoughness={"baseColorFactor": [0.8, 0.8, 0.75, 1],
                                             "metallicFactor": 0.0, "roughnessFactor": 0.6})
    b.node(mesh=b.mesh([{"attributes": {
        "POSITION": b.accessor(sphere.positions, minmax=True),
        "NORMAL": b.accessor(sphere.normals)},
        "indices": b.accessor(sphere.faces.reshape(-1), USHORT), "material": glass}]),
        translation=[0, 0.1, 0])
    b.node(mesh=quad(b, gold), translation=[-0.35, -0.2, 0.1], scale=[0.7, 0.6, 1],
           rotation=[-0.2588, 0, 0, 0.9659])
    b.node(mesh=quad(b, plate), translation=[-1, -0.45, 1],
           rotation=[-0.7071, 0, 0, 0.7071], scale=[2, 2, 1])
    return b.write_glb(folder / "DishTwin.glb")


TWINS = {"DishTwin": dish_twin}


@pytest.mark.parametrize("name", [*TWINS, *(m for m in MODELS if m not in REFUSED)])
def test_every_surface_the_rasterizer_lights_the_whitted_tracer_lights(name, tmp_path):
    """Under the default lights and the notes' ambient term (no environment, no shadows),
    each object the rasterizer and the Whitted tracer both see, transmitting and masked
    ones included, is lit alike within a factor of two on average (the two light a surface
    by the same terms; refraction shows other things through glass, never black glass).
    Why the first-hit and direct-light checks above let a black dish pass (issue 49, item 3):
    they compare the unlit base colour, and the path tracer's direct light on opaque
    surfaces only; the Whitted tracer's lit picture of glass and masked metal was compared
    with nothing. The DishTwin written here (single-sided glass over masked gold) runs
    too; the black dish itself came from the sample file, which ../shared does not hold,
    and tests/test_material_record.py checks its cause (the glass's far side).) Both
    engines take the same 2 x 2 grid of samples a pixel: AnisotropyStrengthTest's mirror
    metals (roughness 0) have lobes a line thin, whose one-sample value swings by 100x with
    the last bits of the normal (with 16 samples a pixel the two agree per object to 0.4%),
    and each picture is compared as 8 bits show it, clipped at 1. (What this check first
    found there was the Whitted tracer's float colour clamped to 1: a highlight of 3.1 read
    0.18; tests/test_path.py checks every engine's float colour.)"""
    if name in TWINS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            scene = facet.load(TWINS[name](tmp_path))
    else:
        scene, _ = _load(name)
    opts = dict(lights="camera", outputs=("color", "ids"), shadows=False, float_color=True,
                aa="ssaa:grid:4")
    with facet.Renderer(SIZE * 2, SIZE * 2) as r:
        raster, _ = _render(r, scene, "raster", **opts)
        trace, _ = _render(r, scene, "trace", **opts)
    luminance = np.array([0.2126, 0.7152, 0.0722])
    # As an 8-bit picture shows it (clipped at 1): a highlight's spike above 1 swings with
    # where a sample lands on a line-thin lobe, and says nothing of a surface left dark.
    a = _blurred(np.minimum(raster.color[..., :3], 1.0)) @ luminance
    b = _blurred(np.minimum(trace.color[..., :3], 1.0)) @ luminance
    same = _same_ids(raster.object_ids, trace.object_ids) & (raster.object_ids >= 0)
    caught = []
    for oid in np.unique(raster.object_ids[same]):
        where = same & (raster.object_ids == oid)
        if where.sum() < 12:
            continue
        lit, traced = a[where].mean(), b[where].mean()
        if lit > 0.02 and not 0.5 * lit <= traced <= 2.0 * lit:
            material = next(o.material for o in scene.objects if o.id == oid)
            caught.append(f"object {oid} ({getattr(material, 'name', '')}): rasterizer "
                          f"{lit:.3f}, Whitted tracer {traced:.3f}")
    assert not caught, (name, caught)


# What taking a feature away means (the glTF default it falls back to).
STRIP = {
    "baseColorTexture": dict(base_color_texture=None),
    "metallicRoughnessTexture": dict(metallic_roughness_texture=None),
    "normalTexture": dict(normal_texture=None),
    "occlusionTexture": dict(occlusion_texture=None),
    "emissiveTexture": dict(emissive_texture=None),
    "KHR_materials_clearcoat": dict(clearcoat=0.0),
    "clearcoatNormalTexture": dict(clearcoat_normal_texture=None),
    "KHR_materials_sheen": dict(sheen_color=np.zeros(3)),
    "KHR_materials_specular": dict(specular=1.0, specular_color=np.ones(3),
                                   specular_texture=None, specular_color_texture=None),
    "KHR_materials_ior": dict(ior=1.5),
    "alphaMode MASK": dict(alpha_mode="OPAQUE"),
}


def _stripped(scene, feature: str):
    """``scene`` with ``feature`` taken from every material that has it."""
    out = scene.view(objects=[
        replace(o, material=replace(o.material, **STRIP[feature]))
        if feature in material_features(o.material) else o for o in scene.objects])
    out.environment = scene.environment
    return out


@needs_models
@pytest.mark.parametrize("name", [m for m in MODELS if m not in REFUSED])
def test_a_feature_the_rasterizer_draws_is_drawn_or_named_by_each_tracer(name):
    """Under the default lights and an ambient light: for each feature of the file's
    materials (STRIP), if taking it away changes the rasterizer's picture (by 4/255 somewhere,
    0.1/255 on average), it must change each tracer's (by over 1/255 somewhere), or that
    tracer must name it in a warning line; and each engine names every feature its
    capability table leaves out; a feature the table says an engine computes itself (the
    path tracer's occlusion) is exempt. (The Whitted tracer leaving occlusionTexture out
    again fails it on AlphaBlendModeTest, GlassBrokenWindow and NormalTangentTest.)"""
    scene, _ = _load(name)
    # No environment: the Whitted tracer lights glTF materials by the ambient term (said in
    # a warning line), so a feature seen in the environment's reflection would differ.
    scene.ambient = np.full(3, 0.3)
    present = sorted({f for o in scene.objects for f in material_features(o.material)})
    checked = [f for f in present if f in STRIP]
    caught = []
    opts = dict(lights="camera", outputs=("color",), shadows=False)
    with facet.Renderer(24, 24) as r:
        pictures, said = {}, {}
        for e in ENGINES:
            frame, lines = _render(r, scene, e, **opts)
            pictures[e], said[e] = frame.color.astype(int), lines
            for feature in present:  # the table's, always named
                if feature in CAPABILITIES[e].leaves_out and \
                        not any(feature in line for line in lines):
                    caught.append(f"{e} leaves out {feature} without a word")
        for feature in checked:
            bare = _stripped(scene, feature)
            raster = r.render(bare, engine="raster", aa="none", **opts).color.astype(int)
            change = np.abs(raster - pictures["raster"])
            if change.max() < 4 or change.mean() < 0.1:
                continue  # not visible in this view: nothing to compare
            for e in ("trace", "path"):
                if any(feature in line for line in said[e]) or \
                        feature in CAPABILITIES[e].computes:
                    continue
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    other = r.render(bare, engine=e, aa="none", **opts).color.astype(int)
                if np.abs(other - pictures[e]).max() <= 1:
                    caught.append(f"{e} draws the same without {feature} and says nothing")
    assert not caught, (name, caught)

"""KHR_materials_pbrSpecularGlossiness (archived, still common in files made before 2022):
converted to metallic-roughness as KHR_materials_specular describes (ior 0: F0 is the
specular colour). As the Khronos model SpecGlossVsMetalRough shows, a material written
both ways draws alike: a gold metal and a glossy dielectric with textures, each a
specular-glossiness sphere beside its metallic-roughness twin, in every engine."""

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera

from gltf_files import UINT, GltfBuilder, png

CAM = Camera.look_at((0, 0, 4.2), (0, 0, 0), fov_y=40, near=0.5, far=20)


def _sphere(b, material, x):
    import trimesh

    s = trimesh.creation.uv_sphere(radius=0.8, count=[48, 48])
    v = np.asarray(s.vertices)
    uv = np.stack([0.5 + np.arctan2(v[:, 2], v[:, 0]) / (2 * np.pi),
                   np.arccos(np.clip(v[:, 1] / 0.8, -1, 1)) / np.pi], axis=1)
    prim = {"attributes": {"POSITION": b.accessor(v, minmax=True),
                           "NORMAL": b.accessor(v / 0.8),
                           "TEXCOORD_0": b.accessor(uv)},
            "indices": b.accessor(np.asarray(s.faces).reshape(-1), UINT), "material": material}
    b.node(mesh=b.mesh([prim]), translation=[x, 0.0, 0.0])


def _pair(tmp_path, textured: bool):
    """Two files: the specular-glossiness spheres, and the metallic-roughness twins."""
    paths = []
    rng = np.random.default_rng(3)
    colour = rng.integers(40, 230, (8, 8, 3)).astype(np.uint8)  # (sRGB)
    gloss = rng.integers(60, 250, (8, 8)).astype(np.uint8)
    for kind in ("specgloss", "metalrough"):
        b = GltfBuilder()
        if kind == "specgloss":
            b.doc["extensionsUsed"] = ["KHR_materials_pbrSpecularGlossiness"]
            gold = b.material(extensions={"KHR_materials_pbrSpecularGlossiness": {
                "diffuseFactor": [0, 0, 0, 1], "specularFactor": [1.0, 0.766, 0.336],
                "glossinessFactor": 0.7}})
            sg = {"specularFactor": [0.04, 0.04, 0.04], "glossinessFactor": 0.8}
            if textured:
                # F0 0.04 (linear) in the texture's sRGB RGB; glossiness in its alpha
                spec = np.dstack([np.full((8, 8, 3), 56, np.uint8), gloss])
                sg = {"diffuseTexture": {"index": b.texture(png(colour))},
                      "specularGlossinessTexture": {"index": b.texture(png(spec))},
                      "specularFactor": [1.0, 1.0, 1.0], "glossinessFactor": 0.8}
            plastic = b.material(extensions={"KHR_materials_pbrSpecularGlossiness": sg})
        else:
            gold = b.material(pbrMetallicRoughness={
                "baseColorFactor": [1.0, 0.766, 0.336, 1], "metallicFactor": 1.0,
                "roughnessFactor": 0.3})
            mr = {"metallicFactor": 0.0, "roughnessFactor": 0.2}
            if textured:
                rough = np.zeros((8, 8, 3), np.uint8)
                rough[..., 1] = np.rint(255 * (1 - 0.8 * gloss / 255.0))
                mr = {"baseColorTexture": {"index": b.texture(png(colour))},
                      "metallicRoughnessTexture": {"index": b.texture(png(rough))},
                      "metallicFactor": 0.0, "roughnessFactor": 1.0}
            plastic = b.material(pbrMetallicRoughness=mr)
        _sphere(b, gold, -0.95)
        _sphere(b, plastic, 0.95)
        paths.append(b.write_gltf(tmp_path / f"{kind}.gltf"))
    return paths


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
@pytest.mark.parametrize("textured", [False, True])
def test_specular_glossiness_draws_as_its_metallic_roughness_twin(tmp_path, engine, textured):
    import warnings

    pictures = []
    for path in _pair(tmp_path, textured):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no "ignores" line: the extension is read
            scene = facet.load(path)
        scene.environment = None
        with facet.Renderer(96, 64) as r:
            frame = r.render(scene, CAM, engine=engine, spp=64 if engine == "path" else 4,
                             float_color=True, lights="camera", seed=5)
        pictures.append(frame.color[..., :3])
    spec, metal = pictures
    lit = metal.mean(axis=2) > 0.02
    assert lit.sum() > 1000 and spec.max() > 0.05
    # The same material model, so the same picture: within what the specular texture's
    # 8-bit sRGB step (F0 0.0409 for 0.04) and the path tracer's noise allow.
    tolerance = 0.04 if engine == "path" else 0.01
    diff = np.abs(spec - metal)[lit]
    assert diff.mean() < tolerance, (engine, diff.mean())
    for half in (slice(0, 48), slice(48, 96)):  # each sphere alike on its own
        a, b = spec[:, half][lit[:, half]].mean(), metal[:, half][lit[:, half]].mean()
        assert abs(a - b) < 0.03 * max(b, 0.05), (engine, half, a, b)

"""KHR_materials_variants: ``variant`` (every front) dresses each primitive in the material
its file maps to that variant, the same picture as a file whose default is that material;
an unknown name is one line naming the variants there are."""

from __future__ import annotations

import json

import numpy as np
import pytest

import facet
from facet.cli import main

from gltf_files import GltfBuilder, quad

RED, BLUE, GREEN = [0.8, 0.1, 0.1, 1], [0.1, 0.2, 0.9, 1], [0.1, 0.8, 0.2, 1]


def _file(tmp_path, default=RED, variants=True):
    b = GltfBuilder()
    mats = [b.material(pbrMetallicRoughness={"baseColorFactor": c, "metallicFactor": 0.0})
            for c in (default, BLUE, GREEN)]
    mesh = quad(b, mats[0])
    if variants:
        b.doc["extensionsUsed"] = ["KHR_materials_variants"]
        b.doc["extensions"] = {"KHR_materials_variants": {"variants": [
            {"name": "blue"}, {"name": "green"}, {"name": "ocean"}]}}
        b.doc["meshes"][mesh]["primitives"][0]["extensions"] = {"KHR_materials_variants": {
            "mappings": [{"material": mats[1], "variants": [0, 2]},
                         {"material": mats[2], "variants": [1]}]}}
    b.node(mesh=mesh)
    return b.write_gltf(tmp_path / f"v{len(list(tmp_path.iterdir()))}.gltf")


@pytest.mark.parametrize("variant, colour", [("blue", BLUE), ("green", GREEN),
                                             ("ocean", BLUE), (None, RED)])
def test_a_variant_draws_as_its_material_does(tmp_path, renderer, variant, colour):
    scene = facet.load(_file(tmp_path))
    plain = facet.load(_file(tmp_path, default=colour, variants=False))
    r = renderer(32, 32)
    cam = r.camera(plain, r.options(plain))
    got = r.render(scene, cam, variant=variant).color
    want = r.render(plain, cam).color
    np.testing.assert_array_equal(got, want)


def test_variant_from_the_command_line_and_a_scene_file(tmp_path, renderer):
    from PIL import Image

    path = _file(tmp_path)
    out = tmp_path / "x.png"
    assert main(["render", str(path), "-o", str(out), "--size", "32x32", "--variant",
                 "green", "-q"]) == 0
    img = np.asarray(Image.open(out).convert("RGB")).astype(int)
    centre = img[16, 16]
    assert centre[1] > centre[0] + 40 and centre[1] > centre[2] + 40  # green
    toml = tmp_path / "s.toml"
    toml.write_text(f'[render]\nvariant = "green"\nsize = [32, 32]\n[[objects]]\n'
                    f'mesh = "{path.name}"\n')
    r = renderer(32, 32)
    scene = facet.load(toml)
    frame = r.render(scene, r.camera(scene, r.options(scene)))
    c = frame.color[16, 16]
    assert c[1] > c[0] and c[1] > c[2]


def test_an_unknown_variant_is_one_line_naming_the_variants(tmp_path, capsys):
    path = _file(tmp_path)
    out = tmp_path / "x.png"
    assert main(["render", str(path), "-o", str(out), "--variant", "purple"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "blue, green, ocean" in err[0]
    assert not out.exists()


def test_a_mapping_to_a_missing_material_is_one_line(tmp_path, capsys):
    path = _file(tmp_path)
    doc = json.loads(path.read_text())
    doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"][
        "mappings"][0]["material"] = 9
    path.write_text(json.dumps(doc))
    assert main(["render", str(path), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "mappings[0].material" in err[0]


def _webp(pixels: np.ndarray) -> bytes:
    import io

    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(np.asarray(pixels, np.uint8)).save(out, "WEBP", lossless=True)
    return out.getvalue()


def _textured(tmp_path, extension: str, fallback: bool, required: bool, webp: bool = False):
    from gltf_files import png

    b = GltfBuilder()
    pixels = np.full((4, 4, 3), (20, 200, 40), np.uint8)
    tex = b.texture(_webp(pixels) if webp else png(pixels))
    if webp:
        b.doc["images"][-1]["mimeType"] = "image/webp"
    texture = b.doc["textures"][tex]
    texture["name"] = "basecolor.ktx2" if extension == "KHR_texture_basisu" else "basecolor"
    source = texture.pop("source")
    texture["extensions"] = {extension: {"source": source}}
    if fallback:
        texture["source"] = source
    b.doc["extensionsUsed"] = [extension]
    if required:
        b.doc["extensionsRequired"] = [extension]
    b.node(mesh=quad(b, b.material(pbrMetallicRoughness={
        "baseColorTexture": {"index": tex}, "metallicFactor": 0.0})))
    return b.write_gltf(tmp_path / "t.gltf")


def test_ktx2_textures_are_refused_by_name_or_their_fallbacks_drawn(tmp_path, capsys, renderer,
                                                                  monkeypatch):
    """Without the ktx2 extra (no KTX2 / Basis Universal transcoder): a file that requires
    KHR_texture_basisu is one refusal line naming it and the extra; one that offers PNG
    fallbacks draws them (one warning line); a texture with no fallback is drawn without,
    and said so (tests/test_ktx2.py: with the extra, the KTX2 images themselves)."""
    import sys

    monkeypatch.setitem(sys.modules, "opengl_basisu", None)  # as if not installed
    path = _textured(tmp_path, "KHR_texture_basisu", fallback=False, required=True)
    assert main(["render", str(path), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "KHR_texture_basisu" in err[0] and "PNG or JPEG" in err[0]
    assert "facet-render[ktx2]" in err[0]
    path = _textured(tmp_path, "KHR_texture_basisu", fallback=True, required=False)
    with pytest.warns(facet.FacetWarning) as said:
        scene = facet.load(path)
    lines = [str(x.message) for x in said]
    assert len(lines) == 1 and "fallbacks of its KTX2 textures 'basecolor.ktx2'" in lines[0]
    assert scene.objects[0].material.base_color_texture is not None
    # No fallback: the texture is named and no fallback is claimed, on every load.
    path = _textured(tmp_path, "KHR_texture_basisu", fallback=False, required=False)
    for _ in range(2):
        with pytest.warns(facet.FacetWarning) as said:
            scene = facet.load(path)
        lines = [str(x.message) for x in said]
        assert len(lines) == 1 and "'basecolor.ktx2', which has no PNG or JPEG" in lines[0]
        assert "draws the PNG" not in lines[0]
        assert scene.objects[0].material.base_color_texture is None


def test_webp_textures_are_decoded(tmp_path, renderer):
    """EXT_texture_webp: Pillow decodes the WebP image (a lossless one, written here)."""
    import warnings

    path = _textured(tmp_path, "EXT_texture_webp", fallback=False, required=True, webp=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(path)
    slot = scene.objects[0].material.base_color_texture
    assert slot is not None
    r = renderer(32, 32)
    c = r.render(scene, r.camera(scene, r.options(scene))).color[16, 16]
    assert c[1] > c[0] + 0.2 and c[1] > c[2] + 0.2

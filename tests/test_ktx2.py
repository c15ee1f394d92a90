"""KHR_texture_basisu: KTX2 / Basis Universal textures (ETC1S and UASTC) decoded by the
ktx2 extra (opengl_basisu). The test card encoded both ways (tests/data/ktx2, made with
Basis Universal's own encoder) decodes to the card (UASTC exactly, ETC1S within its
loss); a glTF whose only texture is KTX2 (the extension required, no PNG fallback) loads
with no warning and draws as its PNG twin in every engine; without the extra it is one
refusal line naming it."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import facet
from facet.cli import main

from gltf_files import GltfBuilder, png, quad

pytest.importorskip("opengl_basisu", reason="the ktx2 extra (pip install opengl_basisu)")
DATA = Path(__file__).resolve().parent / "data" / "ktx2"
CARD = np.asarray(Image.open(DATA / "card.png").convert("RGBA")).astype(int)
CAM = facet.Camera.look_at((0.5, 0.5, 1.6), (0.5, 0.5, 0), fov_y=40, near=0.1, far=10)


@pytest.mark.parametrize("codec, mean_error", [("uastc", 0.5), ("etc1s", 4.0)])
def test_the_card_decodes(codec, mean_error):
    from facet.formats.gltf_data import ktx2_pixels

    pixels = ktx2_pixels((DATA / f"card-{codec}.ktx2").read_bytes(), codec)
    assert pixels.shape == (32, 32, 4) and pixels.dtype == np.uint8
    assert np.abs(pixels.astype(int) - CARD).mean() < mean_error  # (rows from the top)


def _card_gltf(tmp_path, ktx2: bool, codec: str = "uastc") -> Path:
    b = GltfBuilder()
    if ktx2:
        raw = (DATA / f"card-{codec}.ktx2").read_bytes()
        b.doc.setdefault("images", []).append({"bufferView": b.view(raw),
                                               "mimeType": "image/ktx2"})
        b.doc.setdefault("textures", []).append({"extensions": {
            "KHR_texture_basisu": {"source": len(b.doc["images"]) - 1}}})
        b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = ["KHR_texture_basisu"]
        tex = len(b.doc["textures"]) - 1
    else:
        tex = b.texture(png(CARD[..., :3].astype(np.uint8)))
    b.node(mesh=quad(b, b.material(pbrMetallicRoughness={
        "baseColorTexture": {"index": tex}, "metallicFactor": 0.0}, extensions={
        "KHR_materials_unlit": {}})))
    b.doc["extensionsUsed"] = b.doc.get("extensionsUsed", []) + ["KHR_materials_unlit"]
    return b.write_gltf(tmp_path / f"card-{'ktx2' if ktx2 else 'png'}.gltf")


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_ktx2_only_file_draws_as_its_png_twin(tmp_path, engine):
    pictures = []
    for ktx2 in (True, False):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no refusal, no "draws the fallbacks" line
            scene = facet.load(_card_gltf(tmp_path, ktx2))
        assert scene.objects[0].material.base_color_texture is not None
        with facet.Renderer(48, 48) as r:
            pictures.append(r.render(scene, CAM, engine=engine, spp=4, lights="scene",
                                     float_color=True).color[..., :3])
    np.testing.assert_allclose(pictures[0], pictures[1], atol=0.02)
    assert pictures[0].std() > 0.1  # (the card's quadrants show)


def test_without_the_extra_a_ktx2_only_file_is_one_line(tmp_path, capsys, monkeypatch):
    path = _card_gltf(tmp_path, True)
    monkeypatch.setitem(sys.modules, "opengl_basisu", None)  # as if not installed
    assert main(["render", str(path), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "KHR_texture_basisu" in err[0] and "facet-render[ktx2]" in err[0]


def test_a_broken_ktx2_image_is_named_and_drawn_without(tmp_path):
    """A KTX2 image cut short: one warning naming it (drawn without it), no traceback."""
    path = _card_gltf(tmp_path, True)
    doc_text = path.read_text()
    good = (DATA / "card-uastc.ktx2").read_bytes()
    import base64

    doc_text = doc_text.replace(base64.b64encode(good).decode()[:40], "A" * 40)
    path.write_text(doc_text)
    with pytest.warns(facet.FacetWarning, match="drawn without it") as said:
        scene = facet.load(path)
    assert len(said) == 1
    assert scene.objects[0].material.base_color_texture is None

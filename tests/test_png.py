"""facet's PNG encoder (facet.image.png): every file decodes, in Pillow too, to exactly the
array written."""

import io
import zlib

import numpy as np
import pytest
from PIL import Image

from facet.image.png import FAST_LEVELS, decode_png, deflate, encode_png
from facet.image.writers import save_indexed


@pytest.mark.parametrize("shape", [(1, 1), (5, 7), (6, 9, 3), (4, 1, 3), (8, 5, 4), (33, 17, 4)])
@pytest.mark.parametrize("level", [0, 1, 6])
def test_8_bit_images_decode_exactly_in_pillow(shape, level):
    rng = np.random.default_rng(len(shape) * 10 + shape[0])
    a = rng.integers(0, 256, shape, dtype=np.uint8)
    a[0] = 255  # wrap-around of the Sub filter (255 - 0, 0 - 255)
    data = encode_png(a, level)
    with Image.open(io.BytesIO(data)) as img:
        got = np.asarray(img)
        assert img.mode == ("L" if a.ndim == 2 else {3: "RGB", 4: "RGBA"}[a.shape[2]])
    np.testing.assert_array_equal(got, a)
    np.testing.assert_array_equal(decode_png(data), a)


def test_16_bit_grey_decodes_exactly_in_pillow():
    a = np.random.default_rng(3).integers(0, 65536, (9, 11), dtype=np.uint16)
    a[0, :2] = (65535, 0)
    with Image.open(io.BytesIO(encode_png(a))) as img:
        np.testing.assert_array_equal(np.asarray(img).astype(np.uint16), a)
    rgb = np.random.default_rng(4).integers(0, 65536, (3, 5, 3), dtype=np.uint16)
    np.testing.assert_array_equal(decode_png(encode_png(rgb)), rgb)


def test_a_rendered_image_compresses_like_pillows():
    """A smooth picture on a flat background (what renders look like): the file is no more
    than 15% larger than Pillow's adaptive filtering makes at the same zlib level."""
    y, x = np.mgrid[0:256, 0:256]
    disc = (x - 128) ** 2 + (y - 128) ** 2 < 90 ** 2
    a = np.zeros((256, 256, 3), np.uint8)
    a[disc] = np.stack([x, y, 255 - x], -1)[disc].astype(np.uint8)
    buf = io.BytesIO()
    Image.fromarray(a).save(buf, format="PNG", compress_level=1)
    assert len(encode_png(a, 1)) < 1.15 * buf.tell()


@pytest.mark.parametrize("entries", [1, 17, 256])
@pytest.mark.parametrize("level", [0, 1, 6])
def test_indexed_images_decode_to_their_indices_and_palette(entries, level):
    rng = np.random.default_rng(entries)
    index = rng.integers(0, entries, (13, 21), dtype=np.uint8)
    palette = rng.integers(0, 256, (entries, 3), dtype=np.uint8)
    data = encode_png(index, level, palette=palette)
    with Image.open(io.BytesIO(data)) as img:
        assert img.mode == "P"
        np.testing.assert_array_equal(np.asarray(img), index)
        got = np.asarray(img.getpalette()[:3 * entries], np.uint8).reshape(-1, 3)
    np.testing.assert_array_equal(got, palette)
    np.testing.assert_array_equal(decode_png(data), index)


def test_save_indexed_covers_indices_past_the_palette(tmp_path):
    """Indices the palette does not reach are black, never an unreadable file."""
    index = np.array([[0, 1], [5, 200]], np.uint8)
    path = save_indexed(tmp_path / "p.png", index, np.array([[255, 0, 0], [0, 255, 0]]))
    with Image.open(path) as img:
        np.testing.assert_array_equal(np.asarray(img.convert("RGB")),
                                      [[[255, 0, 0], [0, 255, 0]], [[0, 0, 0], [0, 0, 0]]])


@pytest.mark.parametrize("level", [0, *FAST_LEVELS, 6, 9])
def test_every_level_deflates_to_a_zlib_stream(level):
    """ISA-L (the fast levels) and zlib (the others) both write what zlib inflates."""
    data = np.random.default_rng(level).integers(0, 4, 100_000, dtype=np.uint8).tobytes()
    assert zlib.decompress(deflate(data, level)) == data


def test_a_bad_palette_is_one_error():
    with pytest.raises(ValueError, match="palette"):
        encode_png(np.zeros((2, 2), np.uint8), palette=np.zeros((2, 4), np.uint8))
    with pytest.raises(ValueError, match="encode_png expects"):
        encode_png(np.zeros((2, 2, 3), np.uint8), palette=np.zeros((2, 3), np.uint8))


@pytest.mark.parametrize("bad", [np.zeros((4, 4, 2), np.uint8), np.zeros((4, 4, 4), np.uint16),
                                 np.zeros((4, 4), np.float32), np.zeros((0, 4), np.uint8)])
def test_what_it_cannot_write_is_one_error(bad):
    with pytest.raises(ValueError, match="encode_png expects"):
        encode_png(bad)


def test_without_isal_zlib_writes_every_level(monkeypatch):
    """ISA-L is a speed-up, not a need: without it the fast levels go through zlib."""
    import facet.image.png as png

    monkeypatch.setattr(png, "isal_zlib", None)
    a = np.random.default_rng(7).integers(0, 256, (9, 13, 3), dtype=np.uint8)
    for level in (0, *FAST_LEVELS, 6):
        with Image.open(io.BytesIO(encode_png(a, level))) as img:
            np.testing.assert_array_equal(np.asarray(img), a)

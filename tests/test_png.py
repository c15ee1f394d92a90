"""facet's PNG encoder (facet.image.png): every file decodes, in Pillow too, to exactly the
array written."""

import io

import numpy as np
import pytest
from PIL import Image

from facet.image.png import decode_png, encode_png


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


@pytest.mark.parametrize("bad", [np.zeros((4, 4, 2), np.uint8), np.zeros((4, 4, 4), np.uint16),
                                 np.zeros((4, 4), np.float32), np.zeros((0, 4), np.uint8)])
def test_what_it_cannot_write_is_one_error(bad):
    with pytest.raises(ValueError, match="encode_png expects"):
        encode_png(bad)

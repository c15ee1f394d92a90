"""Colour quantisation (notes §1.3): bit depths, dithering, palettes, 16-bit PNG (no GL)."""

import numpy as np
import pytest
from PIL import Image

from facet.errors import InputError
from facet.image import quantize
from facet.image.png import decode_png, encode_png


def gradient(h=64, w=256):
    """A smooth horizontal ramp with a gentle vertical tint: float RGB in [0, 1]."""
    x = np.linspace(0, 1, w)[None, :, None]
    y = np.linspace(0, 0.2, h)[:, None, None]
    return np.clip(np.concatenate([x + 0 * y, x * 0.8 + y, 1 - x + 0 * y], axis=2), 0, 1)


def box(a, k=8):
    """Box filter by k x k block means (what the eye does from a distance)."""
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    a = a[:h, :w]
    return a.reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


def test_bayer_matrix():
    assert bayer_ok(quantize.bayer_matrix(4))
    assert sorted(quantize.bayer_matrix(8).ravel()) == list(range(64))


def bayer_ok(m):
    return np.array_equal(m, [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]])


@pytest.mark.parametrize("bits", [(2,), (3, 3, 3), (5, 6, 5)])
def test_levels_and_banding(bits):
    g = gradient()
    q = quantize.reduce_bits(g, bits, grey=quantize.is_grey(bits))
    chans = q[..., None] if q.ndim == 2 else q
    per_channel = bits * chans.shape[-1] if len(bits) == 1 else bits
    for c, b in enumerate(per_channel):
        assert len(np.unique(chans[..., c])) <= 2 ** b
        assert len(np.unique(chans[..., c])) >= 2 ** b - 1  # the ramp visits every level
    assert q.dtype == np.uint8 and chans[..., 0].max() == 255


@pytest.mark.parametrize("dither", ["bayer4", "bayer8", "floyd-steinberg"])
@pytest.mark.parametrize("bits", [(2, 2, 2), (3, 3, 3)])
def test_dithering_lowers_the_filtered_error(dither, bits):
    """Mean error of the 8x8 box-filtered image against the box-filtered float image: plain
    rounding bands (large local bias), dithering spreads the error so its average cancels."""
    g = gradient()
    plain = quantize.reduce_bits(g, bits, "none") / 255.0
    dithered = quantize.reduce_bits(g, bits, dither) / 255.0
    err_plain = np.abs(box(plain) - box(g)).mean()
    err_dith = np.abs(box(dithered) - box(g)).mean()
    assert err_dith < 0.5 * err_plain, (err_dith, err_plain)
    # Dithering does not cheat: every pixel still holds one of the 2^bits levels.
    levels = np.rint(np.arange(2 ** bits[0]) * 255 / (2 ** bits[0] - 1)) / 255
    assert np.isin(np.round(dithered, 6), np.round(levels, 6)).all()


@pytest.mark.parametrize("mode", ["none", "bayer4", "bayer8", "floyd-steinberg"])
def test_quantisation_is_deterministic(mode):
    g = gradient()
    a = quantize.reduce_bits(g, (4, 4, 4), mode)
    b = quantize.reduce_bits(g.copy(), (4, 4, 4), mode)
    assert a.tobytes() == b.tobytes()


@pytest.mark.parametrize("method", ["median-cut", "kmeans"])
def test_palette(method):
    rng = np.random.default_rng(3)
    img = np.clip(gradient() + rng.normal(0, 0.02, gradient().shape), 0, 1)
    q = quantize.palette(img, 12, method)
    assert len(np.unique(q.reshape(-1, 3), axis=0)) <= 12
    assert np.abs(q / 255.0 - img).mean() < 0.08
    assert q.tobytes() == quantize.palette(img, 12, method).tobytes()


def test_bad_quantisation_arguments():
    with pytest.raises(InputError, match="each 1..8"):
        quantize.parse_bits("9")
    with pytest.raises(InputError, match="expected N"):
        quantize.parse_bits("a,b")
    with pytest.raises(InputError, match="2..256"):
        quantize.palette(gradient(), 1)
    assert quantize.parse_bits("5,6,5") == (5, 6, 5) and quantize.is_grey((4,))
    assert not quantize.is_grey((8,))


@pytest.mark.parametrize("shape", [(7, 5), (6, 9, 3)])
def test_png16_round_trip(tmp_path, shape):
    rng = np.random.default_rng(1)
    a = rng.integers(0, 65536, shape, dtype=np.uint16)
    data = encode_png(a)
    assert np.array_equal(decode_png(data), a)
    (tmp_path / "x.png").write_bytes(data)
    with Image.open(tmp_path / "x.png") as img:  # a valid PNG for other readers too
        assert img.size == (shape[1], shape[0])
        img.load()

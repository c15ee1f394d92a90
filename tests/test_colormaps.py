"""Per-vertex scalars through a named colormap: the built-in viridis at its published
samples (and between them), coolwarm's middle, the range given or the values' own, NaN
grey; meshes and clouds coloured by it; `facet render --scalars` with a colour bar whose
ends are the colormap's ends; bad names and ranges one line."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import facet
from facet.cli import main
from facet.scene.colormap import BUILTIN, colorbar, colormap, colors_for

from conftest import ROOT

VIRIDIS_QUARTER = (0.229739, 0.322361, 0.545706)  # viridis(0.25), from its definition


def test_builtin_viridis_passes_through_its_samples():
    lookup = colormap("viridis") if "viridis" in BUILTIN else None
    table = np.asarray(BUILTIN["viridis"])
    np.testing.assert_allclose(lookup(np.linspace(0, 1, len(table))), table, atol=1e-6)
    try:
        import matplotlib  # noqa: F401 - then colormap() is matplotlib's own
    except ImportError:
        np.testing.assert_allclose(lookup(np.array([0.25]))[0], VIRIDIS_QUARTER, atol=0.01)


def test_scalars_map_over_their_range_or_the_one_given():
    values = np.array([0.0, 5.0, 10.0, np.nan])
    c = colors_for(values, "coolwarm")
    np.testing.assert_allclose(c[1], BUILTIN["coolwarm"][2], atol=1e-3)  # the middle
    np.testing.assert_allclose(c[3], (0.5, 0.5, 0.5))
    clipped = colors_for(values, "gray", limits=(0, 5))
    np.testing.assert_allclose(clipped[2], (1, 1, 1))
    np.testing.assert_allclose(clipped[1], (1, 1, 1))
    np.testing.assert_allclose(clipped[0], (0, 0, 0))


def test_meshes_and_clouds_are_coloured_by_their_scalars():
    mesh = facet.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    coloured = mesh.colored_by([0.0, 1.0, 0.5], "gray")
    np.testing.assert_allclose(coloured.colors[:, :3], [[0, 0, 0], [1, 1, 1], [.5, .5, .5]],
                               atol=1e-6)
    cloud = facet.Points(np.eye(3)).colored_by([1, 2, 3], "gray")
    np.testing.assert_allclose(cloud.colors[:, 0], [0, 0.5, 1], atol=1e-6)
    with pytest.raises(facet.InputError, match="2 scalars for 3 vertices"):
        mesh.colored_by([0, 1])


def test_the_colour_bar_runs_from_the_low_end_at_the_bottom():
    image = np.zeros((64, 64, 3), np.uint8)
    out = colorbar(image, "gray", (0.0, 1.0))
    column = out[:, 58, 0].astype(int)
    painted = np.flatnonzero(out[:, 58].sum(axis=1) > 0)
    top, bottom = painted[0], painted[-1]
    assert column[top + 1] > 240 and column[bottom - 1] < 15  # white at the top


def test_render_by_height_with_a_colour_bar(tmp_path, capsys):
    out = tmp_path / "h.png"
    assert main(["render", str(ROOT / "models" / "default.obj"), "--scalars", "y",
                 "--colormap", "gray", "--colorbar", "-o", str(out), "--size", "96x64",
                 "--msaa", "0", "-q"]) == 0
    img = np.asarray(Image.open(out).convert("L")).astype(int)[:, :80]  # (left of the bar)
    rows = np.flatnonzero((img > 0).any(axis=1))
    third = max(1, len(rows) // 3)
    upper, lower = img[rows[:third]], img[rows[-third:]]
    assert upper[upper > 0].mean() > lower[lower > 0].mean() + 30  # grey by height
    rgb = np.asarray(Image.open(out).convert("RGB")).astype(int)[:, :80]
    model = rgb.sum(axis=2) > 30
    # grey: the file's orange material does not tint the colormap (it is made white)
    assert np.abs(rgb[..., 0] - rgb[..., 2])[model].mean() < 6
    assert main(["render", str(ROOT / "models" / "default.obj"), "--colormap", "nope",
                 "--scalars", "y", "-o", str(tmp_path / "x.png")]) == 2
    assert "colormap 'nope'" in capsys.readouterr().err
    assert main(["render", str(ROOT / "models" / "default.obj"), "--colorbar", "-o",
                 str(tmp_path / "y.png")]) == 2
    assert "give --scalars" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "y.png").exists()


QUALITY_PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float quality
element face 2
property list uchar int vertex_indices
end_header
0 0 0 0
1 0 0 1
1 1 0 2
0 1 0 3
3 0 1 2
3 0 2 3
"""


def test_a_plys_own_vertex_property_colours_it(tmp_path, capsys):
    """A PLY's per-vertex property (here `quality`) comes with its mesh, follows the
    vertices when they are split at creases, and --scalars names it; an unknown name lists
    the model's."""
    path = tmp_path / "q.ply"
    path.write_text(QUALITY_PLY)
    mesh = facet.load(path).objects[0].mesh
    assert set(mesh.scalars) == {"quality"}
    # Each vertex keeps its own value wherever its copies went (0..3 at the corners).
    corner = np.rint(mesh.positions[:, 0] + 2 * mesh.positions[:, 1]).astype(int)
    np.testing.assert_array_equal(mesh.scalars["quality"], np.array([0, 1, 3, 2])[corner])
    out = tmp_path / "q.png"
    assert main(["render", str(path), "--scalars", "quality", "--colormap", "gray",
                 "--eye", "0.5,0.5,3", "--target", "0.5,0.5,0", "--lights", "camera",
                 "--size", "48x48", "--msaa", "0", "-o", str(out), "-q"]) == 0
    img = np.asarray(Image.open(out).convert("L")).astype(int)
    # quality rises from corner (0, 0) (value 0) to (1, 1) (value 2) and (0, 1) (value 3)
    assert img[18, 17] > img[30, 17] + 40  # top-left (3) brighter than bottom-left (0)
    assert main(["render", str(path), "--scalars", "nope", "-o", str(tmp_path / "n.png")]) \
        == 2
    assert "the model's: quality" in capsys.readouterr().err


@pytest.mark.parametrize("background", [0, 255])
def test_colorbar_labels_show_on_any_background(background):
    """The range labels contrast with what lies behind them: on a white picture they are
    dark (they were white on white, invisible), on a black one light."""
    from facet.scene.colormap import colorbar

    image = np.full((200, 300, 3), background, np.uint8)
    out = colorbar(image, "viridis", (0.0, 1.0))
    left_of_bar = out[:, :275].astype(int)  # the labels, not the bar (x >= 279)
    changed = np.abs(left_of_bar - background).max(axis=2) > 100
    assert changed.sum() > 20  # the labels' strokes
    ink = left_of_bar[changed].mean()
    assert (ink < 100) if background == 255 else (ink > 155)

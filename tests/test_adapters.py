"""What users already hold: a Frame shows itself in Jupyter (``_repr_png_``, an HTML
summary), and trimesh's Trimesh, Scene and PointCloud go into a scene as facet's own
geometry: the same picture as the same arrays given to facet.Mesh / facet.Points."""

from __future__ import annotations

import io

import numpy as np
import pytest
import trimesh
from PIL import Image

import facet

CAM = facet.Camera.look_at((2.5, 2, 4), (0.5, 0, 0), fov_y=40)


def test_a_frame_shows_itself_in_a_notebook(renderer):
    scene = facet.Scene()
    scene.add(trimesh.creation.icosphere())
    frame = renderer(40, 30).render(scene, CAM, outputs=("color", "depth"))
    png = frame._repr_png_()
    shown = np.asarray(Image.open(io.BytesIO(png)))
    np.testing.assert_array_equal(shown, frame.color[..., :shown.shape[2]])
    page = frame._repr_html_()
    assert "data:image/png;base64," in page and "40 x 30" in page and "depth" in page


@pytest.mark.parametrize("kind", ["plain", "colours", "uvs"])
def test_a_trimesh_draws_as_the_same_arrays_do(renderer, kind):
    tm = trimesh.creation.icosphere(subdivisions=2)
    v = np.asarray(tm.vertices)
    colours = uvs = texture = None
    if kind == "colours":
        colours = (np.abs(v) * 255).astype(np.uint8)
        tm.visual.vertex_colors = np.hstack([colours, np.full((len(v), 1), 255, np.uint8)])
    if kind == "uvs":
        uvs = (v[:, :2] + 1) / 2
        image = Image.fromarray(np.kron(np.eye(4, dtype=np.uint8) * 200 + 30,
                                        np.ones((8, 8), np.uint8)))
        tm.visual = trimesh.visual.TextureVisuals(uv=uvs, image=image.convert("RGB"))
        texture = facet.Texture.from_pil(image.convert("RGB"))
    ours = facet.Scene()
    ours.add(tm)
    mesh = ours.objects[0].mesh
    theirs = facet.Scene()
    theirs.add(facet.Mesh(v, tm.faces, mesh.normals, uvs,
                          colors=None if colours is None else colours),
               ours.objects[0].material)
    r = renderer(48, 48)
    a = r.render(ours, CAM).color
    b = r.render(theirs, CAM).color
    np.testing.assert_array_equal(a, b)
    if kind == "uvs":  # the image came along
        m = ours.objects[0].material
        assert getattr(m, "texture", None) is not None or \
            getattr(m, "base_color_texture", None) is not None
        del texture


def test_face_colours_colour_their_faces_and_a_box_stays_flat(renderer):
    """trimesh's face_colors (a box with one colour per side, as trimesh's own examples
    make): each face in its colour, each side lit evenly (it was grey and smooth-shaded:
    found in the docs' gallery)."""
    box = trimesh.creation.box((1, 1, 1))
    sides = np.array([[230, 40, 30], [30, 200, 40], [40, 60, 230]], np.uint8)
    axis = np.abs(box.face_normals).argmax(axis=1)  # x sides red, y green, z blue
    box.visual.face_colors = np.hstack([sides[axis], np.full((12, 1), 255, np.uint8)])
    scene = facet.Scene(ambient=0.0)
    scene.add(box, facet.Material(color=(1, 1, 1), ks=0.0))
    scene.add_light(facet.DirectionalLight(direction=(-1.0, -1.2, -0.8)))
    camera = facet.Camera.look_at((2.2, 1.8, 2.6), (0, 0, 0), fov_y=40)
    frame = renderer(64, 64).render(scene, camera, outputs=("color", "ids", "normals"))
    color = frame.color[..., :3].astype(int)
    hit = frame.object_ids == 0
    dominant = color[hit].argmax(axis=1)
    assert {0, 1, 2} <= set(np.unique(dominant))  # three sides, three colours
    for channel in range(3):  # each side: one lit value (flat), not a gradient
        side = hit & (color.argmax(axis=2) == channel) & (color.max(axis=2) > 40)
        values = color[side][:, channel]
        assert side.sum() > 20 and np.percentile(values, 90) - np.percentile(values, 10) <= 3


def test_a_trimesh_scene_keeps_its_graph_and_point_clouds_become_points(renderer):
    ts = trimesh.Scene()
    ts.add_geometry(trimesh.creation.icosphere(subdivisions=2), node_name="ball")
    shift = trimesh.transformations.translation_matrix([1.5, 0, 0])
    ts.add_geometry(trimesh.creation.box(), node_name="box", transform=shift)
    scene = facet.Scene()
    ids = scene.add(ts)
    assert ids == [0, 1]
    np.testing.assert_allclose(scene.objects[1].transform, shift)
    cloud = trimesh.PointCloud(np.random.default_rng(0).normal(size=(50, 3)),
                               colors=np.tile([255, 0, 0, 255], (50, 1)))
    k = scene.add(cloud)
    assert isinstance(scene.objects[k].mesh, facet.Points)
    ids_image = renderer(48, 48).render(scene, CAM, outputs=("ids",)).object_ids
    assert {0, 1, 2} <= set(np.unique(ids_image))
    merged = facet.Mesh.from_trimesh(ts)
    assert merged.face_count == sum(g.faces.shape[0] for g in ts.geometry.values())


def test_a_gltf_read_by_trimesh_keeps_its_pbr_material(tmp_path):
    from conftest import SHARED_GLTF, shared_model

    tm = trimesh.load(shared_model("NormalTangentTest/NormalTangentTest.glb", SHARED_GLTF))
    scene = facet.Scene()
    ids = scene.add(tm)
    material = scene.objects[ids[0]].material
    assert isinstance(material, facet.PbrMaterial)
    assert material.base_color_texture is not None


def test_other_objects_are_refused_in_one_line():
    with pytest.raises(facet.InputError, match="facet.Mesh"):
        facet.Scene().add(object())

"""Meshes with the same arrays are uploaded to the ray scene once (facet.render.rays.pack
same_geometry): a glTF whose nodes' meshes differ only in their materials shares its
accessors (MetalRoughSpheresNoTextures: 98 spheres of one set of accessors became 98
uploads of its 10,600 triangles and hierarchies, and every ray missed the caches). The
pictures are those of one Mesh placed several times; meshes that differ in any array stay
apart."""

from pathlib import Path

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.render.rays import pack
from facet.scene.mesh import Mesh
from facet.scene.pbr import PbrMaterial

SPHERES = Path(__file__).resolve().parents[2] / "shared" / "gltf" / \
    "MetalRoughSpheresNoTextures" / "MetalRoughSpheresNoTextures.glb"
CAMERA = Camera.look_at((0.0, 0.0, 7.0), (0.0, 0.0, 0.0), fov_y=50)


def _copy(mesh: Mesh, **changes) -> Mesh:
    arrays = dict(positions=mesh.positions.copy(), faces=mesh.faces.copy(),
                  normals=mesh.normals.copy(), uvs=None if mesh.uvs is None else
                  mesh.uvs.copy())
    return Mesh(**{**arrays, **changes})


def _scene(meshes) -> facet.Scene:
    scene = facet.Scene()
    for i, mesh in enumerate(meshes):
        scene.add(mesh, PbrMaterial(base_color=(0.2 + 0.15 * i, 0.5, 0.7 - 0.1 * i),
                                    roughness=0.3 + 0.1 * i),
                  facet.transforms.translate((1.5 * i - 2.25, 0.0, 0.0)))
    return scene


def _render(scene, engine):
    with facet.Renderer(64, 40) as r:
        frame = r.render(scene, CAMERA, engine=engine, spp=2, float_color=True,
                         outputs=("color", "depth", "ids", "normals"))
        roots = set(r._engines[engine].rays.roots.values())  # (a hierarchy each upload)
        return (frame.color, frame.depth, frame.object_ids, frame.normals), len(roots)


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_meshes_of_the_same_arrays_are_uploaded_once(engine):
    ball = facet.primitives.sphere(0.6)
    twins, uploads = _render(_scene([_copy(ball) for _ in range(4)]), engine)
    shared, _ = _render(_scene([_copy(ball)] * 4), engine)  # (Mesh normalises normals)
    assert uploads == 1
    for x, y in zip(twins, shared, strict=True):
        np.testing.assert_array_equal(x, y)
    assert len(np.unique(twins[2][twins[2] >= 0])) == 4


def test_meshes_that_differ_in_an_array_stay_apart():
    ball = facet.primitives.sphere(0.6)
    bent = ball.normals.copy()
    bent[:, 0] = -bent[:, 0]  # (the same positions and faces, other normals)
    meshes = [_copy(ball), _copy(ball), _copy(ball, normals=bent),  # (copies of one: Mesh
              _copy(ball, uvs=np.zeros((len(ball.positions), 2), np.float32))]  # normalises)
    assert pack.same_geometry(meshes, set()) == [0, 0, 2, 3]
    assert pack.same_geometry(meshes[:2], {id(meshes[1])}) == [0, 1]  # (one normal-mapped)
    bent_frame, _ = _render(_scene(meshes[:3]), "trace")
    frame, _ = _render(_scene(meshes[:2] + [_copy(ball)]), "trace")
    third = frame[2] == 2
    assert third.sum() > 30 and np.array_equal(bent_frame[2], frame[2])
    np.testing.assert_allclose(bent_frame[3][third][:, 0], -frame[3][third][:, 0], atol=1e-3)
    np.testing.assert_allclose(bent_frame[3][third][:, 1:], frame[3][third][:, 1:], atol=1e-3)


@pytest.mark.skipif(not SPHERES.exists(), reason=f"{SPHERES} is absent (../shared/gltf)")
def test_a_gltf_of_shared_accessors_uploads_them_once():
    scene = facet.load(SPHERES)
    assert len({id(o.mesh) for o in scene.objects}) > 100  # (a Mesh per glTF mesh)
    with facet.Renderer(32, 32) as r:
        r.render(scene, engine="path", spp=1)
        roots = r._engines["path"].rays.roots
        spheres = {roots[id(o.mesh)] for o in scene.objects if len(o.mesh.faces) == 10600}
    assert len(spheres) == 1  # (98 spheres of 10,600 triangles: one upload)

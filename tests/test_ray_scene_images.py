"""The ray scene's two ways of reading its arrays (glsl/trace/data.glsl): through image
units where the context has image load and store (GL 4.2: on llvmpipe cheaper than a texel
fetch), or by texelFetch (GL 3.3). Both must draw the same picture, bit for bit, in the path
tracer, the Whitted tracer and the exact channels, over every array: triangles, their
indices, vertices (normals, texture coordinates, tangents of a normal-mapped mesh),
hierarchies, instances and the top level read from textures (too many objects for the
uniform blocks), points, and emitting triangles sampled by the path tracer."""

from types import SimpleNamespace

import numpy as np
import pytest

import facet
from facet.geometry.camera import Camera
from facet.render.rays.scene import RayScene, reads_images
from facet.scene.pbr import PbrMaterial
from facet.scene.texture import Texture
from facet.scene.texture_slot import TextureSlot

from conftest import both_ways


def _scene():
    scene = facet.Scene()
    bumps = np.full((16, 16, 3), (128, 128, 255), np.uint8)
    bumps[::4, :, 0] = 230  # (a normal map that tilts: tangents are read)
    ball = facet.primitives.sphere(0.35)  # (with texture coordinates)
    for i in range(70):  # 70 objects: their rows are over a uniform block's 4096 texels
        x, y = i % 10 - 4.5, i // 10 - 3.0
        material = PbrMaterial(base_color=(0.8, 0.5, 0.3), roughness=0.4,
                               normal_texture=TextureSlot(Texture(bumps))) if i % 3 == 0 else \
            PbrMaterial(base_color=(0.3, 0.6, 0.8), emissive=(1.0, 0.75, 0.5),
                        emissive_strength=3.0) if i == 34 \
            else PbrMaterial(base_color=(0.7, 0.7, 0.7), metallic=0.5, roughness=0.3)
        scene.add(ball, material, facet.transforms.translate((x, y, 0.0)))
    scene.add(facet.primitives.plane(12.0), PbrMaterial(base_color=(0.4, 0.4, 0.4)),
              facet.transforms.translate((0, 0, -0.4)) @ facet.transforms.rotate_x(90.0))
    pts = np.random.default_rng(3).uniform(-4, 4, (40, 3)) * (1, 1, 0) + (0, 0, 0.6)
    scene.add(facet.Points(pts, radius=0.08), PbrMaterial(base_color=(0.9, 0.2, 0.2)))
    scene.add_light(facet.PointLight((2.0, 3.0, 6.0), intensity=6.0))
    return scene


@pytest.mark.parametrize("engine", ["path", "trace"])
def test_images_and_texel_fetches_draw_the_same_picture(engine, renderer):
    if not reads_images(renderer(8, 8).ctx):
        pytest.skip("this context has no image load and store (GL 4.2)")
    scene = _scene()
    camera = Camera.look_at((0.0, -3.0, 9.0), (0.0, 0.0, 0.0), fov_y=55)

    def render():
        with facet.Renderer(64, 48) as r:
            frame = r.render(scene, camera, engine=engine, spp=2, float_color=True,
                             outputs=("color", "depth", "ids", "normals", "uv"))
            rays = r._engines[engine].rays
            used = any("SCENE_IMAGES" in defines for _, defines in rays._defines.values())
            return (frame.color, frame.depth, frame.object_ids, frame.normals, frame.uv,
                    used, rays._in_blocks)

    a, b = both_ways(RayScene, "use_images", render)
    assert a[5] and not b[5]  # (each way was taken)
    assert not a[6]  # (instances and top level from their textures)
    for x, y in zip(a[:5], b[:5], strict=True):
        np.testing.assert_array_equal(x, y)
    ids = a[2]
    assert len(np.unique(ids[ids >= 0])) > 30  # (balls, the floor and points in view)
    assert a[0][..., :3].mean() > 0.02


def test_images_need_their_two_extensions():
    """The programs are GLSL 3.30: image load and store and layout bindings are required
    as extensions, so a context must list both (a GL 4.2 one does)."""
    assert not reads_images(SimpleNamespace(version_code=450, extensions=set()))
    assert not reads_images(SimpleNamespace(version_code=330, extensions=set()))
    assert not reads_images(SimpleNamespace(
        version_code=410, extensions={"GL_ARB_shader_image_load_store"}))
    assert reads_images(SimpleNamespace(version_code=410, extensions={
        "GL_ARB_shader_image_load_store", "GL_ARB_shading_language_420pack"}))

"""Long-lived renderers stay bounded: scenes that differ only in light order share their
programs, and the program cache keeps at most MAX_PROGRAMS (least recently used go), so a
thousand scenes with random light sets do not grow memory."""

import random

import numpy as np

from facet.geometry.camera import Camera
from facet.render.raster.forward import MAX_PROGRAMS
from facet.render.renderer import Renderer
from facet.scene import DirectionalLight, PointLight, Scene, SpotLight, primitives

MAKERS = [lambda: DirectionalLight((-1, -1, -1), intensity=0.5),
          lambda: PointLight((1, 2, 2), intensity=2.0),
          lambda: SpotLight((0, 2, 2), (0, -1, -1), intensity=2.0)]


def _rss_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def test_light_order_shares_programs_and_the_cache_is_bounded():
    sphere = primitives.sphere(0.5)
    camera = Camera.look_at((0, 0, 3), (0, 0, 0), near=1, far=10)
    rng = random.Random(7)
    with Renderer(16, 16, msaa=0) as r:
        def render(kinds):
            scene = Scene()
            scene.add(sphere)
            for k in kinds:
                scene.add_light(MAKERS[k]())
            return r.render(scene, camera, outputs=("color",)).color

        # Order does not matter: one program, the same picture.
        a = render([0, 1, 2])
        count = len(r._engine("raster").forward.programs)
        b = render([2, 0, 1])
        assert len(r._engine("raster").forward.programs) == count
        np.testing.assert_allclose(a.astype(int), b.astype(int), atol=1)
        for _ in range(100):  # warm-up: the allocator's pools, compiled programs
            render([rng.randrange(3) for _ in range(rng.randint(1, 4))])
        before = _rss_mib()
        for _ in range(900):
            render([rng.randrange(3) for _ in range(rng.randint(1, 4))])
        assert len(r._engine("raster").forward.programs) <= MAX_PROGRAMS
        assert _rss_mib() - before < 50

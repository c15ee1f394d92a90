"""KHR_materials_iridescence: the thin film's Fresnel term (glsl/lib/iridescence.glsl)
against a numpy transcription of the extension's formulas (Belcour and Barla's model as
its implementation notes give it) at several thicknesses, angles, film indices and base
reflectances; the extension read from glTF; IridescenceSuzanne drawn in every engine with
the metal's film colours (teal with purple rims, as its screenshot), and no film where
the factor is 0."""

import numpy as np
import pytest

import facet
from facet.gl.fullscreen import FullScreenPass, fullscreen_vertex
from facet.gl.glsl_source import glsl_root
from facet.gl.shaders import compile_program
from facet.scene.pbr import PbrMaterial

from conftest import SHARED_GLTF, shared_model

XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])


def _sensitivity(opd, shift):
    phase = 2 * np.pi * opd * 1e-9
    val = np.array([5.4856e-13, 4.4201e-13, 5.2481e-13])
    pos = np.array([1.6810e+06, 1.7953e+06, 2.2084e+06])
    var = np.array([4.3278e+09, 9.3046e+09, 6.6121e+09])
    xyz = val * np.sqrt(2 * np.pi * var) * np.cos(pos * phase + shift) * np.exp(-phase ** 2 * var)
    xyz[0] += 9.7470e-14 * np.sqrt(2 * np.pi * 4.5282e+09) * np.cos(2.2399e+06 * phase + shift[0]) \
        * np.exp(-4.5282e+09 * phase ** 2)
    return XYZ_TO_REC709 @ (xyz / 1.0685e-7)


def _schlick(f0, c):
    return f0 + (1 - f0) * (1 - c) ** 5


def film_fresnel(outside, eta2, cos1, thickness, base_f0):
    """The extension's F_iridescence (its implementation notes, with the Sample Viewer's
    fade of the film's index below 30 nm and total internal reflection)."""
    t = np.clip(thickness / 0.03, 0, 1)
    film = outside + (eta2 - outside) * t * t * (3 - 2 * t)  # smoothstep(0, 0.03, d)
    sin2 = (outside / film) ** 2 * (1 - cos1 ** 2)
    if sin2 >= 1:
        return np.ones(3)
    cos2 = np.sqrt(1 - sin2)
    r12 = _schlick(((film - outside) / (film + outside)) ** 2, cos1)
    t121 = 1 - r12
    phi21 = np.pi - (np.pi if film < outside else 0.0)
    sq = np.sqrt(np.clip(base_f0, 0, 0.9999))
    base_ior = (1 + sq) / (1 - sq)
    r23 = _schlick(((base_ior - film) / (base_ior + film)) ** 2, cos2)
    phi23 = np.where(base_ior < film, np.pi, 0.0)
    opd = 2 * film * thickness * cos2
    phi = phi21 + phi23
    r123 = np.clip(r12 * r23, 1e-5, 0.9999)
    rs = t121 ** 2 * r23 / (1 - r123)
    f, cm = r12 + rs, rs - t121
    for m in (1, 2):
        cm = cm * np.sqrt(r123)
        f = f + cm * 2 * _sensitivity(m * opd, m * phi)
    return np.maximum(f, 0)


CASES = [(1.0, 1.3, c, d, f0) for c in (1.0, 0.7, 0.3, 0.05) for d in (0.0, 120.0, 250.0, 400.0,
                                                                      800.0)
         for f0 in ((0.04, 0.04, 0.04), (0.95, 0.64, 0.54))] + \
        [(1.0, 1.8, 0.5, 300.0, (0.04, 0.04, 0.04)), (1.5, 1.2, 0.2, 300.0, (0.5, 0.5, 0.5)),
         (1.5, 1.2, 0.05, 300.0, (0.04, 0.04, 0.04))]  # (the last: total internal reflection)

SHADER = """#version 330 core
#include "lib/iridescence.glsl"
uniform vec4 u_case[64];   // outside ior, film ior, cos, thickness
uniform vec3 u_f0[64];
out vec4 f_color;
void main() {
    int i = int(gl_FragCoord.x);
    vec4 c = u_case[i];
    f_color = vec4(thin_film_fresnel(c.x, c.y, c.z, c.w, u_f0[i]), 1.0);
}
"""


def test_the_film_fresnel_is_the_extensions_formula(renderer):
    ctx = renderer(8, 8).ctx
    with ctx:
        got = _film_on_gl(ctx)
    want = np.array([film_fresnel(*c[:4], np.array(c[4])) for c in CASES])
    np.testing.assert_allclose(got, want, atol=2e-4)
    assert np.ptp(want[5:10], axis=0).max() > 0.05  # (colours vary with thickness)
    np.testing.assert_allclose(want[-1], 1.0)


def _film_on_gl(ctx):
    program = compile_program(ctx, fullscreen_vertex(), glsl_root() / "iridescence_test.frag",
                              fragment_text=SHADER)
    quad = FullScreenPass(ctx, None, program=program)
    target = ctx.framebuffer([ctx.texture((len(CASES), 1), 4, dtype="f4")])
    target.use()
    cases = np.zeros((64, 4), np.float32)
    f0s = np.zeros((64, 3), np.float32)
    cases[:len(CASES)] = [c[:4] for c in CASES]
    f0s[:len(CASES)] = [c[4] for c in CASES]
    program.gl["u_case"].write(cases.tobytes())
    program.gl["u_f0"].write(f0s.tobytes())
    quad.draw()
    got = np.frombuffer(target.read(components=4, dtype="f4"), np.float32).reshape(-1, 4)[:, :3]
    target.release()
    quad.release()
    return got


def test_iridescence_is_read_from_gltf():
    path = shared_model("IridescenceSuzanne/IridescenceSuzanne.glb", SHARED_GLTF)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = facet.load(path)
    films = [o.material for o in scene.objects]
    assert all(m.iridescence == 1.0 for m in films)
    assert {m.iridescence_ior for m in films} == {1.33, 1.8}
    assert any(m.iridescence_thickness_texture is not None for m in films)


@pytest.mark.parametrize("engine", ["raster", "trace", "path"])
def test_a_film_on_a_metal_shows_its_colours(engine):
    """A grey metal sphere under a grey sky: with a 250 nm film of index 1.3 its face turns
    the colour the formula gives at normal incidence (the sky's grey times F_film there),
    its rim another; without the film it stays grey."""
    def picture(iridescence):
        scene = facet.Scene(ambient=0.0)
        scene.add(facet.shapes.Sphere(1.0), PbrMaterial(
            base_color=(0.8, 0.8, 0.8), metallic=1.0, roughness=0.05, iridescence=iridescence,
            iridescence_ior=1.3, iridescence_thickness_max=250.0))
        cam = facet.Camera.look_at((0, 0, 4), (0, 0, 0), fov_y=40, near=0.5, far=20)
        with facet.Renderer(48, 48) as r:
            return r.render(scene, cam, engine=engine, spp=16 if engine == "path" else 1,
                            float_color=True, lights="scene",
                            environment={"color": [0.5, 0.5, 0.5]}).color[..., :3]

    film, bare = picture(1.0), picture(0.0)
    face_film, face_bare = film[22:26, 22:26].reshape(-1, 3).mean(0), \
        bare[22:26, 22:26].reshape(-1, 3).mean(0)
    want = film_fresnel(1.0, 1.3, 1.0, 250.0, np.full(3, 0.8))
    assert np.ptp(face_bare) < 0.02 * face_bare.mean()  # a grey metal: grey
    # The film's colour at the face: the hue of F_film at normal incidence.
    got = face_film / face_film.sum()
    np.testing.assert_allclose(got, want / want.sum(), atol=0.03)

"""The scene-to-GPU contract's bindings (facet.gl.bindings): every texture unit and uniform
block has one name and one number, and a program facet builds binds each sampler it declares
to its own unit. Differential: a skinned mesh with a metallic-roughness texture draws what
the same vertices placed by hand draw (its joints' texture once shared the
metallic-roughness texture's unit)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import facet
from facet.geometry.camera import Camera
from facet.render.rays.scene import reads_images

from test_animation import ref_skin, skinned_strip


def _textured(material_slot: str):
    """A dielectric whose metallic-roughness (or other) image is one flat texel: roughness
    0.25, metal 1, gold base: wrong texels (another texture on its unit) show at once."""
    pixels = np.zeros((4, 4, 4), np.uint8)
    pixels[..., 1], pixels[..., 2], pixels[..., 3] = 64, 255, 255  # G roughness, B metal
    slot = facet.TextureSlot(facet.Texture(pixels))
    return facet.PbrMaterial(base_color=(1.0, 0.8, 0.3, 1.0), metallic=1.0, roughness=1.0,
                             **{f"{material_slot}_texture": slot})


def test_a_skinned_mesh_with_a_metallic_roughness_texture_draws_as_placed_by_hand(
        tmp_path, renderer):
    """The strip skinned on the GPU at t = 0.6 and a plain mesh of the reference's
    vertices, both with one metallic-roughness texture, under one light: the same colour
    within 2/255 away from edges. (Old code: the joints' texture took unit 14, the
    metallic-roughness slot's, and the strip was shaded by joint matrices: up to 0.77
    away.)"""
    scene = facet.load(skinned_strip(tmp_path))
    material = _textured("metallic_roughness")
    scene.objects[0] = replace(scene.objects[0], material=material)
    want, faces = ref_skin(0.6)
    plain = facet.Scene()
    plain.add(facet.Mesh(want, faces), material)
    for s in (scene, plain):
        s.add_light(facet.DirectionalLight(direction=(-0.2, -0.3, -1.0), intensity=1.0))
        s.ambient = np.full(3, 0.2)
    cam = Camera.look_at((0.0, 1.2, 3), (0.0, 1.2, 0), fov_y=40)
    r = renderer(128, 128)
    a = r.render(scene, cam, time=0.6, outputs=("color", "ids"), shading="pbr")
    b = r.render(plain, cam, outputs=("color", "ids"), shading="pbr")
    inside = (a.object_ids >= 0) & (b.object_ids >= 0)
    for axis in (0, 1):  # away from the silhouette
        for shift in (1, -1):
            inside &= np.roll(inside, shift, axis)
    assert inside.sum() > 300, inside.sum()
    diff = np.abs(a.color[..., :3].astype(int) - b.color[..., :3].astype(int))[inside]
    assert diff.max() <= 2, diff.max()


def _every_slot_material(**extra):
    """A metallic-roughness material with an image in every texture slot (and the clear
    coat, sheen and transmission that use theirs)."""
    from facet.scene.pbr import SLOTS

    pixels = np.full((4, 4, 4), 200, np.uint8)
    tex = facet.Texture(pixels)
    slots = {f"{s}_texture": facet.TextureSlot(tex, texcoord=0) for s in SLOTS}
    return facet.PbrMaterial(metallic=0.2, roughness=0.3, clearcoat=0.5, sheen_color=(0.3,) * 3,
                             transmission=0.5, thickness=0.1, **slots, **extra)


def _variant_scenes(tmp_path):
    """Scenes that make facet build its program variants: both material models, every
    texture slot, skinned, morphed, instanced, points, lines and clouds, mirrors, an
    environment, shadows, MASK and BLEND (light kinds and colour formats change defines,
    not the samplers a program declares)."""
    from facet.scene import primitives, shapes
    from facet.scene.environment import Environment

    from test_animation import morphed_quad

    T = facet.transforms
    base = facet.Scene(ambient=0.2)
    base.add_light(facet.DirectionalLight(direction=(-0.3, -1, -0.4)))
    base.add(primitives.sphere(0.5), _every_slot_material(), T.translate((-1, 0, 0)))
    base.add(primitives.cube(0.5), _every_slot_material(alpha_mode="MASK"))
    base.add(primitives.cube(0.4), facet.PbrMaterial(base_color=(1, 0, 0, 0.5),
                                                     alpha_mode="BLEND"), T.translate((1, 0, 0)))
    base.add(primitives.plane(4), facet.Material(color=(0.8, 0.8, 0.8), reflectivity=0.4,
                                                 mirror=True), T.translate((0, -1, 0)))
    tex = facet.Texture(np.full((4, 4, 3), 180, np.uint8))
    base.add(primitives.torus(), facet.Material(texture=tex, reflectivity=0.3, ior=1.4),
             T.translate((0, 1, 0)))
    for k in range(3):  # one mesh and material, three places: instanced
        base.add(primitives.cube(0.2), facet.Material(color=(0.2, 0.9, 0.2)),
                 T.translate((k - 1.0, -0.5, 1.0)))
    base.add(facet.Points(np.random.default_rng(1).random((50, 3)), size=4), facet.Material())
    base.add(facet.Lines(np.random.default_rng(2).random((10, 3)), width=2), facet.Material())
    base.add(shapes.Sphere(0.3), facet.PbrMaterial(emissive=(1, 1, 1), emissive_strength=2.0),
             T.translate((0, 2, 0)))
    env = base.view()
    env.environment = Environment.sky(size=8)
    skinned = facet.load(skinned_strip(tmp_path))
    skinned.objects[0] = replace(skinned.objects[0], material=_every_slot_material())
    morphed = facet.load(morphed_quad(tmp_path))
    return [(base, {}), (env, {}), (skinned, {"time": 0.6}), (morphed, {"time": 1.5})]


def test_every_program_binds_each_sampler_to_its_own_unit(tmp_path, renderer, monkeypatch):
    """Walks the programs facet links for scenes that use every engine, shading model,
    texture slot, pose (skinned, morphed), instancing, points and lines, mirrors,
    environments, shadows and transparency: in each, every active sampler
    holds the unit facet.gl.bindings names for it, and no two share one."""
    from facet.gl import bindings

    linked: list[tuple[str, dict]] = []
    bind = bindings.bind

    def recording(program, own, label="program"):
        bind(program, own, label)
        linked.append((label, bindings.samplers(program), bindings.images(program)))

    monkeypatch.setattr(bindings, "bind", recording)
    r = facet.Renderer(32, 32)  # a fresh one: every program is linked in this test
    as_images = reads_images(r.ctx)
    outputs = ("color", "depth", "ids", "normals", "position", "uv")
    cam = Camera.look_at((0, 2, 6), (0, 0, 0), fov_y=50)
    try:
        for scene, opts in _variant_scenes(tmp_path):
            # (the Phong family's programs declare the same samplers: one of them will do)
            r.render(scene, cam, shadows=True, outputs=outputs, **opts)
            for engine in ("trace", "path"):
                r.render(scene, cam, engine=engine, outputs=outputs,
                         **({"aa": "ssaa:grid:1"} | opts))
    finally:
        r.close()
    assert len(linked) > 25, len(linked)
    units = bindings.SAMPLERS
    assert len(set(units.values())) == len(units)  # one unit, one name
    for label, samplers, images in linked:
        assert all(samplers[n] == units[n] for n in samplers), (label, samplers)
        assert len(set(samplers.values())) == len(samplers), (label, samplers)
        assert images <= set(bindings.IMAGES), (label, images)
    seen = {n for _, s, _ in linked for n in s}
    # The ray scene's arrays are images where the context reads them so (GL 4.2).
    arrays = {n for _, _, i in linked for n in i} if as_images else seen
    assert {"u_joints", "u_targets", "u_tex_mr", "u_tex_clearcoat_normal", "u_behind",
            "u_irradiance", "u_shadow_atlas", "u_emitters", "u_mirror",
            "u_edl_shade"} <= seen, sorted(set(units) - seen)
    assert {"u_tris", "u_nodes", "u_vertices", "u_tri_index"} <= arrays, arrays


def test_a_sampler_without_a_unit_is_refused_at_link_time(renderer):
    """facet's own GLSL may not declare a sampler the table lacks: the program fails to
    link with one line naming it (a unit picked by hand is how two textures met)."""
    import pytest

    from facet.errors import ShaderError
    from facet.gl import bindings

    ctx = renderer(8, 8).ctx
    with ctx:
        prog = ctx.program(
            vertex_shader="#version 330\nvoid main() { gl_Position = vec4(0.0); }",
            fragment_shader="#version 330\nuniform sampler2D u_nobody; out vec4 c;\n"
                            "void main() { c = texture(u_nobody, vec2(0.5)); }")
        try:
            with pytest.raises(ShaderError, match="u_nobody"):
                bindings.bind(prog, own=True)
            bindings.bind(prog, own=False)  # a user's own sampler is left to its host
        finally:
            prog.release()


def test_the_image_units_fit_every_gl_4_2_fragment_shader():
    from facet.gl import bindings

    assert len(bindings.IMAGES) <= bindings.MAX_IMAGES == 8
    assert sorted(bindings.IMAGES.values()) == list(range(len(bindings.IMAGES)))


def test_an_image_without_a_unit_is_refused_at_link_time(renderer):
    """Nor an image uniform the table of image units lacks (IMAGES)."""
    import pytest

    from facet.errors import ShaderError
    from facet.gl import bindings

    ctx = renderer(8, 8).ctx
    if not reads_images(ctx):
        pytest.skip("this context has no image load and store (GL 4.2)")
    with ctx:
        prog = ctx.program(
            vertex_shader="#version 330\nvoid main() { gl_Position = vec4(0.0); }",
            fragment_shader="#version 420\nlayout(binding = 5, rgba32f) readonly uniform "
                            "image2D u_nobody; out vec4 c;\n"
                            "void main() { c = imageLoad(u_nobody, ivec2(0)); }")
        try:
            with pytest.raises(ShaderError, match="u_nobody"):
                bindings.bind(prog, own=True)
            bindings.bind(prog, own=False)
            assert bindings.images(prog) == {"u_nobody"}
        finally:
            prog.release()

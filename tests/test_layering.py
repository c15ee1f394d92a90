"""Layering: geometry and scene never load GL; the CLI's --help loads nothing heavy."""

import json
import subprocess
import sys


def _loaded_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys, json\n"
                          "print(json.dumps(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.splitlines()[-1]))


def test_geometry_and_scene_do_not_import_gl():
    mods = _loaded_after("import facet.geometry, facet.scene, facet.gl.glsl_source\n"
                         "import facet.render.shading\n"
                         "facet.scene.Mesh([[0,0,0],[1,0,0],[0,1,0]], [[0,1,2]])")
    assert "facet.geometry.camera" in mods and "facet.scene.mesh" in mods
    assert not {m for m in mods if m.split(".")[0] in ("moderngl", "glfw", "glcontext")}


def test_cli_help_is_light():
    mods = _loaded_after("import facet.cli\nfacet.cli.build_parser()")
    heavy = {"numpy", "trimesh", "moderngl", "PIL", "glfw"}
    assert not heavy & {m.split(".")[0] for m in mods}


def test_renderer_does_load_gl():
    """The check above can fail: the renderer module does pull in moderngl."""
    mods = _loaded_after("import facet.render.renderer")
    assert "moderngl" in mods

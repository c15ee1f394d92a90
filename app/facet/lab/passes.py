"""One pass of a Shadertoy-style program compiled (facet.lab.shadertoy): its text read
afresh (from its file, or from the JSON export read again), its dialect decided
(facet.lab.dialect), the common file and the user's file included into facet's wrapper
(glsl/shadertoy/host.frag for Shadertoy, viewer.frag for glslViewer), with the pass's
defines and its channels' sampler types; a compiler error caused by the user's file is
blamed on it.
"""

from __future__ import annotations

import warnings

from ..errors import InputError, ShaderError
from ..gl.fullscreen import fullscreen_vertex
from ..gl.glsl_source import display_path, glsl_root
from ..gl.shaders import Program, compile_program
from . import project as P
from .dialect import GLSLVIEWER, blame_user, declared_inputs, prepare
from .shadertoy_json import load_shadertoy_json


def compile_pass(ctx, project: P.Project, p: P.Pass, types) -> tuple[Program, str]:
    """(program, dialect) of pass ``p``; ``types``: per channel 0-3 its GLSL sampler type
    (sampler2D, samplerCube or sampler3D)."""
    name = display_path(p.path)
    try:
        text = source(project, p)
    except UnicodeDecodeError:
        raise InputError(f"{name}: not a text file (GLSL must be UTF-8)") from None
    prepared = prepare(text, name, cube=p.key == "cube")
    texts = {p.path: prepared.text}
    includes = []
    wanted = set(prepared.defines)
    common = project.common
    if common is not None and prepared.kind != GLSLVIEWER:
        code = project.common_code
        if code is None:
            from ..guard import read_text

            code = read_text(common, "common file")
        shared = prepare(code, display_path(common), common=True)
        texts[common] = shared.text
        wanted |= set(shared.defines) - {"FACET_GLOBAL_MAIN"}
        # (an input one file declares is not declared again for the other)
        wanted -= {f"FACET_DECLARE_{n}" for n in declared_inputs(code) |
                   declared_inputs(prepared.text)}
        includes.append(f'#include "{common.resolve()}"')
    if prepared.rename_main:  # (the file's main() beside mainImage: not facet's)
        includes.append("#define main facet_users_main")
    includes.append(f'#include "{p.path.resolve()}"')
    if prepared.rename_main:
        includes.append("#undef main")
    host = "viewer.frag" if prepared.kind == GLSLVIEWER else "host.frag"
    host_path = glsl_root() / "shadertoy" / host
    stage = host_path.read_text().replace("\nFACET_USER_CODE\n",
                                          "\n" + "\n".join(includes) + "\n")
    defines = {"HW_PERFORMANCE": 1, **p.defines}
    if prepared.kind != GLSLVIEWER:
        defines.update(dict.fromkeys(sorted(wanted)))
    for n, kind in enumerate(types):
        defines[f"FACET_CHANNEL{n}"] = kind
    if p.key == "cube":
        defines["FACET_CUBE_PASS"] = None
    if prepared.frag_color:
        defines["FACET_FRAG_COLOR"] = None
    try:
        prog = compile_program(ctx, fullscreen_vertex(), host_path, defines,
                               fragment_text=stage, texts=texts)
    except ShaderError as exc:
        raise blame_user(exc, name, prepared.text) from None
    return prog, prepared.kind


def source(project: P.Project, p: P.Pass) -> str:
    """The pass's current text (from its file, or from the export read again)."""
    if p.code is None:
        from ..guard import read_text

        return read_text(p.path, "shader file")
    origin = project.origin
    if origin is not None and origin.suffix.lower() == ".json" and origin.is_file():
        with warnings.catch_warnings():  # (said when the export was first read)
            warnings.simplefilter("ignore")
            fresh = load_shadertoy_json(origin, project.media).passes.get(p.key)
        if fresh is not None:
            return fresh.code
    return p.code

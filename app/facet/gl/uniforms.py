"""Users' uniforms, for mesh shaders and Shadertoy passes alike: a value is checked against
what the linked programs declare (name, GLSL type, array length, integer or not) before it
is written, and errors say what the program has instead."""

from __future__ import annotations

import warnings

import numpy as np

from ..boundary import reals
from ..errors import FacetWarning, InputError
from .shaders import INT_TYPES, Program

_SIZES = {"float": 1, "int": 1, "bool": 1, "uint": 1, "mat2": 4, "mat3": 9, "mat4": 16}


def components(gl_type: str) -> int:
    """Numbers in one value of a GLSL type (vec3: 3, mat4: 16)."""
    return _SIZES.get(gl_type, int(gl_type[-1]) if gl_type[-1].isdigit() else 1)


def check_uniform(name: str, value, programs, filled, where: str) -> np.ndarray | None:
    """``value`` as the numbers to write into user uniform ``name`` of ``programs``; None
    when the programs declare it but the compiler removed it (a warning says so once).
    ``filled``: the names facet sets itself. InputError for anything else."""
    active: dict[str, tuple[str, int]] = {}
    for prog in programs:
        active.update(prog.uniform_types())
    if name not in active or name in filled:
        if name not in filled and any(name in prog.declared for prog in programs):
            warnings.warn(f"{where}: uniform {name} is declared but unused (the compiler "
                          "removed it); its value has no effect", FacetWarning, stacklevel=3)
            return None
        user = sorted(n for n in active if n not in filled)
        raise InputError(f"{where}: no user uniform named {name!r}; it has: "
                         f"{', '.join(user) or 'none'}")
    gl_type, length = active[name]
    size = components(gl_type) * length
    shown = f"{gl_type}[{length}]" if length > 1 else gl_type
    values = np.atleast_1d(reals(value, f"{where}: uniform {name}: value",
                                 most=1 << 20)).ravel()
    if values.size != size or not np.all(np.isfinite(values)):
        raise InputError(f"{where}: uniform {name} is {shown}: expected {size} finite "
                         f"number(s) as its value, got {values.size}"
                         f"{'' if np.all(np.isfinite(values)) else ', not all finite'}")
    if gl_type in INT_TYPES and not np.all(values == np.round(values)):
        raise InputError(f"{where}: uniform {name} is {shown}: expected integers, got "
                         f"{values.tolist()}")
    return values


def write_uniform(prog: Program, name: str, values: np.ndarray) -> None:
    """Write checked ``values`` into ``prog``'s uniform ``name`` if the program has it."""
    if name in prog.gl:
        member = prog.gl[name]
        integer = prog.uniform_types()[name][0] in INT_TYPES
        member.write(values.astype("i4" if integer else "f4").tobytes())


def write_sized(member, value) -> None:
    """A value into a uniform of whatever size the user's shader declared it with (u_mouse
    as vec2 or vec4, u_frame as int or float)."""
    n = getattr(member, "dimension", 1)
    if isinstance(value, tuple):
        value = tuple(value[:n]) + (0.0,) * (n - len(value)) if n > 1 else value[0]
    if member.gl_type in (0x1404, 0x8B56):  # int, bool
        value = int(value) if not isinstance(value, tuple) else tuple(int(v) for v in value)
    member.value = value

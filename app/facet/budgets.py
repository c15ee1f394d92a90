"""Resource budgets for what facet reads, allocates and waits for on an input's behalf,
stated once (no numpy, no GL). An input beyond a budget is refused with one line naming the
budget, before the memory is allocated or the wait begins; up to it, facet's work is linear
in the input.

Each budget is raised (or lowered) with the environment variable ``FACET_BUDGET_<NAME>``
(e.g. ``FACET_BUDGET_PIXELS=1000000000``) or ``facet --budget NAME=VALUE COMMAND ...``;
``facet info`` prints them.
"""

from __future__ import annotations

import os

from .errors import InputError

# name: (default, what it bounds)
BUDGETS = {
    "pixels": (1 << 26, "pixels of one image: a render's size, textures, environments, "
               "channels (8192 x 8192)"),
    "file_bytes": (1 << 31, "bytes of one file read into memory: models, glTF buffers, "
                   "images, includes, manifests"),
    "elements": (1 << 28, "numbers in one glTF accessor"),
    "gltf_items": (1_000_000, "accessors, meshes, materials, ... of one glTF file, each"),
    "nodes": (200_000, "nodes of one glTF file"),
    "objects": (50_000, "objects of one scene file"),
    "depth": (1_000, "levels of nesting: node hierarchies, parent chains, includes, JSON"),
    "shader_bytes": (1 << 20, "bytes of one shader with everything it includes"),
    "wait_seconds": (10, "seconds to wait for a window system to answer"),
}


def budget(name: str) -> int:
    """The budget ``name`` (its default, or FACET_BUDGET_<NAME> when set)."""
    default = BUDGETS[name][0]
    text = os.environ.get(f"FACET_BUDGET_{name.upper()}")
    if text is None:
        return default
    try:
        value = int(text.strip().replace("_", ""))
    except ValueError:
        value = -1
    if value < 1:
        raise InputError(f"FACET_BUDGET_{name.upper()}={text!r}: expected a whole number >= 1")
    return value


def set_budget(text: str) -> None:
    """``NAME=VALUE`` (the command line's --budget): this process's budget NAME."""
    name, eq, value = text.partition("=")
    name = name.strip().lower()
    if not eq or name not in BUDGETS:
        raise InputError(f"--budget {text!r}: expected NAME=VALUE with NAME one of "
                         f"{', '.join(BUDGETS)}")
    os.environ[f"FACET_BUDGET_{name.upper()}"] = value.strip()
    budget(name)  # checked now


def check_pixels(width: int, height: int, what: str) -> None:
    """One line when a ``width`` x ``height`` image is beyond the pixel budget (before any
    of it is allocated)."""
    limit = budget("pixels")
    if width * height > limit:
        raise InputError(f"{what}: {width}x{height} is {width * height / 2**20:.0f} megapixels, "
                         f"beyond facet's budget of {limit / 2**20:.0f} megapixels; make it "
                         "smaller, or raise the budget with --budget pixels=N")


def describe() -> dict[str, int]:
    return {name: budget(name) for name in BUDGETS}

"""The viewer's key map: key -> action with a one-line description (no GL, no glfw, so
``facet view --help`` can print it).

``facet view --help`` and the ``h`` key print it; later features add rows to ``KEYMAP``.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..options.values import ENGINES, SHADING

TURNTABLE_FRAMES = 36
AA_CYCLE = ("msaa:4", "none", "ssaa:jittered:16", "ssaa:jittered:64")  # the a key's modes


@dataclass(frozen=True)
class Action:
    method: str  # Viewer method to call
    description: str


# Key -> action; ``h`` prints this table. Later features add rows here.
KEYMAP: dict[str, Action] = {
    "f": Action("frame_model", "frame the model"),
    "r": Action("reset", "reset the view: the camera, shading, wireframe, background, "
                "shadows, anti-aliasing and lights as it opened (the engine stays)"),
    "o": Action("toggle_projection", "perspective / orthographic"),
    "m": Action("cycle_shading", f"shading model: {', '.join(SHADING)}"),
    "w": Action("toggle_wireframe", "wireframe overlay"),
    "a": Action("cycle_aa", f"anti-aliasing: {', '.join(AA_CYCLE)} (supersampling "
                "refines while the camera is still)"),
    "l": Action("toggle_headlight", "lights follow the camera / stay in the scene"),
    "x": Action("toggle_shadows", "shadows (every light)"),
    "e": Action("cycle_engine", f"engine: {', '.join(ENGINES)} (the tracers refine while "
                "the camera is still)"),
    "b": Action("cycle_background", "background colour"),
    "s": Action("screenshot", "save a screenshot (PNG, window size)"),
    "S": Action("screenshot_2x", "save a 2x screenshot (offscreen render)"),
    "t": Action("record_turntable", f"record a {TURNTABLE_FRAMES}-frame turntable GIF"),
    "p": Action("toggle_playing", "play / pause the animations (and u_time)"),
    ",": Action("step_back", "pause, one frame (1/30 s) back"),
    ".": Action("step_forward", "pause, one frame (1/30 s) on"),
    "[": Action("second_back", "pause, one second back"),
    "]": Action("second_forward", "pause, one second on"),
    "h": Action("print_help", "print this key map"),
    "?": Action("print_help", "print this key map"),
    "q": Action("quit", "quit (also Esc)"),
    "1-9": Action("use_camera", "the scene file's cameras, in order"),
}


def help_text(front: str = "window") -> str:
    """The key map for a ``front``: "window" (glfw), or "page" (a served page, a notebook
    widget: no quitting from it, no files dropped onto it)."""
    page = front == "page"
    rows = [f"  {key:5} {action.description}" for key, action in KEYMAP.items()
            if not (page and action.method == "quit")]
    mouse = ["  drag  orbit (left), pan (right / middle / shift+left)", "  wheel zoom to cursor"]
    if not page:
        mouse.append("  drop  a mesh or scene file onto the window to open it")
    return "facet view keys:\n" + "\n".join(rows + mouse)



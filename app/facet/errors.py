"""The exceptions facet raises for problems a user can fix.

Every error a user can cause is a ``FacetError``; the CLI prints its message on one line and
exits with status 2. Anything else escaping is a bug in facet.
"""


class FacetError(Exception):
    """Base class: a problem with the user's input or environment, with a message that says
    what went wrong, where, and how to fix it."""


class InputError(FacetError, ValueError):
    """A bad argument or value (size, vector, option)."""


class MeshError(FacetError):
    """A mesh file that cannot be read: missing, unknown format, truncated, empty, not finite."""


class ShaderError(FacetError):
    """A GLSL problem: missing include, include cycle, or a compile/link error.

    ``str(err)`` reads like a compiler: ``glsl/lib/lighting.glsl:12:19: error: ...``.
    ``diagnostics`` holds (path, line, column, severity, message) tuples.
    """

    def __init__(self, message: str, diagnostics=()):
        super().__init__(message)
        self.diagnostics = list(diagnostics)
        self.missing: list = []  # included files that do not exist (yet): worth watching


class ContextError(FacetError):
    """No OpenGL context could be made (missing EGL/Mesa, no driver)."""


class SceneError(InputError):
    """A scene file that cannot be used: bad TOML, a wrong type, an unknown key, a missing
    file, a parent cycle. The message names the file and the key path, e.g.
    ``scene.toml: objects[2].material.shininess: expected a number >= 0, got "shiny"``."""


class FacetWarning(UserWarning):
    """Something facet changed for the user and says so in one line (a sample count capped,
    MSAA clamped to what the GL offers); the CLI prints it as ``facet: warning: ...``."""


def show_warning(message, category, filename, lineno, file=None, line=None):
    """Every warning as one line, ``facet: warning: ...`` (for ``warnings.showwarning``:
    the CLI and batch workers): facet's own as they are, a library's (numpy, Pillow,
    trimesh) with its kind, never with a source path and line of code from inside a
    library."""
    import sys

    text = str(message).strip().splitlines()[0] if str(message).strip() else category.__name__
    if not issubclass(category, FacetWarning):
        text = f"{text} ({category.__name__})"
    print(f"facet: warning: {printable(text)}", file=sys.stderr)


def printable(text, keep_newlines: bool = False) -> str:
    """``text`` with control characters escaped (``\\n``, ``\\x1b``, ...): a name from
    the input printed raw could end a line early, rewrite it (CR) or drive the terminal
    (ESC). ``keep_newlines`` keeps line breaks for multi-line compiler output."""
    text = str(text)
    keep = "\n" if keep_newlines else ""
    if not any((ord(c) < 32 or ord(c) == 127) and c not in keep for c in text):
        return text
    return "".join(c.encode("unicode_escape").decode("ascii")
                   if (ord(c) < 32 or ord(c) == 127) and c not in keep else c for c in text)


def gl_out_of_memory(exc: BaseException) -> str | None:
    """One line for a GL error that means the driver could not make buffers (an
    incomplete framebuffer, out of memory), or None for any other exception: the
    command line's and batch workers' last word on a size the budget let through."""
    text = str(exc).strip()
    if type(exc).__module__.split(".")[0] != "moderngl" or not any(
            key in text.lower() for key in ("framebuffer", "out of memory", "outofmemory")):
        return None
    return (f"the GL could not make its buffers ({text}): most likely out of memory for "
            "this size; render smaller (--size), with fewer samples (--msaa, --ssaa), or "
            "on a larger GPU")

"""Where facet's bundled data lives: ``facet/<name>`` in a wheel, ``<repo>/<name>`` in a checkout.

The wheel carries the top-level ``glsl/`` and ``models/`` folders inside the package (see
pyproject.toml); a source checkout keeps them at the repository root.
"""

from __future__ import annotations

from pathlib import Path

from .errors import FacetError

_PACKAGE = Path(__file__).resolve().parent


def data_dir(name: str, marker: str) -> Path:
    """The bundled folder ``name`` (``glsl`` or ``models``) that contains ``marker``."""
    candidates = (_PACKAGE / name, _PACKAGE.parents[1] / name)
    for candidate in candidates:
        if (candidate / marker).is_file():
            return candidate
    raise FacetError(f"facet's bundled '{name}' folder is missing (looked in "
                     f"{', '.join(str(c) for c in candidates)}); reinstall facet")


def default_model() -> Path:
    """The model ``facet render`` draws when given none."""
    return data_dir("models", "default.obj") / "default.obj"

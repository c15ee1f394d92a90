"""``facet.show``: the viewer where the user is: a widget in a Jupyter notebook, else the
glfw window."""

from __future__ import annotations

from typing import Any

from ..boundary import FilePath, Size, checked
from ..viewing.core import Source


@checked
def show(source: Source | None = None, size: Size | None = None,
         screenshots: FilePath | None = None, **options) -> Any:
    """Show ``source`` interactively.

    Parameters
    ----------
    source : Scene or str or Path, optional
        A scene, or a mesh or scene file (default: the bundled torus knot).
    size : (int, int), optional
        The view's size (CSS pixels in a notebook, pixels in a window).
    screenshots : str or Path, optional
        The folder the ``s``, ``S`` and ``t`` keys write into (default: the working
        directory, the notebook's own in Jupyter).
    **options
        Render options over the scene's (``engine="path"``, ``shading="pbr"``, ...).

    Returns
    -------
    Widget or None
        In Jupyter, the widget (make it the last expression of a cell, or ``display`` it);
        elsewhere None, after the window closed.
    """
    from ..paths import default_model
    from .widget import in_jupyter

    source = default_model() if source is None else source
    if in_jupyter():
        from .widget import widget_class

        return widget_class()(source, size=size, screenshots=screenshots, **options)
    from ..window.viewer import view

    view(source, size=size, options=options, screenshots=screenshots)
    return None

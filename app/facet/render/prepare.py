"""Step 1 of facet.render.renderer's sequence: the scene as one render sees it (the lights
that shine, in a canonical order; its background and environment as the options say) and
the frame's state (facet.render.state); and a snapshot of a scene for a pass drawn later.
"""

from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np

from ..formats.environment_files import resolve as resolve_environment
from ..geometry.lens import with_lens
from ..scene.light import active_lights
from .antialias import point_lights_for
from .capabilities import CAPABILITIES
from .state import FrameState

LIGHT_ORDER = ("DirectionalLight", "PointLight", "SpotLight", "AreaLight", "SphereLight")


def prepare_frame(scene, camera, opts, window: bool):
    """The scene as a render sees it (its lights that shine, in a canonical order; its
    background and environment as the options say), and the frame's state: step 1 of
    facet.render.renderer's sequence. ``window``: a window shows colour only (opaque)."""
    camera = with_lens(camera, opts.aperture, opts.focus)
    # Lights in a canonical order (by kind; the sum does not care): programs are
    # specialised on the kinds, so scenes that differ only in light order share one.
    lights = sorted(active_lights(scene.lights, camera.view, opts.lights),
                    key=lambda light: LIGHT_ORDER.index(type(light).__name__))
    view = scene.view(lights=lights)
    # options_for put the scene's own background and environment under the explicit
    # ones; None (a RenderOptions built without a scene) means the scene's.
    background = np.array(scene.background if opts.background is None else opts.background,
                          dtype=np.float64)
    if window:
        background[3] = 1.0
    view.background = background
    if opts.environment is not None:  # (a file the options name is read here, once: the
        view.environment = resolve_environment(opts.environment)  # loader keeps it)
    # The ambient light no one declared lights only engines with the notes' ambient term.
    ambient = view.ambient if view.ambient_declared or \
        CAPABILITIES[opts.engine].implied_ambient else np.zeros(3)
    state = FrameState(camera, opts.width, opts.height, not window, opts.shading, opts.srgb,
                       tuple(point_lights_for(view).lights), ambient, view.environment,
                       time=opts.time, cull=opts.cull,
                       linear_out=bool(opts.float_color) and not window)
    return view, state


def frozen(scene):
    """A view of ``scene`` whose objects are copies with their own transforms and materials
    (what a deferred pass draws, whatever the caller changes afterwards); objects that share
    a material share its copy (they are drawn instanced: facet.render.raster.instancing)."""
    copies: dict[int, object] = {}

    def material(m):
        if id(m) not in copies:
            copies[id(m)] = copy.copy(m)
        return copies[id(m)]

    return scene.view(objects=[
        replace(o, transform=np.array(o.transform, dtype=np.float64),
                material=material(o.material)) for o in scene.objects])


def say_if_nothing_in_view(scene, camera, opts) -> None:
    """One warning line when no object of the scene can show in the camera's view (the
    picture would be empty with no word): its likely causes named."""
    import warnings

    from ..errors import FacetWarning
    from ..geometry.framing import boxes_in_view

    finite = [o for o in scene.objects if not o.infinite]
    if not finite or len(finite) < len(scene.objects) or \
            any(getattr(o.mesh, "rest", None) is not None for o in finite):
        return  # (nothing to see, an infinite plane, which nearly any view meets, or a
        #          skinned or morphed pose, whose box would cost posing it on the CPU)
    boxes = [o.shape.bounds if o.shape is not None else o.mesh.bounds for o in finite]
    w, h = opts.size
    view_projection = camera.projection(w, h) @ camera.view
    if boxes_in_view(view_projection, boxes, [o.transform for o in finite]).any():
        return
    warnings.warn(f"nothing of the scene ({len(finite)} objects) is in the camera's view: "
                  "is its pose in the other convention (Camera.from_intrinsics takes "
                  "OpenCV's, x right, y down, z forward; an OpenGL camera looks down -z), "
                  "does it look away, or is the scene beyond near / far "
                  f"({camera.near:g} / {camera.far:g})?", FacetWarning, stacklevel=3)

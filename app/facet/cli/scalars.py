"""``facet render --scalars NAME``: meshes and clouds coloured by a per-vertex property or a
world coordinate through a colormap, one range over the scene (facet.cli.render's)."""

from __future__ import annotations

from ..errors import InputError


def color_by_scalars(scene, args, opts) -> None:
    """--scalars: every mesh and cloud coloured by a world coordinate of its vertices,
    one range over the scene (--scalar-range, else the values'); the range is kept on
    ``args`` for --colorbar."""
    from dataclasses import replace

    import numpy as np

    from ..scene.colormap import colormap, scalar_range

    axes = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0), "up": opts.up}
    colormap(args.colormap)  # an unknown name: one line, before any work
    values = {}
    for o in scene.objects:
        if o.mesh.kind not in ("mesh", "points"):
            continue
        own = getattr(o.mesh, "scalars", None) or {}
        if args.scalars in own:
            values[o.id] = np.asarray(own[args.scalars], dtype=np.float64)
        elif args.scalars in axes:
            axis = np.asarray(axes[args.scalars], dtype=np.float64)
            world = o.mesh.positions @ o.transform[:3, :3].T + o.transform[:3, 3]
            values[o.id] = world @ (axis / np.linalg.norm(axis))
    if not values and args.scalars not in axes:
        names = sorted({k for o in scene.objects for k in getattr(o.mesh, "scalars", {})})
        raise InputError(f"--scalars {args.scalars}: no such per-vertex property (the "
                         f"model's: {', '.join(names) or 'none'}; or x, y, z, up)")
    if not values:
        raise InputError("--scalars: the scene has no meshes or points to colour")
    limits = None
    if args.scalar_range is not None:
        try:
            limits = tuple(float(v) for v in args.scalar_range.split(","))
            assert len(limits) == 2
        except (ValueError, AssertionError):
            raise InputError(f"--scalar-range {args.scalar_range}: expected LO,HI") from None
    limits = scalar_range(np.concatenate(list(values.values())), limits)
    args.scalar_limits = limits
    objects = []
    for o in scene.objects:
        if o.id in values:
            mesh = o.mesh.colored_by(values[o.id], args.colormap, limits)
            # the file's own material follows (white where it had none); a chosen one stays
            o = replace(o, mesh=mesh, material=mesh.material if o.material is o.mesh.material
                        or o.mesh.material is None else o.material)
        objects.append(o)
    scene.objects = objects

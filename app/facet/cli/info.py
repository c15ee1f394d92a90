"""``facet info``: what the headless OpenGL context offers, and facet's resource budgets;
``facet info MODEL``: what a model or scene file holds (objects, triangles, cameras,
animations with their lengths, material variants), without GL."""

from __future__ import annotations


def add_parser(sub) -> None:
    p = sub.add_parser("info", help="print the OpenGL backend, vendor, renderer, version and "
                       "limits; or what a model file holds",
                       description="Create a headless context and print what it offers: the "
                       "backend (EGL, or OSMesa where EGL cannot make a context; "
                       "FACET_GL_BACKEND=egl|osmesa chooses), vendor, renderer and limits; "
                       "then facet's resource budgets (budget.NAME; facet --budget "
                       "NAME=VALUE or FACET_BUDGET_NAME raise them). With MODEL: its objects, "
                       "triangles, cameras, animations (for --animation, --time) and material "
                       "variants (for --variant).")
    p.add_argument("model", nargs="?", help="a mesh, OpenUSD stage, URDF robot or .toml "
                   "scene file to describe")
    p.add_argument("--package-path", action="append", metavar="DIR",
                   help="URDF: where package:// names are found (repeatable)")


def describe_model(path, package_path=None) -> list[str]:
    """Lines saying what the model or scene file at ``path`` holds."""
    from ..formats.source import open_scene
    from ..scene.staging import variant_names

    scene = open_scene(path, package_path=tuple(package_path) if package_path else None)
    lines = [f"{'objects':22} {len(scene.objects):,}",
             f"{'triangles':22} {sum(o.mesh.face_count for o in scene.objects):,}",
             f"{'splats':22} " + (", ".join(
                 f"{c.splats.count:,} (SH degree {c.splats.degree})" for c in scene.splats)
                 or "none"),
             f"{'lights':22} {len(scene.lights)}",
             f"{'cameras':22} {', '.join(scene.cameras) or 'none'}"]
    clips = [(k, c) for a in scene.animated for k, c in enumerate(a.rig.clips)]
    lines.append(f"{'animations':22} " + (", ".join(
        f"{k}: {c.name} ({c.duration:g} s)" for k, c in clips) or "none"))
    skins = sum(len(a.rig.skins) for a in scene.animated)
    if skins:
        lines.append(f"{'skins':22} {skins}")
    lines.append(f"{'variants':22} {', '.join(variant_names(scene)) or 'none'}")
    scalars = sorted({k for o in scene.objects for k in getattr(o.mesh, "scalars", {})})
    lines.append(f"{'vertex scalars':22} {', '.join(scalars) or 'none'}")
    from pathlib import Path

    from ..formats.usd_stage import USD_SUFFIXES

    if Path(path).suffix.lower() in USD_SUFFIXES:  # an OpenUSD stage: what composed it
        from ..formats.usd import describe_stage

        lines += describe_stage(Path(path))
    if Path(path).suffix.lower() == ".urdf":  # a robot: its links and joints
        from ..formats.urdf import describe_robot

        lines += describe_robot(Path(path))
    return lines


def run(args) -> None:
    if getattr(args, "model", None):
        print("\n".join(describe_model(args.model, getattr(args, "package_path", None))))
        return
    from .. import budgets
    from ..gl.context import create_headless, describe

    ctx = create_headless()
    try:
        for key, value in describe(ctx).items():
            print(f"{key:22} {value}")
    finally:
        ctx.release()
    for name, value in budgets.describe().items():
        print(f"{'budget.' + name:22} {value:<12} {budgets.BUDGETS[name][1]}")

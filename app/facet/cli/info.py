"""``facet info``: what the headless OpenGL context offers, and facet's resource budgets."""

from __future__ import annotations


def add_parser(sub) -> None:
    sub.add_parser("info", help="print the OpenGL backend, vendor, renderer, version and limits",
                   description="Create a headless context and print what it offers: the "
                   "backend (EGL, or OSMesa where EGL cannot make a context; "
                   "FACET_GL_BACKEND=egl|osmesa chooses), vendor, renderer and limits; "
                   "then facet's resource budgets (budget.NAME; facet --budget NAME=VALUE "
                   "or FACET_BUDGET_NAME raise them).")


def run(args) -> None:
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

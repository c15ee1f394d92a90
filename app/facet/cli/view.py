"""``facet view``: open a model or scene file in the interactive window (facet.window)."""

from __future__ import annotations

import argparse

from . import args as A


def add_parser(sub) -> None:
    from ..viewing.keys import help_text

    v = sub.add_parser("view", help="open a model or scene file in an interactive window",
                       description="Explore MODEL (a mesh or .toml scene file) in a window, "
                       "drawn as 'facet render'\nwould draw it (the scene file's [render] "
                       "table and the flags below apply).\nDrag to orbit, right-drag to pan, "
                       "scroll to zoom; press h for keys.",
                       epilog=help_text(), formatter_class=argparse.RawDescriptionHelpFormatter)
    v.add_argument("model", nargs="?", help="mesh file or .toml scene file (default: the "
                   "bundled torus knot)")
    A.add_render_options(v, "the window opens at the scene file's size, else 1280x720")
    A.add_model_options(v)
    A.add_confine_option(v)
    A.add_shader_options(v)
    v.add_argument("--screenshots", metavar="DIR",
                   help="the folder the s, S and t keys write pictures into (default: the "
                   "working directory)")
    v.add_argument("--serve", metavar="[HOST:]PORT",
                   help="serve the viewer to a web page instead of opening a window (for "
                   "machines without a display): binds 127.0.0.1 unless HOST is given, "
                   "prints the URL (with its token) and the ssh -L line that reaches it; "
                   "PORT 0 picks a free one")


def run(args) -> None:
    from ..paths import default_model
    from ..window.viewer import view  # no glfw import until a window opens
    from .render import user_shader

    model = args.model or default_model()
    stage = A.stage_options(args)
    if stage:  # an OpenUSD stage composed as asked: the view holds the scene it made
        from ..formats.source import open_scene

        model = open_scene(model, crease=args.crease, **stage)
    settings = dict(shader=user_shader(args), options=A.render_layer(args),
                    crease=args.crease, time_end=A.time_range(args)[1],
                    sizes=A.sprite_sizes(args), screenshots=args.screenshots)
    if args.serve is not None:
        from ..serve.server import serve

        serve(model, args.serve, **settings)
        return
    view(model, **settings)

"""The ``facet`` command line: one module per subcommand (render, view, shader, info), each
with ``add_parser(sub)`` and ``run(args)``; no rendering logic lives here.

A user's mistake prints one line ``facet: error: ...`` on stderr and exits with status 2,
leaving no output file; a warning (facet.errors.FacetWarning) prints one line
``facet: warning: ...``. Heavy modules (numpy, trimesh, moderngl, Pillow) are imported
inside the commands, so ``facet --help`` starts instantly and each command loads only what
it uses.
"""

from __future__ import annotations

import argparse
import difflib
import signal
import sys
from importlib import import_module

EXIT_USAGE = 2
COMMANDS = ("render", "view", "shader", "batch", "info")


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (plus where to find help)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)  # typos get a did-you-mean instead
        super().__init__(*args, **kwargs)

    def error(self, message: str):
        from ..errors import printable

        self.exit(EXIT_USAGE, f"{self.prog}: error: {printable(message)} "
                  f"(see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="facet", description="facet: headless GPU rendering of 3D scenes "
                     "(meshes, points, lines, shapes, glTF) by a rasterizer, a Whitted ray "
                     "tracer and a path tracer, and GLSL shaders (OpenGL through EGL; Mesa "
                     "llvmpipe when there is no GPU).")
    parser.add_argument("--version", action="version", version="facet 0.1.0")
    parser.add_argument("--budget", action="append", metavar="NAME=VALUE", default=[],
                        help="raise (or lower) one of facet's resource budgets for this run, "
                        "e.g. --budget pixels=300000000 (facet info lists them); repeatable")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMANDS:
        import_module(f"facet.cli.{name}").add_parser(sub)
    return parser


def _subparser(parser, command: str | None):
    for action in parser._subparsers._group_actions:  # argparse keeps them only here
        if command in getattr(action, "choices", {}):
            return action.choices[command]
    return None


def _join_negative_values(parser, argv: list[str]) -> list[str]:
    """``--target -1,0,0`` -> ``--target=-1,0,0``, ``--up -z`` -> ``--up=-z``: a value that
    starts with a minus sign and is none of the subcommand's options goes with the option
    before it, when that one takes a value (argparse would take it for an option)."""
    command = next((a for a in argv if a in COMMANDS), None)
    sub = _subparser(parser, command)
    if sub is None:
        return argv
    options = {opt for action in sub._actions for opt in action.option_strings}
    takes_value = {opt for action in sub._actions if action.nargs is None and
                   action.option_strings for opt in action.option_strings}
    out, i = [], 0
    while i < len(argv):
        value = argv[i + 1] if i + 1 < len(argv) else ""
        if argv[i] in takes_value and value.startswith("-") and len(value) > 1 and \
                value.split("=", 1)[0] not in options:
            out.append(f"{argv[i]}={value}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def _unknown(parser, command: str, extras: list[str]) -> str:
    """One line for arguments the subcommand does not know, with a did-you-mean."""
    sub = _subparser(parser, command)
    first = extras[0]
    if not first.startswith("-"):
        return f"unexpected argument {first!r}"
    known = [s for a in sub._actions for s in a.option_strings] if sub else []
    close = difflib.get_close_matches(first.split("=", 1)[0], known, n=1, cutoff=0.6)
    hint = f"; did you mean {close[0]}?" if close else ""
    return f"unknown option {first}{hint}"


def _apply_budgets(argv: list[str]) -> None:
    """``facet --budget NAME=VALUE ... COMMAND``: set before anything is parsed (a
    subcommand's --size is checked against the pixel budget as it is read)."""
    from ..budgets import set_budget

    for i, arg in enumerate(argv):
        if arg in COMMANDS:
            return
        if arg == "--budget" and i + 1 < len(argv):
            set_budget(argv[i + 1])
        elif arg.startswith("--budget="):
            set_budget(arg.split("=", 1)[1])


def parse_args(argv: list[str]):
    """(arguments, one line about what the subcommand does not know or None): argparse
    with negative values joined to their options (argparse's own usage errors exit 2)."""
    _apply_budgets(list(argv))
    parser = build_parser()
    args, extras = parser.parse_known_args(_join_negative_values(parser, list(argv)))
    problem = _unknown(parser, args.command, extras) if extras else None
    return args, problem


def main(argv: list[str] | None = None) -> int:
    import warnings

    from ..errors import InputError

    try:
        args, problem = parse_args(sys.argv[1:] if argv is None else argv)
    except InputError as exc:  # a --budget that is no budget
        print(f"facet: error: {_printable(exc)}", file=sys.stderr)
        return EXIT_USAGE
    if problem:
        prog = f"facet {args.command}"
        print(f"{prog}: error: {_printable(problem)} (see {prog} --help)",
              file=sys.stderr)
        return EXIT_USAGE
    from ..errors import FacetError, ShaderError, gl_out_of_memory, printable, show_warning

    previous = _stop_on_sigterm()
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            with _confinement(args):
                result = import_module(f"facet.cli.{args.command}").run(args)
        if args.command == "batch":
            return result  # 1 when any job failed (the summary line says which)
        if args.command in ("render", "shader") and not args.quiet:
            for path in result or ():
                print(_printable(path))
    except FacetError as exc:  # compiler output keeps its lines; anything else is one line
        print(f"facet: error: {printable(exc, isinstance(exc, ShaderError))}",
              file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:  # unwritable output folder, disk full, ...
        name = f"{_printable(exc.filename)}: " if exc.filename else ""
        print(f"facet: error: {name}{printable(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as exc:  # a GL that ran out of memory where no Targets could say so
        message = gl_out_of_memory(exc)
        if message is None:
            raise
        print(f"facet: error: {printable(message)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # Ctrl-C, or SIGTERM (timeout, docker, systemd) made one
        return 128 + _STOPPED_BY[0]
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return 0


_STOPPED_BY = [signal.SIGINT]  # the signal that stopped the run: exit status 128 + it


def _stop_on_sigterm():
    """SIGTERM stops a run as Ctrl-C does (temporary files removed, writer processes shut
    down, no traceback), exit status 128 + 15. Returns the previous handler (None when
    this is not the main thread, where handlers cannot be set)."""
    def stop(signum, _frame):
        _STOPPED_BY[0] = signum
        raise KeyboardInterrupt

    _STOPPED_BY[0] = signal.SIGINT
    try:
        return signal.signal(signal.SIGTERM, stop)
    except ValueError:
        return None


def _confinement(args):
    """``--confine DIR``: every file the command reads on the user's behalf must lie in DIR."""
    import contextlib

    folder = getattr(args, "confine", None)
    if folder is None:
        return contextlib.nullcontext()
    from ..guard import confined

    return confined(folder)



def _printable(path) -> str:
    """A written path on one line, control characters escaped (a newline or a carriage
    return in a name would break one-path-per-line scripts; a tab or an escape sequence
    would garble a terminal)."""
    from ..errors import printable

    return printable(path)

"""Packages whose names are imported on first use (``import facet`` and the command line's
--help load no numpy): one pair of module functions for each such package."""

from __future__ import annotations

from importlib import import_module


def lazy_exports(package: str, exports: dict[str, str]):
    """``(__getattr__, __dir__)`` for ``package``: name -> the module (relative to the
    package) it comes from; a name mapped to itself is a submodule."""

    def __getattr__(name: str):
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = import_module(f"{package}.{exports[name]}")
        value = module if exports[name] == name else getattr(module, name)
        vars(import_module(package))[name] = value
        return value

    def __dir__():
        return sorted(set(vars(import_module(package))) | set(exports))

    return __getattr__, __dir__

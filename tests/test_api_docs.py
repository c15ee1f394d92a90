"""The public API is documented and typed: every name facet exports (its functions, classes
and their public methods) has numpydoc sections (Parameters where it takes any, Returns
where it returns something) and a return annotation; the API reference pages hold every
exported name; mypy is clean on the public modules (pyproject's [tool.mypy], also run by
make lint); the package ships py.typed."""

import inspect
import re
import shutil
import subprocess
import sys
import types

import pytest

import facet

from conftest import ROOT

API_PAGES = ROOT / "docs" / "api"


def _public_callables():
    for name in facet.__all__:
        obj = getattr(facet, name)
        if isinstance(obj, types.ModuleType):
            for attr, fn in vars(obj).items():
                if not attr.startswith("_") and inspect.isfunction(fn) and \
                        fn.__module__ == obj.__name__:
                    yield f"{name}.{attr}", fn, None
        elif inspect.isclass(obj):
            if issubclass(obj, Exception):
                continue
            yield f"{name}.__init__", obj.__init__, inspect.getdoc(obj) or ""
            for attr, fn in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(fn, (staticmethod, classmethod)):
                    fn = fn.__func__
                if inspect.isfunction(fn):
                    yield f"{name}.{attr}", fn, None
        elif callable(obj):
            yield name, obj, None


def _problems(name, fn, doc) -> list[str]:
    doc = inspect.getdoc(fn) or "" if doc is None else doc
    sig = inspect.signature(fn)
    out = []
    if [p for p in sig.parameters if p not in ("self", "cls")] and \
            not re.search(r"^Parameters\n-{10}", doc, re.M):
        out.append("no Parameters section")
    if not name.endswith("__init__"):
        ret = sig.return_annotation
        if ret is inspect.Signature.empty:
            out.append("no return annotation")
        elif ret not in (None, "None") and not re.search(r"^Returns\n-{7}", doc, re.M):
            out.append("no Returns section")
    return out


def test_every_public_function_and_class_has_numpydoc_sections():
    found = {name: problems for name, fn, doc in _public_callables()
             if (problems := _problems(name, fn, doc))}
    assert not found, found
    assert sum(1 for _ in _public_callables()) > 100


def test_a_missing_section_is_caught():
    def undocumented(x) -> int:
        """Says nothing of x."""
        return x

    assert _problems("undocumented", undocumented, None) == [
        "no Parameters section", "no Returns section"]


def test_the_api_reference_holds_every_exported_name():
    text = "".join(p.read_text() for p in API_PAGES.glob("*.md"))
    missing = []
    for name in facet.__all__:
        obj = getattr(facet, name)
        if isinstance(obj, types.ModuleType):
            continue
        module = getattr(obj, "__module__", "")
        if f"::: {module}.{name}\n" not in text and not (
                module == "facet.errors" and "::: facet.errors" in text) and name not in (
                "SHADING_MODELS",):
            missing.append(name)
    assert not missing, missing


def test_the_package_is_typed():
    assert (ROOT / "app" / "facet" / "py.typed").is_file()


@pytest.mark.slow
def test_mypy_is_clean_on_the_public_modules():
    if shutil.which("mypy") is None and not (ROOT / ".venv" / "bin" / "mypy").exists():
        pytest.importorskip("mypy", reason="mypy is not installed (the dev extra has it)")
    run = subprocess.run([sys.executable, "-m", "mypy"], cwd=ROOT, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:]


def test_the_documented_msaa_counts_are_the_accepted_ones():
    """The Renderer's msaa parameter lists what the options accept (it listed 16, which
    they refuse)."""
    import re

    from facet.options.values import MSAA_CHOICES
    from facet.render.renderer import Renderer

    doc = Renderer.__doc__ or Renderer.__init__.__doc__
    line = re.search(r"Multisample anti-aliasing samples \(([^:]*):", doc).group(1)
    assert [int(n) for n in re.findall(r"\d+", line)] == list(MSAA_CHOICES)

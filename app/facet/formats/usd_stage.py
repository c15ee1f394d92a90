"""Opening an OpenUSD stage (no GL) through Pixar's own reader, pxr (the usd-core wheel:
``pip install 'facet-render[usd]'``, named in one line when it is missing).

Every layer the composition can reach (sublayers, references, payloads, also those inside
variants, and a .usdz's members) is opened through facet.guard before the stage is
composed (``guard.usd_layer``: confinement with links resolved, a regular file within the
size budget, a package's table of contents), at most ``depth`` levels of layers and the
``gltf_items`` budget of them; a layer that names a missing file, or one it already
reached (a cycle), is left to pxr's composition, whose errors become one warning line
each. The composed stage may use no layer the walk did not check
(``guard.usd_stage``).

Options: ``variants`` ({set: name}, chosen in the stage's session layer on every prim that
has that set; an unknown set or name is one error listing what the stage has),
``payloads`` (loaded by default). pxr's own diagnostics are caught, never printed.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from ..budgets import budget
from ..errors import MeshError

PXR_MISSING = ("reading OpenUSD stages needs Pixar's usd-core: pip install "
               "'facet-render[usd]'")
USD_SUFFIXES = (".usd", ".usda", ".usdc", ".usdz")


def require_pxr(path) -> None:
    try:
        import pxr  # noqa: F401
    except ImportError:
        raise MeshError(f"{path}: {PXR_MISSING}") from None


@contextlib.contextmanager
def quiet_pxr():
    """pxr's diagnostics while the block runs: collected (a list of lines, yielded), never
    printed (its warnings go straight to the process's stderr, so that is held too)."""
    from pxr import Tf

    said: list[str] = []
    err = os.dup(2)
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 2)
        try:
            with Tf.DiagnosticTrap() as trap:
                try:
                    yield said
                finally:
                    said += [d.commentary for d in (*trap.GetErrors(), *trap.GetWarnings())]
                    trap.Dismiss()
        finally:
            os.dup2(err, 2)
            os.close(err)


def open_stage(path: Path, variants: dict | None = None, payloads: bool = True):
    """(stage, warning lines) of the stage at ``path`` (module docstring)."""
    require_pxr(path)
    from pxr import Sdf

    from ..guard import library_path, usd_layer, usd_stage

    with quiet_pxr() as said:
        root = usd_layer(path, "USD stage", MeshError)
        checked = {_outer(root.realPath)}
        keep = [root]  # (pxr's layer registry holds a layer while it is referenced)
        todo = [(root, 0)]
        limit = budget("gltf_items")
        while todo:
            layer, depth = todo.pop()
            for asset in layer.GetCompositionAssetDependencies():
                resolved = layer.ComputeAbsolutePath(asset)
                outer = _outer(resolved)
                if not resolved or not Path(outer).exists() or resolved in checked:
                    continue  # (a missing file is pxr's composition error: said below)
                ext = Path(outer).suffix.lstrip(".")
                if not ext or Sdf.FileFormat.FindByExtension(ext) is None:
                    # not a layer pxr reads (MaterialX without its plug-in, a device):
                    # checked all the same, so that what the guard refuses says so
                    library_path(outer, "USD layer", MeshError)
                    continue
                if depth + 1 > budget("depth"):
                    raise MeshError(f"{path}: layers nest more than {budget('depth'):,} "
                                    "levels deep, facet's budget (--budget depth=N)")
                sub = usd_layer(resolved if "[" in resolved else outer, "USD layer",
                                MeshError)
                checked |= {resolved, outer}
                if len(checked) > limit:
                    raise MeshError(f"{path}: reaches more than {limit:,} layers, facet's "
                                    "budget (--budget gltf_items=N)")
                keep.append(sub)
                todo.append((sub, depth + 1))
        session = Sdf.Layer.CreateAnonymous("facet-session.usda")
        stage = usd_stage(root, session, payloads, checked, MeshError)
        if variants:
            _choose(stage, variants, path)
            usd_stage(root, session, payloads, checked, MeshError)  # (what it now uses)
        errors = [str(e.message if hasattr(e, "message") else e)
                  for e in stage.GetCompositionErrors()]
    notes = [f"{path.name}: {line.strip()}" for line in dict.fromkeys(errors) if line.strip()]
    notes += [f"{path.name}: {line.strip()}" for line in said  # (not the errors again)
              if line.strip() and "instantiating stage on stage" not in line]
    stage.facet_layers = keep  # type: ignore[attr-defined]  (kept alive with the stage)
    return stage, notes


def _outer(real: str) -> str:
    """The file of a layer: a package member's package."""
    return real.split("[", 1)[0] if real else real


def _choose(stage, variants: dict, path: Path) -> None:
    """Variant selections in the session layer, on every prim that has the set."""
    from pxr import Usd

    found: dict[str, set] = {}
    prims = []
    for prim in stage.Traverse(Usd.PrimAllPrimsPredicate):
        sets = prim.GetVariantSets()
        for name in sets.GetNames():
            found.setdefault(name, set()).update(sets.GetVariantSet(name).GetVariantNames())
            prims.append((prim, name))
    for name, choice in variants.items():
        if name not in found:
            have = "; ".join(f"{k}: {', '.join(sorted(v))}" for k, v in sorted(found.items()))
            raise MeshError(f"{path}: no variant set {name!r}; the stage has "
                            f"{have or 'no variant sets'}")
        if choice not in found[name]:
            raise MeshError(f"{path}: variant set {name!r} has no variant {choice!r}; it "
                            f"has {', '.join(sorted(found[name]))}")
    stage.SetEditTarget(stage.GetSessionLayer())
    for prim, name in prims:
        if name in variants and prim.IsValid():
            prim.GetVariantSets().GetVariantSet(name).SetVariantSelection(variants[name])


def variant_sets(stage) -> dict[str, tuple[list[str], str]]:
    """{set: (its variants, the selection as composed)} over the stage (``facet info``)."""
    from pxr import Usd

    out: dict[str, tuple[list[str], str]] = {}
    for prim in stage.Traverse(Usd.PrimAllPrimsPredicate):
        sets = prim.GetVariantSets()
        for name in sets.GetNames():
            vs = sets.GetVariantSet(name)
            names, chosen = out.get(name, ([], ""))
            out[name] = (sorted(set(names) | set(vs.GetVariantNames())),
                         chosen or vs.GetVariantSelection())
    return out

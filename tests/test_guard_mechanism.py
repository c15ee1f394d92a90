"""The guard as a mechanism: every byte facet reads goes through facet.guard.

The test walks the syntax tree of every module under app/facet and fails on any read of a
file outside facet/guard.py: the built-in ``open`` (for reading), ``io.open``, ``os.open``
without a write flag, ``Path.read_bytes / read_text / open``, ``np.load / fromfile /
memmap``, ``np.loadtxt / genfromtxt`` of a name (a path), Pillow's ``Image.open``, imageio
and OpenCV reads, trimesh's loaders, pygltflib's ``load``, OpenEXR's ``InputFile``, ``json /
tomllib / pickle.load`` of a file object, ``zipfile`` and ``tarfile``. What may stay is in
ALLOWED, each with its reason: facet's own files (shaders, the served page), never a
user's. A new reader written beside the guard fails here, not in a hostile battery."""

from __future__ import annotations

import ast

import pytest

from conftest import ROOT

PACKAGE = ROOT / "app" / "facet"

# (module path relative to app/facet, the call as the walker names it): why it may read.
ALLOWED = {
    ("serve/server.py", "Path.read_bytes"):
        "the served page's own static files, shipped in the package (a fixed name table)",
    ("lab/passes.py", "Path.read_text"):
        "facet's own Shadertoy host stage under glsl/ (never a user's file)",
}

_WRITE_MODES = set("wax")
_NUMPY_READS = {"load", "fromfile", "memmap"}
_NUMPY_TEXT = {"loadtxt", "genfromtxt"}
_PATH_READS = {"read_bytes", "read_text"}
_MODULE_READS = {  # (module alias as written, function)
    ("Image", "open"), ("PIL.Image", "open"), ("iio", "imread"), ("imageio", "imread"),
    ("iio", "imopen"), ("imageio", "imopen"), ("imageio", "get_reader"),
    ("iio", "get_reader"), ("cv2", "imread"), ("cv2", "imreadmulti"),
    ("trimesh", "load"), ("trimesh", "load_mesh"), ("trimesh", "load_path"),
    ("trimesh", "load_scene"), ("OpenEXR", "InputFile"), ("OpenEXR", "File"),
    ("json", "load"), ("tomllib", "load"), ("pickle", "load"), ("io", "open"),
    ("codecs", "open"), ("zipfile", "ZipFile"), ("tarfile", "open"), ("np", "load"),
    ("os", "fdopen"), ("Sdf.Layer", "FindOrOpen"), ("Sdf.Layer", "OpenAsAnonymous"),
    ("Usd.Stage", "Open"), ("yourdfpy.URDF", "load"), ("URDF", "load"),
}


def _dotted(node) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        inner = _dotted(node.value)
        return f"{inner}.{node.attr}" if inner else node.attr
    if isinstance(node, ast.Call):
        return _dotted(node.func) + "()"
    return ""


def _mode(call: ast.Call, position: int) -> str | None:
    """The literal mode of an ``open``-like call, None when not literal (or not given)."""
    for kw in call.keywords:
        if kw.arg == "mode":
            return kw.value.value if isinstance(kw.value, ast.Constant) else ""
    if len(call.args) > position and isinstance(call.args[position], ast.Constant):
        return str(call.args[position].value)
    return None


def _writes(mode: str | None) -> bool:
    return mode is not None and bool(_WRITE_MODES & set(mode))


def _guarded_names(tree: ast.AST) -> set[str]:
    """Names bound by ``with opened(...) as (f, size)`` / ``opened_name(...) as name``:
    what the guard opened and checked, which a library may then read."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.With, ast.AsyncWith)):
            for item in node.items:
                call = item.context_expr
                if isinstance(call, ast.Call) and _dotted(call.func).split(".")[-1] in (
                        "opened", "opened_name") and item.optional_vars is not None:
                    names |= {n.id for n in ast.walk(item.optional_vars)
                              if isinstance(n, ast.Name)}
    return names


def _of_memory(call: ast.Call, guarded: set[str]) -> bool:
    """Whether a library's read is of bytes in memory (``io.BytesIO(...)``) or of what the
    guard opened (a name bound by ``opened`` / ``opened_name``)."""
    first = call.args[0] if call.args else None
    if isinstance(first, ast.Call) and _dotted(first.func).split(".")[-1] == "BytesIO":
        return True
    return isinstance(first, ast.Name) and first.id in guarded


def reads(tree: ast.AST) -> list[tuple[int, str]]:
    """(line, the call as named in ALLOWED) of every file read in ``tree``."""
    found = []
    guarded = _guarded_names(tree)
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        if isinstance(func, ast.Attribute) and _of_memory(node, guarded):
            continue
        if isinstance(func, ast.Name) and func.id == "open":
            if not _writes(_mode(node, 1)):
                found.append((node.lineno, "open"))
            continue
        if not isinstance(func, ast.Attribute):
            continue
        owner, attr = _dotted(func.value), func.attr
        if (owner, attr) == ("os", "open"):
            flags = ast.unparse(node.args[1]) if len(node.args) > 1 else ""
            if not any(f in flags for f in ("O_WRONLY", "O_RDWR", "O_CREAT")):
                found.append((node.lineno, "os.open"))
        elif (owner, attr) == ("os", "fdopen"):
            if not _writes(_mode(node, 1)):
                found.append((node.lineno, "os.fdopen"))
        elif owner in ("np", "numpy") and attr in _NUMPY_READS:
            found.append((node.lineno, f"np.{attr}"))
        elif owner in ("np", "numpy") and attr in _NUMPY_TEXT:
            if node.args and isinstance(node.args[0], (ast.Name, ast.Constant,
                                                      ast.Attribute)):
                found.append((node.lineno, f"np.{attr}"))
        elif (owner, attr) == ("OpenEXR", "File"):
            if len(node.args) == 1:  # File(name): a read; File(header, channels): a write
                found.append((node.lineno, "OpenEXR.File"))
        elif (owner.split(".")[-1], attr) in _MODULE_READS or (owner, attr) in _MODULE_READS:
            if attr == "open" and owner.endswith("Image") or not _writes(_mode(node, 1)):
                found.append((node.lineno, f"{owner.split('.')[-1]}.{attr}"))
        elif attr in _PATH_READS and owner != "guard":
            found.append((node.lineno, f"Path.{attr}"))
        elif attr == "open" and not _writes(_mode(node, 0)) and owner not in (
                "webbrowser", "opengl_basisu", "self", "contextlib"):
            found.append((node.lineno, "Path.open"))
        elif attr == "load" and owner.endswith("GLTF2()"):
            found.append((node.lineno, "GLTF2.load"))
    return found


def _modules():
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_every_read_goes_through_the_guard():
    offending = []
    used = set()
    for path in _modules():
        rel = path.relative_to(PACKAGE).as_posix()
        if rel == "guard.py":
            continue
        for line, call in reads(ast.parse(path.read_text(encoding="utf-8"))):
            if (rel, call) in ALLOWED:
                used.add((rel, call))
            else:
                offending.append(f"app/facet/{rel}:{line}: {call}")
    assert not offending, "reads outside facet.guard (read through facet.guard, or add " \
        "an entry with its reason to ALLOWED):\n" + "\n".join(offending)
    assert used == set(ALLOWED), f"stale allow-list entries: {set(ALLOWED) - used}"


@pytest.mark.parametrize("code,call", [
    ("open(p)", "open"), ("open(p, 'rb')", "open"), ("Path(p).read_bytes()", "Path.read_bytes"),
    ("p.read_text(encoding='utf-8')", "Path.read_text"), ("p.open()", "Path.open"),
    ("np.fromfile(p, dtype=d)", "np.fromfile"), ("np.load(p)", "np.load"),
    ("np.loadtxt(p)", "np.loadtxt"), ("Image.open(p)", "Image.open"),
    ("iio.imread(p)", "iio.imread"), ("cv2.imread(p)", "cv2.imread"),
    ("trimesh.load(str(p))", "trimesh.load"), ("GLTF2().load(str(p))", "GLTF2.load"),
    ("OpenEXR.InputFile(str(p))", "OpenEXR.InputFile"), ("json.load(f)", "json.load"),
    ("OpenEXR.File(str(p), header_only=True)", "OpenEXR.File"),
    ("os.open(p, os.O_RDONLY)", "os.open"), ("io.open(p)", "io.open"),
])
def test_the_walker_finds_each_kind_of_read(code, call):
    assert reads(ast.parse(code)) == [(1, call)]


@pytest.mark.parametrize("code", [
    "open(p, 'wb')", "open(tmp, mode='w', encoding='utf-8')", "p.open('a')",
    "os.open(p, os.O_WRONLY | os.O_CREAT)", "np.loadtxt(io.BytesIO(data))",
    "np.loadtxt(body.splitlines()[:n])", "webbrowser.open(url)", "guard.read_bytes(p)",
    "OpenEXR.File(header, channels).write(str(tmp))",
    "trimesh.load(io.BytesIO(data), file_type='obj')", "Image.open(io.BytesIO(raw))",
    "with opened_name(p) as name, OpenEXR.File(name) as f: pass",
])
def test_the_walker_leaves_writes_and_reads_of_memory(code):
    assert reads(ast.parse(code)) == []

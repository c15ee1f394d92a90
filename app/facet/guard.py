"""One guard for what facet reads on a user's behalf (no numpy, no GL).

``regular_file(path, what)`` is called before any user-named file is opened: a missing
path, a directory, a FIFO, a device or a socket each get one clear error instead of a hang
(a FIFO blocks an open) or a misleading message, and so does a Git LFS pointer (what a
clone without Git LFS leaves in place of a model or an image) or a file beyond the size
budget (facet.budgets). Under ``confined(folder)`` a file outside the folder gets the same
sentence whether it exists or not (a confined input cannot probe which files exist). The
confinement holds in every thread: facet's own threads carry it (``carried``), and a
thread that carries none is held to every confinement active in the process.

Writing: ``check_output(path)`` before any file is written: an existing FIFO, device or
socket is refused (never opened, never replaced), and within ``writing_into(folder)`` (a
dataset's output folder) a path whose folder resolves outside it (a symbolic link to
elsewhere) or that is itself a symbolic link is refused: facet writes only inside the
output folder it was given. ``open_image`` opens an image with an
explicit pixel budget (a decompression bomb is an error, not a traceback) and no warnings
reaching the terminal. ``parse_toml`` turns a nesting the parser cannot follow into one
line.
"""

from __future__ import annotations

import contextlib
import os
import stat
import threading
from contextvars import ContextVar, copy_context
from pathlib import Path

from .budgets import budget
from .errors import InputError

LFS_POINTER = b"version https://git-lfs.github.com/spec/"  # how a pointer file starts


# The folder every file read on a user's behalf must lie in (``confined``), or None.
_CONFINE: ContextVar[Path | None] = ContextVar("facet_confine", default=None)
# Every confinement active in this process, whichever thread set it: a thread that does not
# carry one (a pool's worker, started without the context) is held to all of them (fail
# closed), so no thread can read past a confinement by not knowing of it.
_ACTIVE: dict[int, Path] = {}
_ACTIVE_LOCK = threading.Lock()
# The folder every file written must lie in (``writing_into``), or None.
_OUTPUT: ContextVar[Path | None] = ContextVar("facet_output", default=None)


@contextlib.contextmanager
def confined(folder):
    """Within this block, refuse any file outside ``folder`` (symbolic links resolved
    first): for services that render uploaded scenes, whose files may name any path."""
    root = Path(folder).resolve()
    if not root.is_dir():
        raise InputError(f"{folder}: the confinement folder does not exist or is not a "
                         "folder")
    token = _CONFINE.set(root)
    with _ACTIVE_LOCK:
        _ACTIVE[id(token)] = root
    try:
        yield root
    finally:
        with _ACTIVE_LOCK:
            _ACTIVE.pop(id(token), None)
        _CONFINE.reset(token)


def carried(fn):
    """``fn`` to run in another thread with this thread's confinement (and every other
    context variable): each call runs in a fresh copy of the context it was made in."""
    context = copy_context()

    def run(*args, **kwargs):
        return context.copy().run(fn, *args, **kwargs)

    return run


def confinement_roots() -> list[Path]:
    """The folders a file read in this thread must lie in: the thread's own confinement,
    or, when it carries none, every confinement active in the process (empty: none)."""
    root = _CONFINE.get()
    if root is not None:
        return [root]
    with _ACTIVE_LOCK:
        return list(dict.fromkeys(_ACTIVE.values()))


@contextlib.contextmanager
def writing_into(folder):
    """Within this block, refuse to write outside ``folder`` (module docstring)."""
    token = _OUTPUT.set(Path(folder).resolve())
    try:
        yield
    finally:
        _OUTPUT.reset(token)


def check_output(path) -> Path:
    """``path`` when facet may write it (module docstring); InputError otherwise."""
    p = Path(path)
    try:
        info = os.lstat(p)
    except FileNotFoundError:
        info = None
    except OSError as exc:
        raise InputError(f"{p}: cannot be written ({exc.strerror or exc})") from None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise InputError(f"{p}: is a directory; give a file name for the output")
    if info is not None and not (stat.S_ISREG(info.st_mode) or stat.S_ISLNK(info.st_mode)):
        kind = "a named pipe (FIFO)" if stat.S_ISFIFO(info.st_mode) else \
            "a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode) else \
            "a socket"
        raise InputError(f"{p}: is {kind}; facet writes regular files only")
    root = _OUTPUT.get()
    if root is not None:
        parent = p.parent.resolve()
        if (parent != root and root not in parent.parents) or \
                (info is not None and stat.S_ISLNK(info.st_mode)):
            raise InputError(f"{p}: leads outside the output folder {root} (a symbolic "
                             "link); facet writes only inside it")
    return p


def check_confined(path, what: str = "file", error=InputError) -> None:
    """``error`` when ``path`` resolves outside the confinement folder (if one is set)."""
    if "\0" in str(path):
        raise error(f"{str(path)!r}: a path with a NUL byte names no file")
    roots = confinement_roots()
    if not roots:
        return
    try:
        resolved = Path(path).resolve()
    except (OSError, RuntimeError):  # a loop of links leads nowhere inside
        resolved = None
    for root in roots:
        if resolved is None or (resolved != root and root not in resolved.parents):
            raise error(f"{path}: not readable here: outside the confinement folder {root} "
                        f"(--confine; a {what} there is never read, whether it exists or "
                        "not)")


def regular_file(path, what: str = "file", error=InputError, missing: str | None = None,
                 confine: bool = True) -> Path:
    """``path`` when it is a readable regular file (and inside the confinement folder, if
    one is set and ``confine``: facet's own files are not the input's); ``error`` naming it
    otherwise (``missing``: the noun for a path that does not exist, default ``what``)."""
    p = Path(path)
    if confine:
        check_confined(p, what, error)
    elif "\0" in str(p):
        raise error(f"{str(p)!r}: a path with a NUL byte names no file")
    try:
        mode = p.stat().st_mode
    except FileNotFoundError:
        raise error(f"{p}: no such {missing or what}") from None
    except PermissionError:
        raise error(f"{p}: permission denied") from None
    except OSError as exc:  # a name too long, a loop of links...
        raise error(f"{p}: cannot be read as {_a(what)} ({exc.strerror or exc})") from None
    if stat.S_ISDIR(mode):
        raise error(f"{p}: is a directory, expected {_a(what)}")
    if not stat.S_ISREG(mode):
        kind = ("a named pipe (FIFO)" if stat.S_ISFIFO(mode) else
                "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else
                "a socket" if stat.S_ISSOCK(mode) else "not a regular file")
        raise error(f"{p}: is {kind}, expected {_a(what)} (facet reads regular files only)")
    size_limit = budget("file_bytes")
    if os.stat(p).st_size > size_limit:
        raise error(f"{p}: {os.stat(p).st_size / 2**30:.1f} GiB, more than facet's budget of "
                    f"{size_limit / 2**30:.1f} GiB for {_a(what)} (--budget file_bytes=N)")
    if lfs_pointer(p):
        raise error(f"{p}: is a Git LFS pointer, not the {what} itself (its repository was "
                    "cloned without Git LFS: run `git lfs pull` there)")
    return p


@contextlib.contextmanager
def opened(path, what: str = "file", error=InputError, missing: str | None = None,
           confine: bool = True):
    """``(file, size)``: ``path`` open for binary reading through the one guarded opener,
    and its size from ``fstat``. Checked first (``regular_file``: confinement, a regular
    file, the size budget, no LFS pointer), then opened without waiting (O_NONBLOCK: a
    file swapped for a FIFO in between does not hang) at its resolved path, confined
    again, without following a link there (a link swapped in between does not lead out),
    and checked again on the open file before a byte is read. Every byte facet reads on a
    user's behalf comes through here (tests/test_guard_mechanism.py walks the code)."""
    p = regular_file(path, what, error, missing, confine)
    try:
        target = p.resolve()
    except (OSError, RuntimeError):
        raise error(f"{p}: cannot be read as {_a(what)} (a loop of links)") from None
    if confine:
        check_confined(target, what, error)  # the file about to be opened, links resolved
    fd = _open_fd(target, p, what, error)
    with os.fdopen(fd, "rb") as f:
        info = os.fstat(f.fileno())
        if not stat.S_ISREG(info.st_mode) or info.st_size > budget("file_bytes"):
            raise error(f"{p}: changed while it was read (no longer a regular file within "
                        "the budget); facet reads regular files only")
        yield f, info.st_size


def _open_fd(target: Path, shown, what: str, error) -> int:
    """A descriptor of ``target`` opened read-only, without waiting and without following
    a final link; ``error`` naming ``shown`` when it cannot be opened."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | \
        getattr(os, "O_NOFOLLOW", 0)
    try:
        return os.open(target, flags)
    except OSError as exc:
        raise error(f"{shown}: cannot be read as {_a(what)} ({exc.strerror or exc})") from None


@contextlib.contextmanager
def opened_name(path, what: str = "file", error=InputError, missing: str | None = None,
                confine: bool = True):
    """A file name for a library that reads only by name (OpenEXR): ``path`` opened and
    checked by ``opened``, named by its descriptor (``/proc/self/fd/N``: the library reads
    the file that was checked, not whatever the name leads to a moment later); where there
    is no /proc, the checked path itself."""
    with opened(path, what, error, missing, confine) as (f, _size):
        by_fd = f"/proc/self/fd/{f.fileno()}"
        yield by_fd if os.path.exists(by_fd) else str(Path(path).resolve())


def read_bytes(path, what: str = "file", error=InputError, missing: str | None = None,
               confine: bool = True, limit: int | None = None) -> bytes:
    """The content of ``path`` (its first ``limit`` bytes, when given), read through
    ``opened``: by the size ``fstat`` gives, never by the budget (a read of the budget
    would reserve gigabytes for every small file)."""
    with opened(path, what, error, missing, confine) as (f, size):
        return f.read(size if limit is None else min(size, limit))


def read_head(path, count: int, what: str = "file", error=InputError,
              confine: bool = True) -> bytes:
    """The first ``count`` bytes of ``path`` (fewer when it is shorter), through the
    guarded opener: how formats are sniffed (is this PLY a splat file?)."""
    return read_bytes(path, what, error, confine=confine, limit=count)


def read_text(path, what: str = "file", error=InputError, missing: str | None = None,
              confine: bool = True) -> str:
    """``read_bytes`` as UTF-8 text, newlines made ``\\n`` (as ``open`` in text mode);
    UnicodeDecodeError when it is not UTF-8 (the caller names what it expected)."""
    text = read_bytes(path, what, error, missing, confine).decode("utf-8")
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _a(noun: str) -> str:
    """``noun`` with its indefinite article."""
    return f"{'an' if noun[:1].lower() in 'aeiou' else 'a'} {noun}"


def lfs_pointer(path) -> bool:
    """Whether ``path`` (a regular file) is a Git LFS pointer file (opened as ``opened``
    opens: without waiting, no final link followed)."""
    try:
        fd = _open_fd(Path(path).resolve(), path, "file", InputError)
    except (InputError, OSError, RuntimeError):
        return False
    with os.fdopen(fd, "rb") as f:
        if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
            return False
        return f.read(len(LFS_POINTER)) == LFS_POINTER


def open_image(source, name: str):
    """A Pillow image opened from ``source`` (a path or a file object), its size checked
    against the pixel budget before any pixel is decoded."""
    import warnings

    from PIL import Image, UnidentifiedImageError

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        try:
            img = Image.open(source)
        except Image.DecompressionBombError:
            img = None
        except UnidentifiedImageError:
            raise InputError(f"{name}: not an image Pillow can read (truncated, or not "
                             "PNG, JPEG or another image format)") from None
        except (OSError, ValueError) as exc:
            raise InputError(f"{name}: cannot read the image ({exc})") from None
    limit = budget("pixels")
    if img is None or img.width * img.height > limit:
        size = f" ({img.width}x{img.height})" if img is not None else ""
        raise InputError(f"{name}: the image{size} is larger than facet's budget of "
                         f"{limit // 2**20} megapixels; scale it down, or raise the budget "
                         "with --budget pixels=N")
    return img


def json_depth(text, within: int | None = None) -> int:
    """How deep arrays and objects nest in JSON ``text`` (str or bytes), without parsing
    it: a running count of the brackets outside strings, 16 MB at a time (numpy). Text
    with escapes has its strings blanked by a regular expression first; without, a
    bracket is inside a string when an odd number of quotes come before it. With
    ``within``, text with no more opening brackets than that returns their count (a
    bound, found at C speed) instead."""
    import re

    import numpy as np

    data = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else bytes(text)
    if within is not None and data.count(b"[") + data.count(b"{") <= within:
        return data.count(b"[") + data.count(b"{")
    if b"\\" in data:
        data = re.sub(rb'"[^"\\]*(?:\\.[^"\\]*)*"', b'""', data)
    chars = np.frombuffer(data, dtype=np.uint8)
    depth = deepest = quotes = 0
    for start in range(0, len(chars), 1 << 24):
        c = chars[start:start + (1 << 24)]
        outside = (np.cumsum(c == 34, dtype=np.int64) + quotes) % 2 == 0
        step = ((c == 91) | (c == 123)).view(np.int8) - ((c == 93) | (c == 125)).view(np.int8)
        running = np.cumsum(step * outside, dtype=np.int64) + depth
        quotes += int(np.count_nonzero(c == 34))
        deepest, depth = max(deepest, int(running.max())), int(running[-1])
    return deepest


def parse_json(text, name: str, error=InputError):
    """The value of JSON ``text`` (str or bytes); one line naming ``name`` when it is not
    JSON or nests deeper than the depth budget (arrays inside arrays 100,000 deep: the
    parser's recursion would fail, so the depth is counted first)."""
    import json

    limit = budget("depth")
    if json_depth(text, limit) > limit:
        raise error(f"{name}: nested more than {limit:,} levels deep, facet's budget "
                    "(--budget depth=N)")
    try:
        return json.loads(text)
    except RecursionError:
        raise error(f"{name}: nested too deeply to read (arrays or objects inside one "
                    "another thousands of times)") from None
    except json.JSONDecodeError as exc:
        raise error(f"{name}: not JSON ({exc.msg} at line {exc.lineno}, column "
                    f"{exc.colno})") from None
    except (ValueError, UnicodeDecodeError) as exc:
        raise error(f"{name}: not JSON text ({exc})") from None


def parse_toml(text: str, name: str, error=InputError) -> dict:
    import tomllib

    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{name}: invalid TOML: {exc}") from None
    except RecursionError:
        raise error(f"{name}: nested too deeply to read (tables or arrays inside one "
                    "another thousands of times)") from None


# -- libraries that open files themselves, by name ------------------------------------------
def library_path(path, what: str = "file", error=InputError) -> str:
    """The resolved name of ``path`` for a library that opens files itself (pxr's layers,
    URDF meshes): every check ``opened`` makes (confinement with links resolved, a regular
    file within the size budget, no LFS pointer, readable) done on it first. The library
    reads by name after that; facet reads nothing through it."""
    with opened(path, what, error):
        pass
    return str(Path(path).resolve())


def check_package(path, what: str = "USDZ package", error=InputError) -> list[str]:
    """The member names of a zip package (a .usdz) after its table of contents is checked:
    every member within the size budget and all of them together, at most the budget of
    items, no absolute or parent-folder names, nothing compressed (USDZ stores members
    as they are, so an archive that expands is not one)."""
    import zipfile

    limit = budget("file_bytes")
    with opened(path, what, error) as (f, _size):
        try:
            archive = zipfile.ZipFile(f)
        except (zipfile.BadZipFile, OSError) as exc:
            raise error(f"{path}: not a readable {what} ({exc})") from None
        with archive:
            infos = archive.infolist()
    if len(infos) > budget("gltf_items"):
        raise error(f"{path}: {len(infos):,} members, more than facet's budget of "
                    f"{budget('gltf_items'):,} (--budget gltf_items=N)")
    total = 0
    for info in infos:
        name = info.filename
        if name.startswith(("/", "\\")) or ".." in Path(name).parts:
            raise error(f"{path}: member {name!r} names a place outside the package")
        if info.compress_type != zipfile.ZIP_STORED:
            raise error(f"{path}: member {name!r} is compressed; a {what} stores its files "
                        "uncompressed (USDZ's rule), so facet does not expand it")
        total += info.file_size
        if info.file_size > limit or total > limit:
            raise error(f"{path}: its members hold more than facet's budget of "
                        f"{limit / 2**30:.1f} GiB (--budget file_bytes=N)")
    return [info.filename for info in infos]


def package_member(path, member: str, what: str = "file", error=InputError) -> bytes:
    """The bytes of ``member`` of the zip package ``path`` (checked by ``check_package``)."""
    import zipfile

    check_package(path, error=error)
    with opened(path, what, error) as (f, _size), zipfile.ZipFile(f) as archive:
        try:
            return archive.read(member)
        except KeyError:
            raise error(f"{path}: has no member {member!r} (the {what} it names)") from None


def usd_layer(path, what: str = "USD layer", error=InputError):
    """An Sdf layer of ``path`` opened by pxr after ``library_path``'s checks (a .usdz's
    table of contents checked too); ``error`` when pxr cannot read it."""
    text = str(path)
    outer, bracket, member = text.partition("[")  # a package's member: pkg.usdz[a.usdc]
    name = library_path(outer, what, error)
    if name.lower().endswith(".usdz"):
        check_package(name, error=error)
    if bracket:
        name = f"{name}[{member}"
    from pxr import Sdf, Tf

    try:
        layer = Sdf.Layer.FindOrOpen(name)
    except Tf.ErrorException as exc:
        raise error(f"{path}: not a USD layer pxr can read ({pxr_message(exc)})") from None
    if layer is None:
        raise error(f"{path}: not a USD layer pxr can read")
    return layer


def usd_stage(root, session, load_payloads: bool, checked: set, error=InputError):
    """The stage composed on the root layer ``root`` (opened by ``usd_layer``, as every
    layer it reaches must have been: ``checked`` holds their real paths) with the session
    layer ``session`` (variant selections); a layer the composition used that was not
    checked is ``error`` (none should be: the walk opens each one first)."""
    from pxr import Usd

    load = Usd.Stage.LoadAll if load_payloads else Usd.Stage.LoadNone
    stage = Usd.Stage.Open(root, session, load)
    for layer in stage.GetUsedLayers():
        real = layer.realPath
        if layer.anonymous or not real:
            continue
        outer = real.split("[", 1)[0]  # a member of a package: the package was checked
        if outer not in checked:
            raise error(f"{real}: a layer the stage reads that facet did not check first")
    return stage


def pxr_message(exc) -> str:
    """The last message of a pxr error, without its C++ location."""
    block = str(exc).split("Error in")[-1]
    at = block.find(" : '")
    text = block[at + 4:] if at >= 0 else block
    return text.strip().rstrip("'").strip() or "unreadable"

"""Dataset manifests: which models to render, from which views, into what (no GL).

A manifest is a TOML file, a JSON Lines file, or a glob of model files::

    # dataset.toml
    [defaults]                       # every job's values unless the job gives its own
    size = [256, 256]                # (a dataset's default size and channels, below a
    outputs = ["color", "depth", "normals"]  # scene file's [render]: FRONT_DEFAULTS)
    views = { plan = "sphere", count = 8 }
    seed = 0

    [[jobs]]
    model = "models/bunny.obj"       # a mesh file or a .toml scene, relative to the manifest
    name = "bunny"                   # the job's folder (default: the model's name)
    views = { plan = "turntable", count = 12, elevation = 20 }
    shading = "blinn"                # any render option (facet.options.render)
    float_files = ["npy", "exr"]     # float channels as .npy (default) and / or OpenEXR
    colmap = true                    # also a COLMAP text model in JOB/sparse/0/

In JSON Lines each line is one job (``{"model": ..., ...}``); a line ``{"defaults": {...}}``
sets defaults for the lines after it. A .json file may also be one document: a list of
jobs, or ``{"defaults": {...}, "jobs": [...]}``. A glob (``"models/*.obj"``) makes one job per file.
Views: facet.batch.views. Render options are handed raw to the one options parser
(facet.options.render), file names relative to the manifest's folder; a job renders with
facet's defaults < a dataset's (FRONT_DEFAULTS["batch"]) < its scene file's [render] <
the manifest's defaults < the command line's < its own. The whole manifest is validated
before anything renders; an error names the line (JSON Lines) or job and the key.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

from ..budgets import budget
from ..errors import InputError
from ..guard import confined, json_depth, parse_json, read_text, regular_file
from ..options.render import (
    MAX_FRAMES,
    PARSERS,
    PATH_KEYS,
    ParsedLayer,
    merge_raw,
    parse_layer,
)
from .views import PLANS, ViewPlan

JOB_KEYS = ("model", "name", "views", "seed", "float_files", "colmap",  # and render options
            "joints", "variants", "payloads", "purposes", "package_path", "collision")
# How a job's model is read (open_scene's arguments): a URDF robot's configuration, an
# OpenUSD stage's variants, payloads and purposes.
LOAD_KEYS = ("joints", "variants", "payloads", "purposes", "package_path", "collision")
FLOAT_FILES = ("npy", "exr")
VIEW_KEYS = ("plan", "count", "elevation", "elevations", "seed", "file", "times",
             "random_times", "joints", "random_joints")
FRONT = "batch"  # a dataset's defaults (facet.options.render.FRONT_DEFAULTS)


@dataclass(frozen=True)
class Job:
    """One model's renders: its folder ``name``, views, the render options it gives
    (parsed once: facet.options.render; size, outputs, up, ... all among them), the float
    channels' file formats and whether a COLMAP model is written too (facet.batch.layout).
    ``given``: the options as the manifest wrote them (file names made absolute), what the
    digest reads."""

    name: str
    model: Path
    views: ViewPlan
    options: ParsedLayer = field(default_factory=ParsedLayer)
    given: dict = field(default_factory=dict)
    float_files: tuple[str, ...] = ("npy",)
    colmap: bool = False
    load: dict = field(default_factory=dict)  # open_scene's arguments (LOAD_KEYS)

    def digest(self) -> str:
        """What the job's files depend on (a rerun skips a finished job with the same)."""
        text = json.dumps([str(self.model), self.views.__dict__, self.given,
                           self.float_files, self.colmap, self.load], sort_keys=True,
                          default=str)
        try:
            stamp = self.model.stat()
            text += f"{stamp.st_size}:{stamp.st_mtime_ns}"
        except OSError:
            pass
        return hashlib.sha1(text.encode()).hexdigest()


def load_manifest(source, defaults: dict | None = None, confine=None) -> list[Job]:
    """Jobs of a manifest file (.toml, .jsonl / .json) or a glob of model files;
    ``defaults`` (the command line's --size, --outputs, --views ...) override the
    manifest's defaults; a job's own values override both. ``confine``: None or (folder,
    widen) (``job_root``): a job's cameras file is checked against its folder before it
    is opened."""
    text = str(source)
    path = Path(text)
    base_defaults = dict(defaults or {})
    if path.suffix.lower() == ".toml" and path.is_file():
        from ..guard import parse_toml

        data = parse_toml(read_text(path, "manifest"), path.name)
        entries = _document_entries(data, path.name, base_defaults, "[defaults] and [[jobs]]")
        base = path.parent
    elif path.suffix.lower() in (".jsonl", ".json") and path.is_file():
        entries, merged = [], base_defaults
        text_ = read_text(path, "manifest")
        document = _json_document(text_, path.name) if path.suffix.lower() == ".json" else None
        if document is not None:  # one JSON value: [jobs] or {"defaults", "jobs"}
            if isinstance(document, list):
                document = {"jobs": document}
            entries = _document_entries(_table(document, path.name), path.name, base_defaults,
                                        "\"defaults\" and \"jobs\"")
        lines = [] if document is not None else text_.splitlines()
        for number, line in enumerate(lines, start=1):
            if not line.strip():
                continue
            where = f"{path.name}:{number}"
            obj = _table(parse_json(line, where), where)
            if "defaults" in obj:
                merged = merge_raw(merged, _table(obj["defaults"], f"{where}: defaults"),
                                   base_defaults)
                continue
            entries.append((where, merged, obj))
        base = path.parent
    else:
        # Files only: a folder the pattern also matches is no model.
        files = _model_files(text)
        if not files:
            raise InputError(f"{text}: no manifest file and no model files match it")
        entries = [(f, base_defaults, {"model": f}) for f in files]
        base = Path(".")
    if not entries:
        raise InputError(f"{text}: the manifest lists no jobs")
    jobs = [_job(where, merge_raw(d, j), base, confine) for where, d, j in entries]
    _say_what_jobs_keep(base_defaults, [j for _, _, j in entries])
    names: dict[str, str] = {}
    unique = []
    for (where, _, _), job in zip(entries, jobs, strict=True):
        name, k = job.name, 1
        while name in names:  # two models of one name: number the later folders
            k += 1
            name = f"{job.name}-{k}"
        names[name] = where
        unique.append(job if name == job.name else dataclasses.replace(job, name=name))
    return unique


def _say_what_jobs_keep(given: dict, jobs: list[dict]) -> None:
    """One warning line for each command-line default (--views, --size ...) that some jobs
    set for themselves: a job's own value wins (the documented precedence), so the flag
    does not reach them, and that is said, not silent."""
    import warnings

    from ..errors import FacetWarning

    for key in given:
        own = sum(1 for j in jobs if key in j)
        if own:
            flag = "--" + key.replace("_", "-")
            warnings.warn(f"{own} of {len(jobs)} jobs set their own {key}: {flag} is the "
                          "default of the others only (a job's own values win)",
                          FacetWarning, stacklevel=3)


def _model_files(pattern: str) -> list[str]:
    """The files a glob names, sorted; ``**`` descends into folders but never through a
    symbolic link to one (a link back up would loop for ever)."""
    parts = Path(pattern).parts
    fixed = next((i for i, part in enumerate(parts) if any(c in part for c in "*?[")),
                 len(parts))
    if fixed == len(parts):
        return [pattern] if Path(pattern).is_file() else []
    base = Path(*parts[:fixed]) if fixed else Path(".")
    try:
        found = base.glob(str(Path(*parts[fixed:])))
        return sorted(str(f) for f in found if f.is_file())
    except (OSError, ValueError):  # unreadable folders, a pattern pathlib cannot take
        return []


def _document_entries(data: dict, name: str, base_defaults: dict, keys: str) -> list:
    """(where, defaults, job) of a manifest written as one document (TOML, or one JSON
    value): its defaults under the command line's, each job with them."""
    for key in data:
        if key not in ("defaults", "jobs"):
            raise InputError(f"{name}: unknown key {key!r}; a manifest has {keys}")
    merged = merge_raw(_table(data.get("defaults", {}), f"{name}: defaults"), base_defaults)
    jobs = data.get("jobs", [])
    if not isinstance(jobs, list):
        raise InputError(f"{name}: jobs: expected a list of jobs")
    return [(f"{name}: jobs[{i}]", merged, _table(j, f"{name}: jobs[{i}]"))
            for i, j in enumerate(jobs)]


def _json_document(text: str, name: str):
    """The value of a .json manifest written as one JSON document, or None when it is JSON
    Lines (one job per line) instead."""
    try:
        value = json.loads(text) if json_depth(text, budget("depth")) <= budget("depth") \
            else parse_json(text, name)  # says how deep, in one line
    except json.JSONDecodeError:
        return None
    return value if isinstance(value, list) or (isinstance(value, dict) and (
        "jobs" in value or set(value) <= {"defaults"})) else None


def _table(value, where: str) -> dict:
    if not isinstance(value, dict):
        raise InputError(f"{where}: expected a table / object, got {value!r}")
    return value


def _job(where: str, t: dict, base: Path, confine=None) -> Job:
    for key in t:
        if key not in JOB_KEYS and key not in PARSERS:
            import difflib

            close = difflib.get_close_matches(key, [*JOB_KEYS, *PARSERS], n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(f"{where}: unknown key {key!r}{hint}")
    if "model" not in t:
        raise InputError(f"{where}: needs model = \"FILE\"")
    if not isinstance(t["model"], str) or not t["model"]:
        raise InputError(f"{where}.model: expected a file name, got {t['model']!r}")
    model = Path(t["model"])
    model = model if model.is_absolute() else base / model
    try:  # the whole manifest is checked before any rendering
        regular_file(model, "model file", missing="file")
    except InputError as exc:
        raise InputError(f"{where}.model: {exc}") from None
    name = str(t.get("name") or model.stem)
    if not name or "/" in name or name.startswith(".") or "\0" in name or \
            any(ord(c) < 32 for c in name) or len(name.encode("utf-8", "replace")) > 200:
        raise InputError(f"{where}.name: {name!r} cannot be a folder name")
    given = {k: v for k, v in t.items() if k in PARSERS and v is not None}
    for key in PATH_KEYS:  # file names from the manifest's folder (and so in the digest)
        if isinstance(given.get(key), str) and given[key] != "sky":
            given[key] = str((base / given[key]).resolve())
    try:
        options = parse_layer(given, base)
        json.dumps(given)  # what the digest reads: a manifest's values always are JSON
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    except TypeError:
        raise InputError(f"{where}: render options must be plain values (numbers, text, "
                         "lists)") from None
    views = _views(t.get("views", {}), f"{where}.views", t.get("seed", 0))
    if views.file is not None:  # relative to the manifest, checked now
        file = Path(views.file) if Path(views.file).is_absolute() else base / views.file
        try:  # read now: a file that is no transforms.json is found before any rendering
            root = job_root(confine, model)
            with contextlib.nullcontext() if root is None else confined(root):
                regular_file(file, "cameras file", missing="file")  # confined: checked first
                count = _camera_count(str(file.resolve()))
        except InputError as exc:
            raise InputError(f"{where}.views.file: {exc}") from None
        views = ViewPlan(views.kind, count, views.elevation, views.elevations,
                         views.seed, str(file))
    return Job(name, model, views, options, given, _float_files(t, where),
               _flag(t, "colmap", where), _load_arguments(t, where, base))


def _load_arguments(t: dict, where: str, base: Path) -> dict:
    """open_scene's arguments a job gives (LOAD_KEYS), checked."""
    out: dict = {}
    for key in ("joints", "variants"):
        if key in t:
            value = t[key]
            if not isinstance(value, dict) or not all(isinstance(k, str) for k in value):
                raise InputError(f"{where}.{key}: expected a table of names, got {value!r}")
            if key == "joints" and not all(isinstance(v, (int, float)) and
                                           not isinstance(v, bool) for v in value.values()):
                raise InputError(f"{where}.joints: values must be numbers (radians, metres)")
            if key == "variants" and not all(isinstance(v, str) for v in value.values()):
                raise InputError(f"{where}.variants: values must be variant names")
            out[key] = dict(value)
    for key in ("payloads", "collision"):
        if key in t:
            out[key] = _flag(t, key, where)
    if "purposes" in t:
        value = t["purposes"]
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise InputError(f"{where}.purposes: expected a list of purposes")
        out["purposes"] = tuple(value)
    if "package_path" in t:
        value = t["package_path"]
        value = [value] if isinstance(value, str) else value
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise InputError(f"{where}.package_path: expected folder names")
        out["package_path"] = tuple(str((base / v).resolve()) for v in value)
    return out


def job_root(confine, model) -> Path | None:
    """The folder outside which a job reads no file: ``confine = (folder, widen)``; with
    ``widen`` (the default, a manifest's own folder) a model the manifest lists outside
    that folder gets its own folder instead: the manifest named it, so it is read, and
    what it refers to (textures, material libraries, a scene's meshes) must lie beside
    or under it."""
    if confine is None:
        return None
    root, widen = Path(confine[0]), confine[1]
    model = Path(model).resolve()
    return model.parent if widen and root not in model.parents else root


def _float_files(t: dict, where: str) -> tuple[str, ...]:
    value = t.get("float_files", "npy")
    formats = (value,) if isinstance(value, str) else value
    if (not isinstance(formats, (list, tuple)) or not formats
            or any(f not in FLOAT_FILES for f in formats)):
        raise InputError(f"{where}.float_files: {value!r}; give \"npy\", \"exr\" or both "
                         "as a list")
    if "exr" in formats:
        from ..image.writers import EXR_HINT, exr_available

        if not exr_available():
            raise InputError(f"{where}.float_files: EXR files need {EXR_HINT}")
    return tuple(dict.fromkeys(formats))


def _flag(t: dict, key: str, where: str) -> bool:
    value = t.get(key, False)
    if not isinstance(value, bool):
        raise InputError(f"{where}.{key}: expected true or false, got {value!r}")
    return value


@functools.lru_cache(maxsize=64)  # jobs of a manifest often share one cameras file
def _camera_count(path: str) -> int:
    from .transforms_file import read_transforms

    count = len(read_transforms(Path(path), size=(64, 64)))  # (any size: only counted)
    if not 1 <= count <= MAX_FRAMES:
        raise InputError(f"{path}: {count} frames; expected 1..{MAX_FRAMES}")
    return count


def _views(v, where: str, seed) -> ViewPlan:
    if isinstance(v, int):
        v = {"count": v}
    v = _table(v, where)
    for key in v:
        if key not in VIEW_KEYS:
            raise InputError(f"{where}: unknown key {key!r}; expected {', '.join(VIEW_KEYS)}")
    plan = v.get("plan", "sphere")
    if plan not in PLANS:
        raise InputError(f"{where}.plan: {plan!r}; choose one of {', '.join(PLANS)}")
    joints = _view_joints(v, where)
    count = v.get("count", 8 if joints is None else len(joints))
    if joints is not None and count != len(joints):
        raise InputError(f"{where}.joints: {len(joints)} configurations for {count!r} views; "
                         "give one per view (or leave count out)")
    if plan != "cameras" and not (_whole(count) and 1 <= count <= MAX_FRAMES):
        raise InputError(f"{where}.count: expected 1..{MAX_FRAMES} views, got {count!r}")
    if plan == "cameras" and "file" not in v:
        raise InputError(f"{where}: plan = \"cameras\" needs file = \"transforms.json\"")
    file = v.get("file")
    if file is not None and (not isinstance(file, str) or not file or "\0" in file):
        raise InputError(f"{where}.file: expected the path of a transforms.json, got {file!r}")
    seed = v.get("seed", seed)
    if not (_whole(seed) and 0 <= seed < 2**63):
        raise InputError(f"{where}.seed: expected a whole number >= 0, got {seed!r}")
    elevation = v.get("elevation", 20.0)
    if not (_real(elevation) and -90 <= elevation <= 90):
        raise InputError(f"{where}.elevation: expected degrees in [-90, 90], got {elevation!r}")
    lo_hi = v.get("elevations", [-10.0, 40.0])
    if not (isinstance(lo_hi, (list, tuple)) and len(lo_hi) == 2 and all(map(_real, lo_hi))
            and -90 <= lo_hi[0] <= lo_hi[1] <= 90):
        raise InputError(f"{where}.elevations: expected [low, high] degrees with -90 <= low "
                         f"<= high <= 90, got {lo_hi!r}")
    times = v.get("times")
    if times is not None and not (isinstance(times, (list, tuple)) and len(times) == 2 and
                                  all(map(_real, times)) and 0 <= times[0] <= times[1]):
        raise InputError(f"{where}.times: expected [start, end] seconds with 0 <= start <= "
                         f"end (the animations' times the views sample), got {times!r}")
    random_times = v.get("random_times", False)
    if not isinstance(random_times, bool) or (random_times and times is None):
        raise InputError(f"{where}.random_times: expected true or false, with times = "
                         f"[start, end] (got {random_times!r})")
    random_joints = v.get("random_joints", False)
    if not isinstance(random_joints, bool) or (random_joints and joints is not None):
        raise InputError(f"{where}.random_joints: expected true or false, without joints "
                         f"(got {random_joints!r})")
    return ViewPlan(plan, int(count), float(elevation), (float(lo_hi[0]), float(lo_hi[1])),
                    int(seed), file, None if times is None else
                    (float(times[0]), float(times[1])), random_times, joints, random_joints)


def _view_joints(v: dict, where: str) -> tuple | None:
    """A views table's ``joints``: a list of {joint: number} tables, one per view."""
    if "joints" not in v:
        return None
    value = v["joints"]
    if not isinstance(value, list) or not value or not all(
            isinstance(c, dict) and all(isinstance(k, str) and _real(x)
                                        for k, x in c.items()) for c in value):
        raise InputError(f"{where}.joints: expected a list of tables of joint values "
                         "(radians, metres), one per view")
    if len(value) > MAX_FRAMES:
        raise InputError(f"{where}.joints: {len(value)} configurations; at most "
                         f"{MAX_FRAMES} views")
    return tuple(dict(c) for c in value)


def _whole(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _real(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)

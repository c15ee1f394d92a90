"""Test data for the dataset tests: small generated models, manifests, and the child
processes of a running ``facet batch``."""

import json
from pathlib import Path

import trimesh


def make_models(folder: Path, n: int) -> list[Path]:
    """n small closed meshes of different shapes and sizes (generated)."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in range(n):
        mesh = [trimesh.creation.icosphere(subdivisions=2, radius=0.5 + 0.05 * i),
                trimesh.creation.box(extents=(1, 0.5 + 0.1 * i, 0.8)),
                trimesh.creation.cylinder(radius=0.3, height=1.0 + 0.1 * i),
                trimesh.creation.capsule(radius=0.3, height=0.5)][i % 4]
        mesh.apply_translation((0.1 * i, 0, 0))
        path = folder / f"m{i:02d}.ply"
        mesh.export(path)
        paths.append(path)
    return paths


def write_manifest(folder: Path, jobs: list[dict], defaults: dict | None = None) -> Path:
    lines = [json.dumps({"defaults": defaults})] if defaults else []
    lines += [json.dumps(j) for j in jobs]
    path = folder / "dataset.jsonl"
    path.write_text("\n".join(lines) + "\n")
    return path


def child_pids(pid: int) -> list[int]:
    kids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            kids.append(int(stat.parent.name))
    return kids

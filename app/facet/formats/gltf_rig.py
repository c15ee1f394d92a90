"""A glTF file's animations, skins and morph targets -> a facet.scene.animation.Rig.

Reads the document's JSON (node weights and other keys pygltflib leaves out) and its
accessors (facet.formats.gltf_data), and checks what the structural checker
(facet.formats.gltf_check) cannot know without the data: that key counts agree with value
counts, keys are finite and in order, joints index their skin, inverse bind matrices and
morph targets have a value per joint and per vertex. Each failure is one MeshError line
naming the file and the key path.
"""

from __future__ import annotations

import numpy as np

from ..scene.animation import (
    INTERPOLATIONS,
    Binding,
    Channel,
    Clip,
    Deformation,
    Rig,
    Sampler,
    Skin,
)

PATH_WIDTH = {"translation": 3, "rotation": 4, "scale": 3}
TARGET_KEYS = {"POSITION": "positions", "NORMAL": "normals", "TANGENT": "tangents"}


def vertex_deformation(prim: dict, data, count: int, where: str,
                       decoded: dict | None = None) -> Deformation | None:
    """The skin (JOINTS_0/1, WEIGHTS_0/1) and morph-target (targets) data of primitive
    ``prim`` (its JSON) of ``count`` vertices, or None when it has neither; ``decoded``:
    the attributes a Draco stream held ({name: array}), read instead of their accessors."""
    attrs = prim.get("attributes") or {}

    def per_vertex(name: str, accessor, normalize: bool = True):
        if decoded is not None and name in decoded:
            values = np.asarray(decoded[name]).reshape(len(decoded[name]), -1)
            if len(values) != count:
                data.fail(f"{where}: {name} has {len(values):,} values in its Draco stream "
                          f"for {count:,} vertices")
            return values
        return _per_vertex(data, accessor, count, f"{where}: {name}", normalize=normalize)

    joints, weights = [], []
    for k in (0, 1):
        j, w = attrs.get(f"JOINTS_{k}"), attrs.get(f"WEIGHTS_{k}")
        if j is None and w is None:
            continue
        if j is None or w is None:
            data.fail(f"{where}: JOINTS_{k} and WEIGHTS_{k} come in pairs; it has only "
                      f"{'JOINTS' if w is None else 'WEIGHTS'}_{k}")
        joints.append(per_vertex(f"JOINTS_{k}", j, normalize=False))
        weights.append(per_vertex(f"WEIGHTS_{k}", w))
    targets: dict = {}
    for t, target in enumerate(prim.get("targets") or []):
        for key, name in TARGET_KEYS.items():
            if key in target:
                v = _per_vertex(data, target[key], count, f"{where}: targets[{t}].{key}")
                targets.setdefault(name, {})[t] = v[:, :3]
    if not joints and not targets:
        return None
    n_targets = len(prim.get("targets") or [])
    stacked = {name: np.stack([by_t.get(t, np.zeros((count, 3))) for t in range(n_targets)])
               .astype(np.float32) for name, by_t in targets.items()}
    if not joints:
        return Deformation(targets=stacked)
    j = np.concatenate(joints, axis=1).astype(np.int64)
    w = np.concatenate(weights, axis=1).astype(np.float64)
    if (w < 0).any():
        data.fail(f"{where}: WEIGHTS hold negative weights")
    total = w.sum(axis=1, keepdims=True)
    w = np.where(total > 0, w / np.where(total > 0, total, 1.0), np.eye(1, w.shape[1]))
    return Deformation(j, w, stacked)


def _per_vertex(data, accessor: int, count: int, what: str, normalize: bool = True):
    values = np.asarray(data.accessor(accessor, normalize=normalize))
    values = values.reshape(len(values), -1)
    if len(values) != count:
        data.fail(f"{what} has {len(values):,} values for {count:,} vertices (accessor "
                  f"{accessor}); the counts must agree")
    if values.dtype.kind == "f" and not np.isfinite(values).all():
        data.fail(f"{what} holds NaN or infinite values (accessor {accessor})")
    return values


def read_rig(document: dict, data, parts: list, cameras: dict) -> Rig | None:
    """The Rig of a glTF ``document`` whose reader made ``parts`` [(node, skin or None,
    Deformation or None, 4x4 instance -> node or None)], one per part in order;
    ``cameras``: {name: node}. None when nothing in the file moves or deforms."""
    nodes = document.get("nodes") or []
    animations = document.get("animations") or []
    if not animations and not any(s is not None or d is not None for _, s, d, _ in parts):
        return None
    parents = np.full(len(nodes), -1, dtype=np.int64)
    for i, n in enumerate(nodes):
        for c in n.get("children") or []:
            parents[c] = i
    order = _order(parents)
    rest_t, rest_r, rest_s = np.zeros((len(nodes), 3)), np.zeros((len(nodes), 4)), \
        np.ones((len(nodes), 3))
    rest_r[:, 3] = 1.0
    fixed, weights = {}, {}
    meshes = document.get("meshes") or []
    for i, n in enumerate(nodes):
        if n.get("matrix") is not None:
            fixed[i] = np.asarray(n["matrix"], dtype=np.float64).reshape(4, 4).T
        for key, array in (("translation", rest_t), ("rotation", rest_r), ("scale", rest_s)):
            if n.get(key) is not None:
                array[i] = n[key]
        default = n.get("weights")
        if default is None and n.get("mesh") is not None:
            default = meshes[n["mesh"]].get("weights")
        if default is not None:
            weights[i] = np.asarray(default, dtype=np.float64)
    skins = [_skin(s, data, f"skins[{k}]") for k, s in enumerate(document.get("skins") or [])]
    bindings = []
    for part, (node, skin, deform, offset) in enumerate(parts):
        if skin is not None and (deform is None or deform.joints is None):
            data.fail(f"nodes[{node}] has skin {skin}, but its mesh has no JOINTS_0 and "
                      "WEIGHTS_0 to bind it")
        if skin is not None and deform.joints.size and \
                deform.joints.max() >= len(skins[skin].joints):
            data.fail(f"nodes[{node}]: its mesh's JOINTS refer to joint "
                      f"{int(deform.joints.max())}, but skins[{skin}] has "
                      f"{len(skins[skin].joints)} joints")
        if deform is not None and deform.targets and node not in weights:
            weights[node] = np.zeros(next(iter(deform.targets.values())).shape[0])
        bindings.append(Binding(part, node, skin, deform, offset))
    clips = [_clip(a, data, document, fixed, k) for k, a in enumerate(animations)]
    return Rig(parents, order, (rest_t, rest_r, rest_s), fixed, weights, clips, skins,
               bindings, {name: (node, None) for name, node in cameras.items()})


def _order(parents: np.ndarray) -> list[int]:
    """Every node after its parent (the graph is a checked forest: gltf_check)."""
    children: dict[int, list[int]] = {}
    for i, p in enumerate(parents):
        children.setdefault(int(p), []).append(i)
    order, stack = [], list(reversed(children.get(-1, [])))
    while stack:
        k = stack.pop()
        order.append(k)
        stack.extend(reversed(children.get(k, [])))
    return order


def _skin(skin: dict, data, at: str) -> Skin:
    joints = np.asarray(skin.get("joints") or [], dtype=np.int64)
    if not len(joints):
        data.fail(f"{at}.joints: a skin needs at least one joint")
    ibm = skin.get("inverseBindMatrices")
    if ibm is None:
        inverse = np.tile(np.eye(4), (len(joints), 1, 1))
    else:
        values = np.asarray(data.accessor(ibm), dtype=np.float64)
        if values.ndim != 2 or values.shape[1] != 16:
            data.fail(f"{at}.inverseBindMatrices: accessor {ibm} is not MAT4")
        if len(values) < len(joints):
            data.fail(f"{at}.inverseBindMatrices: {len(values)} matrices for "
                      f"{len(joints)} joints; the counts must agree")
        if not np.isfinite(values).all():
            data.fail(f"{at}.inverseBindMatrices hold NaN or infinite values")
        inverse = values[:len(joints)].reshape(-1, 4, 4).transpose(0, 2, 1)
    return Skin(joints, inverse)


def _clip(animation: dict, data, document: dict, fixed: dict, k: int) -> Clip:
    at = f"animations[{k}]"
    samplers = animation.get("samplers") or []
    nodes = document.get("nodes") or []
    channels = []
    for c, ch in enumerate(animation.get("channels") or []):
        where = f"{at}.channels[{c}]"
        target = ch.get("target") or {}
        node, path = target.get("node"), target.get("path")
        if node is None:  # allowed: a channel for an extension's target; nothing to move
            continue
        if path not in PATH_WIDTH and path != "weights":
            if path == "pointer":
                continue  # KHR_animation_pointer's; the reader warns about the extension
            data.fail(f"{where}.target.path: expected translation, rotation, scale or "
                      f"weights, got {path!r}")
        if path != "weights" and node in fixed:
            data.fail(f"{where}: animates nodes[{node}].{path}, but that node is given by a "
                      "matrix (glTF animates nodes given by translation, rotation, scale)")
        index = ch.get("sampler")
        sampler = _sampler(samplers[index], data, f"{at}.samplers[{index}]", path,
                           _targets(document, nodes[node]) if path == "weights" else 1)
        channels.append(Channel(int(node), path, sampler))
    return Clip(animation.get("name") or f"animation{k}", tuple(channels))


def _targets(document: dict, node: dict) -> int:
    mesh = node.get("mesh")
    if mesh is None:
        return 0
    prims = (document.get("meshes") or [])[mesh].get("primitives") or []
    return max((len(p.get("targets") or []) for p in prims), default=0)


def _sampler(s: dict, data, at: str, path: str, n_targets: int) -> Sampler:
    mode = s.get("interpolation", "LINEAR")
    if mode not in INTERPOLATIONS:
        data.fail(f"{at}.interpolation: expected one of {', '.join(INTERPOLATIONS)}, "
                  f"got {mode!r}")
    times = np.asarray(data.accessor(s["input"]), dtype=np.float64).reshape(-1)
    values = np.asarray(data.accessor(s["output"]), dtype=np.float64)
    if not len(times):
        data.fail(f"{at}.input: an animation sampler needs at least one key")
    if not (np.isfinite(times).all() and np.isfinite(values).all()):
        data.fail(f"{at}: its keyframes hold NaN or infinite values")
    if np.any(np.diff(times) < 0):
        data.fail(f"{at}.input: key times must increase")
    width = PATH_WIDTH.get(path, n_targets)
    per_key = (3 if mode == "CUBICSPLINE" else 1) * width
    if width == 0:
        data.fail(f"{at}: animates morph weights of a node whose mesh has no targets")
    if values.size != len(times) * per_key:
        data.fail(f"{at}: {len(times)} key times need {len(times) * per_key:,} output "
                  f"values for {path} ({mode}), the output accessor has {values.size:,}; "
                  "the counts must agree")
    shape = (len(times), 3, width) if mode == "CUBICSPLINE" else (len(times), width)
    return Sampler(times, values.reshape(shape), mode)

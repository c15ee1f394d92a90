"""The Khronos sample models that move (../shared/gltf: RiggedSimple, RiggedFigure,
AnimatedMorphCube, InterpolationTest, BoxAnimated) posed at chosen times against a
reference evaluator written here on pygltflib's parse and numpy (its own accessor reader,
interpolation and skinning from the specification, sharing nothing with facet's), and each
drawn moving: the picture at one time differs from the picture at another."""

from __future__ import annotations

import numpy as np
import pytest

import facet

from conftest import SHARED_GLTF, shared_model
from test_animation import hermite, ref_slerp, rot_matrix

DTYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


class Reference:
    def __init__(self, path):
        from pygltflib import GLTF2

        self.g = GLTF2().load(str(path))
        self.blob = self.g.binary_blob()

    def accessor(self, i):
        a = self.g.accessors[i]
        bv = self.g.bufferViews[a.bufferView]
        dtype = np.dtype(DTYPES[a.componentType])
        width = WIDTHS[a.type]
        stride = bv.byteStride or dtype.itemsize * width
        start = (bv.byteOffset or 0) + (a.byteOffset or 0)
        raw = np.frombuffer(self.blob, np.uint8)
        rows = np.stack([raw[start + k * stride:start + k * stride + dtype.itemsize * width]
                         for k in range(a.count)])
        out = rows.view(dtype).reshape(a.count, width).astype(np.float64)
        if a.normalized:
            out = out / np.iinfo(dtype).max
        return out

    def sample(self, s, t, rotation):
        times = self.accessor(s.input)[:, 0]
        values = self.accessor(s.output)
        cubic = s.interpolation == "CUBICSPLINE"
        v = values.reshape(len(times), 3, -1) if cubic else values.reshape(len(times), -1)
        key = v[:, 1] if cubic else v
        if t <= times[0]:
            return key[0]
        if t >= times[-1]:
            return key[-1]
        k = int(np.searchsorted(times, t, side="right") - 1)
        span = times[k + 1] - times[k]
        u = (t - times[k]) / span
        if s.interpolation == "STEP":
            return key[k]
        if cubic:
            out = hermite(key[k], v[k, 2], key[k + 1], v[k + 1, 0], span, u)
            return out / np.linalg.norm(out) if rotation else out
        return ref_slerp(key[k], key[k + 1], u) if rotation else key[k] + u * (key[k + 1] - key[k])

    def world(self, t):
        nodes = self.g.nodes
        props = [{"translation": n.translation or [0, 0, 0], "rotation": n.rotation or
                  [0, 0, 0, 1], "scale": n.scale or [1, 1, 1]} for n in nodes]
        weights = {}
        for anim in self.g.animations:
            for ch in anim.channels:
                value = self.sample(anim.samplers[ch.sampler], t, ch.target.path == "rotation")
                if ch.target.path == "weights":
                    weights[ch.target.node] = value
                else:
                    props[ch.target.node][ch.target.path] = value
        world = {}

        def visit(i, parent):
            n = nodes[i]
            if n.matrix:
                local = np.array(n.matrix, float).reshape(4, 4).T
            else:
                local = np.eye(4)
                local[:3, :3] = rot_matrix(props[i]["rotation"]) @ np.diag(props[i]["scale"])
                local[:3, 3] = props[i]["translation"]
            world[i] = parent @ local
            for c in n.children or []:
                visit(c, world[i])

        for root in self.g.scenes[self.g.scene or 0].nodes:
            visit(root, np.eye(4))
        return world, weights

    def positions(self, t):
        """{node: (N, 3) world positions} of every mesh node's first primitive."""
        world, weights = self.world(t)
        out = {}
        for i, n in enumerate(self.g.nodes):
            if n.mesh is None:
                continue
            prim = self.g.meshes[n.mesh].primitives[0]
            p = self.accessor(prim.attributes.POSITION)
            w = weights.get(i, self.g.meshes[n.mesh].weights or [])
            for k, target in enumerate(prim.targets or []):
                if k < len(w) and "POSITION" in target:
                    p = p + w[k] * self.accessor(target["POSITION"])
            ph = np.hstack([p, np.ones((len(p), 1))])
            if n.skin is not None:
                skin = self.g.skins[n.skin]
                ibm = self.accessor(skin.inverseBindMatrices).reshape(-1, 4, 4).transpose(0, 2, 1)
                joints = self.accessor(prim.attributes.JOINTS_0).astype(int)
                jw = self.accessor(prim.attributes.WEIGHTS_0)
                acc = np.zeros((len(p), 3))
                for k in range(4):
                    mats = np.stack([world[skin.joints[j]] @ ibm[j]
                                     for j in range(len(skin.joints))])[joints[:, k]]
                    acc += jw[:, k:k + 1] * np.einsum("nij,nj->ni", mats, ph)[:, :3]
                out[i] = acc
            else:
                out[i] = (ph @ world[i].T)[:, :3]
        return out


def _facet_positions(scene, t):
    posed = scene.at(t, "all")  # the reference plays every clip (InterpolationTest has 9)
    return [o.mesh.positions @ o.transform[:3, :3].T + o.transform[:3, 3]
            for o in posed.objects]


@pytest.mark.parametrize("model, times", [
    ("RiggedSimple", (0.0, 0.7, 1.9, 3.1)),
    ("RiggedFigure", (0.0, 0.35, 1.1)),
    ("AnimatedMorphCube", (0.0, 0.5, 1.2, 2.4)),
    ("InterpolationTest", (0.0, 0.3, 1.0, 1.45, 2.2, 3.3)),
    ("BoxAnimated", (0.0, 0.8, 1.6, 3.0)),
])
def test_sample_models_pose_as_the_reference_does(model, times):
    path = shared_model(f"{model}/{model}.glb", SHARED_GLTF)
    ref = Reference(path)
    scene = facet.load(path)
    mesh_nodes = [i for i, n in enumerate(ref.g.nodes) if n.mesh is not None]
    for t in times:
        want = ref.positions(t)
        got = _facet_positions(scene, t)
        # facet's parts come in scene order, one per primitive: match by the vertex count
        # and the nearest reference (the first primitive of each mesh node).
        for node in mesh_nodes:
            w = want[node]
            candidates = [g for g in got if g.shape == w.shape]
            err = min(np.abs(g - w).max() for g in candidates)
            scale = np.abs(w).max()
            assert err < 1e-4 * max(scale, 1.0), (model, t, node, err)


@pytest.mark.parametrize("model, a, b", [("RiggedSimple", 0.0, 1.0),
                                         ("AnimatedMorphCube", 0.0, 1.0),
                                         ("RiggedFigure", 0.0, 0.5)])
def test_sample_models_are_drawn_moving(renderer, model, a, b):
    """At two times, from one camera (framed at the first), the pictures differ."""
    scene = facet.load(shared_model(f"{model}/{model}.glb", SHARED_GLTF))
    r = renderer(64, 64)
    cam = r.camera(scene, r.options(scene, time=a))
    first = r.render(scene, cam, time=a, outputs=("ids",)).object_ids
    second = r.render(scene, cam, time=b, outputs=("ids",)).object_ids
    assert (first >= 0).sum() > 200
    assert (first != second).sum() > 30

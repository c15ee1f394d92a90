"""Shadertoy JSON exports, TOML shader projects and batch manifests (and, fuzzed, glTF
variants and instancing, PCD and HDR headers) with wrong types anywhere: the named cases
through the command line (one line naming the key's path, exit 2), and hypothesis fuzzers
(fuzz_documents.py) mutating valid documents, each run in a child process under a memory
limit and a timeout, with a fixed example budget."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from hostile import MEMORY, ROOT, _limit, facet, refused

HERE = Path(__file__).resolve().parent
EXAMPLES = 300  # per fuzzer: a few seconds each on a 2-core machine


@pytest.mark.parametrize("kind", ["shadertoy", "project", "manifest", "gltf", "pcd", "hdr"])
def test_fuzzed_documents_read_cleanly_or_fail_in_one_line(kind):
    env = {**os.environ, "PYTHONPATH": f"{ROOT / 'app'}{os.pathsep}{HERE}"}
    run = subprocess.run([sys.executable, str(HERE / "fuzz_documents.py"), kind,
                          str(EXAMPLES)], env=env, capture_output=True, text=True,
                         timeout=300, preexec_fn=_limit)
    assert run.returncode == 0, (f"under {MEMORY >> 30} GiB", run.stdout[-3000:],
                                 run.stderr[-3000:])


FRAG = "void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }"


def _export(tmp_path, change):
    rp = [{"type": "buffer", "name": "Buffer A", "code": FRAG, "inputs": [],
           "outputs": [{"id": "4dXGR8", "channel": 0}]},
          {"type": "image", "name": "Image", "code": FRAG,
           "inputs": [{"id": "4dXGR8", "ctype": "buffer", "channel": 0}],
           "outputs": [{"id": "4dfGRr", "channel": 0}]}]
    change(rp)
    (tmp_path / "e.json").write_text(json.dumps({"Shader": {"renderpass": rp}}))
    return facet("shader", "e.json", "-o", "o.png", "--size", "8x8", cwd=tmp_path)


@pytest.mark.parametrize("change, where", [
    (lambda rp: rp[1]["inputs"][0].update(channel=7), "renderpass[1].inputs[0].channel"),
    (lambda rp: rp[1]["inputs"][0].update(channel=None), "renderpass[1].inputs[0].channel"),
    (lambda rp: rp[1]["inputs"][0].update(channel="zero"),
     "renderpass[1].inputs[0].channel"),
    (lambda rp: rp.__setitem__(0, "Buffer A"), "renderpass[0]: expected an object"),
    (lambda rp: rp[1].update(code=42), "renderpass[1].code: expected a string"),
    (lambda rp: rp[1]["inputs"][0].update(id="nobody"), "renderpass[1].inputs[0]: reads"),
    (lambda rp: rp[1]["inputs"][0].update(src="buffer09.png", id=None),
     "renderpass[1].inputs[0]"),
    (lambda rp: rp[1].update(inputs={"0": 1}), "renderpass[1].inputs: expected a list"),
    (lambda rp: rp[1]["inputs"][0].update(sampler={"filter": 3}), "sampler.filter"),
])
def test_shadertoy_exports_with_wrong_types(tmp_path, change, where):
    refused(_export(tmp_path, change), "e.json", where)
    assert not (tmp_path / "o.png").exists()


def test_a_shadertoy_export_still_runs(tmp_path):
    code, err = _export(tmp_path, lambda rp: rp[1]["inputs"][0].update(channel="0"))
    assert code == 0 and (tmp_path / "o.png").exists(), err


@pytest.mark.parametrize("text, where", [
    ('[image]\nshader = 5\n', "[image] shader: expected a string"),
    ('[image]\nshader = "s.frag"\nchannels = [1, 2]\n', "[image] channels: expected a table"),
    ('[image]\nshader = "s.frag"\nchannels = { 7 = "noise" }\n', "channels.7"),
    ('[image]\nshader = "s.frag"\nchannels = { "²" = "noise" }\n', "channels are 0 to 3"),
    ('[image]\nshader = "s.frag"\nchannels = { 0 = 3 }\n', "channels.0: expected a string"),
    ('[image]\nshader = "s.frag"\nchannels = { 0 = { source = "noise", vflip = "yes" } }\n',
     "channels.0.vflip"),
    ('common = ["a"]\n[image]\nshader = "s.frag"\n', "common: expected a string"),
    ('image = "s.frag"\n', "[image]"),
])
def test_toml_projects_with_wrong_types(tmp_path, text, where):
    (tmp_path / "s.frag").write_text(FRAG + "\n")
    (tmp_path / "p.toml").write_text(text)
    refused(facet("shader", "p.toml", "-o", "o.png", "--size", "8x8", cwd=tmp_path),
            "p.toml", where)

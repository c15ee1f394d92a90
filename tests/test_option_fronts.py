"""One door for render options, walked key by key (no GL): for every key of the parser
table (facet.options.values.PARSERS), the same value given through each front (Python
keywords, a scene file's [render] table, `facet render` flags, `facet view` flags, a
dataset manifest's job) resolves to the same RenderOptions, and the same bad value is
refused with the same sentence by each. Every front hands its raw values to the one parser;
none checks, defaults or parses again on its own."""

from __future__ import annotations

import json
import re
from dataclasses import replace

import pytest

from facet.errors import FacetError
from facet.formats.scenefile import load_scene
from facet.options.render import FRONT_DEFAULTS, RenderOptions, options_for
from facet.options.values import PARSERS, parse_option

# key -> (good value, its command-line text or None, bad value or None, bad text or None).
# A text of None: the command line has no flag for the key (the scene file, Python and
# manifests do), or the flag cannot carry a bad value (a boolean switch).
SAMPLES = {
    "size": ((64, 48), "64x48", [0, 10], "0x10"),
    "background": ((0.2, 0.3, 0.4), "0.2,0.3,0.4", [2, 0, 0], "2,0,0"),
    "shading": ("blinn", "blinn", "toon", "toon"),
    "aa": ("ssaa:grid:4", "ssaa:grid:4", "ssaa:grid:7", "ssaa:grid:7"),
    "msaa": (2, "2", 3, "3"),
    "spp": (9, "9", 0, "0"),
    "shadows": (True, True, "yes", None),
    "pcf": (2, "2", 5, "5"),
    "srgb": (True, True, "yes", None),
    "float_color": (True, None, "yes", None),
    "outputs": (("color", "depth"), "color,depth", ["color", "albedo"], "color,albedo"),
    "camera": ("side", "side", None, None),
    "aperture": (0.1, "0.1", -1.0, "-1"),
    "focus": (2.5, "2.5", 0.0, "0"),
    "environment": ("sky", "sky", 5, None),
    "lights": ("scene", "scene", "sun", "sun"),
    "wireframe": (True, True, 1, None),
    "time": (1.5, "1.5", "soon", "soon"),
    "animation": ("walk", "walk", -1, None),
    "variant": ("midnight", "midnight", 5, None),
    "shutter": (0.02, "0.02", -1.0, "-1"),
    "engine": ("trace", "trace", "photon", "photon"),
    "max_depth": (3, "3", 99, "99"),
    "seed": (7, "7", -1, "-1"),
    "up": ("-z", "-z", "w", "w"),
    "cull": ("off", "off", "maybe", "maybe"),
    "denoise": (True, True, "yes", None),
    "noise": (0.05, "0.05", 0, "0"),
    "time_limit": (2.5, "2.5", -1, "-1"),
}
FLAGS = {"max_depth": "--max-depth", "environment": "--env"}  # else --KEY
BOOLEAN_FLAGS = ("shadows", "srgb", "wireframe", "denoise")  # --KEY / --no-KEY
NOT_VIEWED = ("outputs",)  # a window shows colour: `facet view` has no --outputs
SCENE = """
[[objects]]
primitive = "sphere"
[cameras.side]
type = "perspective"
eye = [3, 0, 0]
target = [0, 0, 0]
"""


def test_every_key_has_samples():
    assert set(SAMPLES) == set(PARSERS)


def _toml(value) -> str:
    return json.dumps(list(value) if isinstance(value, tuple) else value)


def _argv(command, key, text, model, tmp_path) -> list[str]:
    if key in BOOLEAN_FLAGS:
        flags = [f"--{key}" if text else f"--no-{key}"]
    else:
        flags = [FLAGS.get(key, f"--{key.replace('_', '-')}"), text]
    if command == "render":
        flags += ["--out-dir", str(tmp_path / "out")] if key == "outputs" else \
            ["-o", str(tmp_path / "x.png")]
    return [command, str(model), *flags]


def _fronts(tmp_path, key, value, text):
    """{front: callable giving the RenderOptions of ``key = value`` through it}."""
    model = tmp_path / "model.toml"
    model.write_text(SCENE)
    scene = load_scene(model)

    def python():
        return options_for(scene, {key: value})

    def scene_file():
        path = tmp_path / "s.toml"
        path.write_text(f"[render]\n{key} = {_toml(value)}\n{SCENE}")
        return options_for(load_scene(path))

    def render_cli():
        from facet.cli import parse_args
        from facet.cli.render import resolve

        args, problem = parse_args(_argv("render", key, text, model, tmp_path))
        assert problem is None
        return resolve(args)[1]

    def view_cli():
        from facet.cli import parse_args
        from facet.cli.args import render_layer
        from facet.window.viewer import FRONT, explicit_layer

        args, problem = parse_args(_argv("view", key, text, model, tmp_path))
        assert problem is None
        return options_for(scene, explicit_layer(render_layer(args)), front=FRONT)

    def manifest():
        from facet.batch.manifest import FRONT, load_manifest

        path = tmp_path / "m.jsonl"
        path.write_text(json.dumps({"model": "model.toml", key: value}) + "\n")
        (job,) = load_manifest(path)
        return options_for(scene, job.options, front=FRONT)

    fronts = {"python": python, "scene file": scene_file, "manifest": manifest}
    if text is not None:
        fronts["render flags"] = render_cli
        if key not in NOT_VIEWED:
            fronts["view flags"] = view_cli
    return fronts


def _same(a: RenderOptions, b: RenderOptions, key: str) -> RenderOptions:
    """``b`` with what its front sets for itself (a window's or a dataset's size, the
    channels `facet render` writes) taken from ``a``, unless ``key`` is that option."""
    own = {name for layer in FRONT_DEFAULTS.values() for name in layer} | {"outputs"}
    return replace(b, **{name: getattr(a, name) for name in own if name != key})


@pytest.mark.parametrize("key", list(SAMPLES))
def test_a_value_means_the_same_through_every_front(tmp_path, key):
    value, text = SAMPLES[key][:2]
    fronts = _fronts(tmp_path, key, value, text)
    results = {name: front() for name, front in fronts.items()}
    python = results.pop("python")
    target = "aa" if key in ("msaa", "spp") else key
    assert getattr(python, target) != getattr(RenderOptions(), target) or key == "camera"
    for name, opts in results.items():
        if key == "environment":  # an Environment is made anew by each: compare the sky
            assert type(opts.environment) is type(python.environment), name
            opts = replace(opts, environment=python.environment)
        assert _same(python, opts, key) == python, name


def _sentence(key, value) -> str:
    """The parser's own sentence for a bad value, without a leading "key: "."""
    with pytest.raises(FacetError) as exc:
        parse_option(key, value)
    return re.sub(rf"^{key}: ", "", str(exc.value))


@pytest.mark.parametrize("key", [k for k, v in SAMPLES.items() if v[2] is not None])
def test_a_bad_value_gets_the_same_sentence_from_every_front(tmp_path, capsys, key):
    from facet.cli import main

    _, _, bad, bad_text = SAMPLES[key]
    sentence = _sentence(key, bad)
    for name, front in _fronts(tmp_path, key, bad, None).items():
        with pytest.raises(FacetError) as exc:
            front()
        assert sentence in str(exc.value), (name, str(exc.value))
    if bad_text is not None:
        sentence = _sentence(key, _text_value(key, bad_text))
        for command in ("render", "view")[:1 if key in NOT_VIEWED else 2]:
            argv = _argv(command, key, bad_text, tmp_path / "model.toml", tmp_path)
            assert main(argv) == 2
            err = capsys.readouterr().err.strip()
            assert err.startswith("facet: error: ") and sentence in err, (command, err)
            assert len(err.splitlines()) == 1
            assert not (tmp_path / "x.png").exists()


def _text_value(key, text):
    from facet.options.values import text_value

    return text_value(key, text)


def test_parsed_values_are_not_parsed_again(tmp_path):
    """A job's msaa / spp (parsed into an AntiAliasing) renders as given; a scene's
    options are kept parsed (the report: "msaa must be one of 0, 2, 4, 8, got
    AntiAliasing(...)")."""
    from facet.batch.manifest import FRONT, load_manifest

    (tmp_path / "model.toml").write_text(SCENE)
    path = tmp_path / "m.jsonl"
    path.write_text("\n".join(json.dumps({"model": "model.toml", **kw})
                              for kw in ({"msaa": 2}, {"spp": 4}, {"aa": "none"})))
    scene = load_scene(tmp_path / "model.toml")
    got = [str(options_for(scene, job.options, front=FRONT).aa)
           for job in load_manifest(path)]
    assert got == ["msaa:2", "ssaa:jittered:4", "none"]

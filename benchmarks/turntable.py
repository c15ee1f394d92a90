"""Turntable benchmark: a 36-frame orbit of the bunny at 512x512 with colour, depth and ids
written to disk (the `facet render --turntable --out-dir` path), next to rendering alone,
and next to the same path with a writer that writes nothing (what handing frames over to
the writer process costs); with the writer's own CPU time per frame.

    python benchmarks/turntable.py
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parents[1] / "shared" / "models"
FRAMES, SIZE = 36, 512
ROUNDS = 3  # best of


def _hand_over_only(frame, *args) -> list:
    """The writer's job with the writing left out (runs in the writer process)."""
    return []


def _writing_alone(frame, out_dir, outputs) -> float:
    """CPU seconds one frame's files take to write, in this process."""
    from facet.image.outputs import ColorOptions, write_outputs

    t = time.process_time()
    write_outputs(frame, out_dir, outputs, ColorOptions(), prefix="alone_")
    return time.process_time() - t


def main() -> None:
    import facet
    import facet.cli.sequence as sequence_module
    from facet.image.outputs import ColorOptions
    from facet.render.renderer import Renderer
    from facet.render.turntable import orbit_cameras

    path = SHARED / "stanford-bunny.obj"
    if not path.is_file():
        print(f"\nTurntable: skipped ({path} not found)")
        return
    scene = facet.Scene()
    scene.add(facet.Mesh.load(path))
    camera = facet.Camera.frame(scene.bounds)
    outputs = ("color", "depth", "ids")
    with Renderer(SIZE, SIZE, msaa=4) as r:
        cams = orbit_cameras(camera, scene.bounds.mean(axis=0), FRAMES)
        opts = r.options(scene, outputs=outputs)  # the default lights follow the camera
        r.render(scene, camera, opts).settle()  # warm-up: programs, uploads

        def sequence(out_dir) -> tuple[float, list]:
            args = argparse.Namespace(turntable=FRAMES, up=(0.0, 1.0, 0.0), fps=30.0,
                                      out_dir=out_dir, quiet=True, png16=False,
                                      normals_space="world")
            t = time.perf_counter()
            written = sequence_module.render_turntable(r, scene, camera, opts, args, None,
                                                       ColorOptions())
            return time.perf_counter() - t, written

        render_only, with_files, handed_over, writing = [], [], [], []
        for _ in range(ROUNDS):  # alternate, so drift in machine load hits all alike
            t = time.perf_counter()
            for cam in cams:  # every output made and read back (under MSAA the exact
                r.render(scene, cam, opts).settle()  # channels are drawn when read)
            render_only.append(time.perf_counter() - t)
            with tempfile.TemporaryDirectory() as tmp:
                seconds, written = sequence(tmp)
                with_files.append(seconds)
                size_mb = sum(p.stat().st_size for p in written) / 2**20
                frame = r.render(scene, camera, opts)
                frame.settle()
                writing.append(_writing_alone(frame, tmp, outputs))
                real = sequence_module._write_frame
                sequence_module._write_frame = _hand_over_only
                try:
                    handed_over.append(sequence(tmp)[0])
                finally:
                    sequence_module._write_frame = real
        render_only, with_files = min(render_only), min(with_files)
        handed_over, writing = min(handed_over), min(writing)
    print(f"\nTurntable: bunny (69k faces), {FRAMES} frames, {SIZE}x{SIZE}, 4x MSAA, "
          f"colour + depth + ids (best of {ROUNDS}, alternating)")
    print(f"{'':>28} | {'s':>6} {'fps':>6}")
    print(f"{'render only':>28} | {render_only:6.2f} {FRAMES / render_only:6.1f}")
    print(f"{'render + files written':>28} | {with_files:6.2f} {FRAMES / with_files:6.1f}"
          f"   ({len(written)} files, {size_mb:.1f} MiB; ratio "
          f"{render_only / with_files:.2f} of render-only fps)")
    print(f"{'render + hand-over only':>28} | {handed_over:6.2f} {FRAMES / handed_over:6.1f}"
          f"   (the writer writes nothing; ratio {render_only / handed_over:.2f})")
    print(f"writing one frame's files: {writing * 1000:.1f} ms of CPU, on the cores the "
          f"renderer uses ({render_only / FRAMES * 1000:.0f} ms a frame)")


if __name__ == "__main__":
    sys.exit(main())

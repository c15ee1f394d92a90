"""``facet render --turntable N``: render an orbit and write it while rendering goes on.

Frames go to a ``BackgroundWriter``: a GIF/MP4/PNG sequence with ``-o``, or every channel
of every frame into ``--out-dir`` (``0000_color.png``, ``0000_depth.npy``, ...,
``0000_camera.json``). A progress bar shows on a terminal unless ``--quiet``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .image.outputs import encode_color, write_outputs
from .image.sequence import BackgroundWriter, ProcessWriter, SequenceSink
from .render.turntable import orbit_cameras
from .scene.light import camera_rig


def progress(total: int, quiet: bool, desc: str):
    """A tqdm bar on stderr; silent with --quiet or when stderr is not a terminal."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="frame", file=sys.stderr, leave=False,
                disable=quiet or not sys.stderr.isatty())


def render_turntable(renderer, scene, camera, args, channels, target, color_options,
                     outputs, headlights: bool = False, aa: str | None = None) -> list[Path]:
    """Render the orbit; ``headlights``: the default light rig follows the camera (the model
    turns under studio lights) instead of staying in world space."""
    cameras = orbit_cameras(camera, scene.bounds.mean(axis=0), args.turntable, args.up)
    # Videos stream into one encoder object, so they use a thread; independent dataset
    # files go to a writer process (see ProcessWriter for why).
    writer = ProcessWriter() if args.out_dir else BackgroundWriter()
    sink = None if args.out_dir else SequenceSink(target, args.fps, writer)
    options = dict(png16=args.png16, normals_space=args.normals_space)
    try:
        with progress(len(cameras), args.quiet, "turntable") as bar:
            for i, cam in enumerate(cameras):
                if headlights:
                    scene.lights = camera_rig(cam.view)
                frame = renderer.render(scene, cam, outputs=outputs, aa=aa)
                if sink is not None:
                    kind, image = encode_color(frame.color, color_options)
                    sink.add(i, image)
                else:
                    writer.submit(_write_frame, frame, args.out_dir, channels, color_options,
                                  options, f"{i:04d}_")
                bar.update(1)
        if sink is not None:
            written = sink.finish()
        writer.close()
    except BaseException:
        try:
            writer.close()
        except Exception:
            pass
        if sink is not None:
            sink.abort()
        raise
    if sink is None:
        return [p for paths in writer.results for p in paths]
    return sink.written if sink.kind == "pattern" else written


def _write_frame(frame, out_dir, channels, color_options, options, prefix) -> list[Path]:
    """One frame's dataset files (runs in the writer process)."""
    return write_outputs(frame, out_dir, channels, color_options, prefix=prefix, **options)

"""``facet render --turntable N``: render an orbit and write it while rendering goes on.

Frames go to a writer: a GIF/MP4/PNG sequence with ``-o`` (encoded on a thread, with one
JSON of every frame's camera beside it), or every channel of every frame into ``--out-dir``
(``0000_color.png``, ``0000_depth.npy``, ..., ``0000_camera.json``; written by a separate
process). A progress bar shows on a terminal unless ``--quiet``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..image.outputs import encode_color, write_camera_json, write_outputs
from ..image.sequence import BackgroundWriter, ProcessWriter, SequenceSink, cameras_path
from ..image.writers import FLOAT_FORMATS
from ..render.turntable import animation_times, play, turntable


def progress(total: int, quiet: bool, desc: str):
    """A tqdm bar on stderr; silent with --quiet or when stderr is not a terminal."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="frame", file=sys.stderr, leave=False,
                disable=quiet or not sys.stderr.isatty())


def render_turntable(renderer, scene, camera, opts, args, target,
                     color_options, span=None) -> list[Path]:
    """Render the orbit about ``opts.up`` with the options ``opts`` (the default light rig,
    if it is used, follows the camera: the model turns under studio lights), and/or the
    animations playing over ``span`` (start, end) seconds: over the orbit's frames, else
    at ``args.fps`` (``camera`` None: the scene's camera, following its node)."""
    # Videos stream into one encoder object, so they use a thread; independent dataset
    # files go to a writer process (see ProcessWriter for why).
    writer = ProcessWriter() if args.out_dir else BackgroundWriter()
    sink = None if args.out_dir else SequenceSink(target, args.fps, writer,
                                                  getattr(args, "quality", None))
    floats = sink is not None and sink.kind == "pattern" and \
        Path(str(target).format(0)).suffix.lower() in FLOAT_FORMATS
    options = dict(png16=args.png16, normals_space=args.normals_space)
    cameras = []
    times = None if span is None else animation_times(*span, fps=args.fps,
                                                       frames=args.turntable)
    total = args.turntable or len(times)
    try:
        with progress(total, args.quiet, "turntable" if args.turntable else "animation") \
                as bar:
            frames = turntable(renderer, scene, args.turntable, camera, opts.up, opts,
                               times=times) if args.turntable else \
                play(renderer, scene, [camera] * total, times, opts)
            for i, frame in enumerate(frames):
                cameras.append(frame.camera_info())
                if sink is not None:  # float patterns (.exr, .hdr) keep linear colour
                    sink.add(i, frame.color if floats else
                             encode_color(frame.color, color_options)[1])
                else:
                    frame.settle()  # read back here: the writer process pickles it
                    writer.submit(_write_frame, frame, args.out_dir, opts.outputs,
                                  color_options, options, f"{i:04d}_")
                bar.update(1)
        if sink is not None:
            written = sink.finish()
        writer.close()
    except BaseException:
        try:
            writer.abort() if isinstance(writer, ProcessWriter) else writer.close()
        except Exception:
            pass
        if sink is not None:
            sink.abort()
        raise
    if sink is None:
        return [p for paths in writer.results for p in paths]
    json_path = write_camera_json(cameras_path(target), {"frames": cameras})
    return [*(sink.written if sink.kind == "pattern" else written), json_path]


def _write_frame(frame, out_dir, channels, color_options, options, prefix) -> list[Path]:
    """One frame's dataset files (runs in the writer process)."""
    return write_outputs(frame, out_dir, channels, color_options, prefix=prefix, **options)

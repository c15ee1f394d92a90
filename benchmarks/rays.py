"""The rays' benchmark set in one run: the tracer against Embree (benchmarks/raytrace.py:
primary and shadow rays, the hierarchy's build, a frame traced against rasterized), the
path tracer against Mitsuba 3 (benchmarks/pathtrace.py: equal-time efficiency, the
default call, the sample rate) and path-traced datasets against Blender's Cycles
(benchmarks/batch.py). The same tables as ``make bench``'s, headed by the GL that ran
them; on a GPU machine benchmarks/device.sh runs this.

    python benchmarks/rays.py [--quick] [--blender PYTHON]

Prints tables; asserts nothing.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--blender", default=os.environ.get("FACET_BPY_PYTHON"))
    a = ap.parse_args()

    import pathtrace
    from facet.render.renderer import Renderer

    import batch
    import raytrace

    with Renderer(8, 8) as r:
        info = r.info
        print(f"GL: {info['renderer']} ({info['version']}, {info['backend']}); "
              f"{os.cpu_count()} CPU cores")
    raytrace.table(a.quick)
    raytrace.frame(a.quick)
    pathtrace.main(a.quick)
    batch.path_table(2 if a.quick else 10, a.blender)


if __name__ == "__main__":
    main()

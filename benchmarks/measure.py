"""Run one command and print its wall time (s) and peak resident memory (KiB).

    python benchmarks/measure.py CMD [ARGS...]

A separate small launcher, because a child's peak RSS counts the memory it inherited at fork:
forked straight from the benchmark process (hundreds of MiB of meshes and contexts), every
command would report the parent's size instead of its own.
"""

import resource
import subprocess
import sys
import time

start = time.perf_counter()
code = subprocess.call(sys.argv[1:], stdout=subprocess.DEVNULL)
wall = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
print(f"{wall:.6f} {peak}")
sys.exit(code)

#!/bin/sh
# The rays' benchmark set (benchmarks/rays.py) on a machine with a GPU: one lent by the
# `device` tool (an NVIDIA H100 or H200 that reaches no network), or any other.
#
#   benchmarks/device.sh [--quick]
#
# It runs from the repository's root with the Python it finds: .venv/bin/python when the
# checkout has one, else python3 with the packages of .whl/ installed under /tmp/site (no
# network there: download them here first, docs/performance.md "On a GPU" says how), and
# facet from app/; GL's loader packages in .gl/, when there, are unpacked first (the
# `device` tool's notes say how to download them). Where NVIDIA's EGL vendor file is
# installed, EGL is pointed at it, so facet's context is the GPU's and not a software one;
# the tables' first line names the GL that ran them. Mitsuba runs its scalar_rgb variant, then llvm_ad_rgb (its vectorised
# CPU variant, which crashes on the 2-core development machine) where that one loads.
set -eu
cd "$(dirname "$0")/.."
if [ -x .venv/bin/python ]; then
    PY=.venv/bin/python
else
    PY=python3
    if [ -d .whl ]; then
        "$PY" -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
            --target /tmp/site .whl/*.whl
        PYTHONPATH=/tmp/site
    fi
    PYTHONPATH="$PWD/app${PYTHONPATH:+:$PYTHONPATH}"
    export PYTHONPATH
fi
if [ -d .gl ]; then  # GL's loaders where the machine lacks them (libEGL, libglvnd)
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [ -f "$vendor" ] && [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ]; then
    export __EGL_VENDOR_LIBRARY_FILENAMES="$vendor"
fi
command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L || true
export PYTHONUNBUFFERED=1
"$PY" benchmarks/rays.py "$@"
# (a render, not just the variant: on some CPUs LLVM aborts while compiling the kernel)
probe="import mitsuba as mi; mi.set_variant('llvm_ad_rgb'); mi.render(mi.load_dict(mi.cornell_box()), spp=1)"
if "$PY" -c "$probe" >/dev/null 2>&1; then
    echo
    echo "Mitsuba's llvm_ad_rgb variant (its vectorised CPU renderer):"
    FACET_MITSUBA_VARIANT=llvm_ad_rgb "$PY" -c \
        "import sys; sys.path[:0] = ['benchmarks', 'tests']; import pathtrace; pathtrace.main('--quick' in sys.argv)" "$@" \
        || echo "(Mitsuba's llvm_ad_rgb stopped: its tables above are incomplete)"
else
    echo "(Mitsuba's llvm_ad_rgb does not render on this machine: its tables are left out)"
fi

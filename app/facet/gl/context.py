"""OpenGL contexts: a headless one through EGL (Mesa llvmpipe when there is no GPU), or
through OSMesa on machines without EGL.

``create_headless()`` either returns a core-profile context of at least GL 3.3 or raises one
``ContextError`` that says what was tried and what to install. The backend comes from its
``backend`` argument or the environment variable ``FACET_GL_BACKEND``: ``auto`` (the
default: EGL, and OSMesa with a one-line warning when EGL cannot make a context), ``egl`` or
``osmesa``; an EGL device asked for by number never falls back to the CPU. Which one was
used is kept in ``ctx.extra["backend"]`` and printed by ``facet info``. On a machine
without a GPU both rasterise with llvmpipe, so they draw the same pixels.

``with ctx:`` makes a context current for a block, and leaving the block releases it (no
context is current afterwards, whatever was current before: glcontext's EGL backend does
not restore). So facet never nests ``with ctx:`` blocks: a nested one would leave the outer
block's GL calls without a context, silently doing nothing. Public methods that enter the
context (``Renderer.render``, ``ShaderToy.render``) must not be called inside one.

WebGL's semantics for what people paste: WebGL (hence Shadertoy) zero-initialises every
variable a shader declares without a value, desktop GL leaves it undefined (Mesa: garbage,
and a pasted ``vec3 color; color += ...`` renders black). Mesa's driconf option
``glsl_zero_init`` does what WebGL does; facet turns it on for the process before its first
context (``MESA_DEBUG=silent`` keeps Mesa from announcing the override on stderr), unless
the environment already sets either. Other drivers keep their own behaviour.
"""

from __future__ import annotations

import os
import warnings

import moderngl

from ..errors import ContextError, FacetWarning, InputError

GL_REQUIRED = 330
BACKENDS = ("auto", "egl", "osmesa")
if "glsl_zero_init" not in os.environ:  # read by Mesa when a context's screen is made
    os.environ["glsl_zero_init"] = "true"
    os.environ.setdefault("MESA_DEBUG", "silent")
INSTALL_HINT = ("install Mesa's EGL and software rasteriser: "
                "sudo apt-get install libegl1 libgl1-mesa-dri")


def create_headless(require: int = GL_REQUIRED, device: int | None = None,
                    backend: str | None = None) -> moderngl.Context:
    """A standalone (no window) OpenGL context; ``device``: the EGL device index (one GPU of
    several; None: the default); ``backend``: auto / egl / osmesa (None: $FACET_GL_BACKEND,
    else auto)."""
    backend = _backend_name(backend)
    version = f"{require // 100}.{require % 100 // 10}"
    if backend == "osmesa":
        return _osmesa(require, version)
    try:
        ctx = _egl(require, device)
    except Exception as exc:  # glcontext raises bare Exceptions with terse EGL messages
        detail = " ".join(str(exc).split()) or type(exc).__name__
        from . import osmesa

        if device is not None:  # a GPU asked for by number: never a CPU in its place
            raise ContextError(f"cannot create an OpenGL {version} context on EGL device "
                               f"{device} ({detail}); list the devices with nvidia-smi or "
                               "leave the device out") from None
        if backend == "auto" and osmesa.library() is not None:
            warnings.warn(f"no EGL context ({detail}); rendering through OSMesa on the CPU",
                          FacetWarning, stacklevel=2)
            return _osmesa(require, version)
        fallback = (f"; or, without EGL, {osmesa.INSTALL_HINT}" if backend == "auto" else "")
        raise ContextError(f"cannot create a headless OpenGL {version} context through EGL "
                           f"({detail}); {INSTALL_HINT}{fallback}") from None
    ctx.extra = {"backend": "egl"}
    return ctx


def _backend_name(backend: str | None) -> str:
    name = (backend or os.environ.get("FACET_GL_BACKEND") or "auto").strip().lower()
    if name not in BACKENDS:
        where = "backend" if backend else "FACET_GL_BACKEND"
        raise InputError(f"{where}: unknown OpenGL backend {name!r}; use one of "
                         f"{', '.join(BACKENDS)}")
    return name


def _egl(require: int, device: int | None) -> moderngl.Context:
    kwargs = {} if device is None else {"device_index": int(device)}
    return moderngl.create_context(standalone=True, backend="egl", require=require, **kwargs)


def _osmesa(require: int, version: str) -> moderngl.Context:
    from . import osmesa

    if osmesa.library() is None:
        raise ContextError(f"cannot create a headless OpenGL {version} context through OSMesa"
                           f" (libOSMesa not found); {osmesa.INSTALL_HINT}")
    try:
        ctx = osmesa.create(require)
    except Exception as exc:
        detail = " ".join(str(exc).split()) or type(exc).__name__
        raise ContextError(f"cannot create a headless OpenGL {version} context through OSMesa"
                           f" ({detail}); {osmesa.INSTALL_HINT}") from None
    ctx.extra = {"backend": "osmesa"}
    return ctx


def describe(ctx: moderngl.Context) -> dict[str, object]:
    """Vendor, renderer, version and the limits that matter for facet."""
    info = ctx.info
    made = ctx.extra if isinstance(ctx.extra, dict) else {}  # set by create_headless
    return {
        "backend": made.get("backend", "external"),
        "vendor": info.get("GL_VENDOR"),
        "renderer": info.get("GL_RENDERER"),
        "version": info.get("GL_VERSION"),
        "max_texture_size": info.get("GL_MAX_TEXTURE_SIZE"),
        "max_renderbuffer_size": info.get("GL_MAX_RENDERBUFFER_SIZE"),
        "max_viewport_dims": info.get("GL_MAX_VIEWPORT_DIMS"),
        "max_samples": ctx.max_samples,
        "max_color_attachments": info.get("GL_MAX_COLOR_ATTACHMENTS"),
    }


def max_image_size(ctx: moderngl.Context) -> int:
    """The largest width or height a render target may have on this context."""
    info = ctx.info
    dims = info.get("GL_MAX_VIEWPORT_DIMS") or (1 << 30, 1 << 30)
    return int(min(info.get("GL_MAX_TEXTURE_SIZE", 1 << 30),
                   info.get("GL_MAX_RENDERBUFFER_SIZE", 1 << 30), *dims))


def create_for_current_window(require: int = GL_REQUIRED) -> moderngl.Context:
    """A moderngl context over the window context that is current (facet.window.base makes it)."""
    try:
        return moderngl.create_context(require=require)
    except Exception as exc:
        detail = " ".join(str(exc).split()) or type(exc).__name__
        raise ContextError(f"the window has no usable OpenGL {require // 100}."
                           f"{require % 100 // 10} core context ({detail})") from None

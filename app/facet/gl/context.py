"""OpenGL contexts: a headless one through EGL (Mesa llvmpipe when there is no GPU).

``create_headless()`` either returns a core-profile context of at least GL 3.3 or raises one
``ContextError`` that says what was tried and what to install.

``with ctx:`` makes a context current for a block, and leaving the block releases it (no
context is current afterwards, whatever was current before: glcontext's EGL backend does
not restore). So facet never nests ``with ctx:`` blocks: a nested one would leave the outer
block's GL calls without a context, silently doing nothing. Public methods that enter the
context (``Renderer.render``, ``ShaderToy.render``) must not be called inside one.
"""

from __future__ import annotations

import moderngl

from ..errors import ContextError

GL_REQUIRED = 330
INSTALL_HINT = ("install Mesa's EGL and software rasteriser: "
                "sudo apt-get install libegl1 libgl1-mesa-dri")


def create_headless(require: int = GL_REQUIRED, device: int | None = None) -> moderngl.Context:
    """A standalone (no window) OpenGL context through EGL; ``device``: the EGL device
    index (one GPU of several; None: the default)."""
    kwargs = {} if device is None else {"device_index": int(device)}
    try:
        ctx = moderngl.create_context(standalone=True, backend="egl", require=require,
                                      **kwargs)
    except Exception as exc:  # glcontext raises bare Exceptions with terse EGL messages
        detail = " ".join(str(exc).split()) or type(exc).__name__
        raise ContextError(f"cannot create a headless OpenGL {require // 100}.{require % 100 // 10}"
                           f" context through EGL ({detail}); {INSTALL_HINT}") from None
    return ctx


def describe(ctx: moderngl.Context) -> dict[str, object]:
    """Vendor, renderer, version and the limits that matter for facet."""
    info = ctx.info
    return {
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

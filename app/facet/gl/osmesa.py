"""A headless OpenGL context through Mesa's OSMesa, for machines without EGL.

glcontext (moderngl's context layer) has EGL and X11 backends but none for OSMesa, so this
module is one: ``OSMesaContext`` has the four methods moderngl asks of a backend
(``load_opengl_function``, ``__enter__``, ``__exit__``, ``release``), over libOSMesa through
ctypes. OSMesa renders with the same llvmpipe rasteriser as Mesa's EGL, so images are the
same; it is CPU only (no device index). Mesa dropped OSMesa in 25.1: distributions up to
then ship it (Debian/Ubuntu ``libosmesa6``).

facet renders into its own framebuffers, so the buffer OSMesa must be made current with is
a single pixel that nothing reads.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import threading

import moderngl

LIBRARIES = ("libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so")
INSTALL_HINT = "sudo apt-get install libosmesa6"

# from GL/osmesa.h
OSMESA_RGBA = 0x1908
GL_UNSIGNED_BYTE = 0x1401
OSMESA_FORMAT = 0x22
OSMESA_DEPTH_BITS = 0x30
OSMESA_STENCIL_BITS = 0x31
OSMESA_PROFILE = 0x33
OSMESA_CORE_PROFILE = 0x34
OSMESA_CONTEXT_MAJOR_VERSION = 0x36
OSMESA_CONTEXT_MINOR_VERSION = 0x37

_lib = None
_swap = threading.Lock()  # glcontext.get_backend_by_name is swapped while a context is made


def library():
    """libOSMesa loaded with its prototypes, or None when it is not installed."""
    global _lib
    if _lib is None:
        names = [*LIBRARIES, ctypes.util.find_library("OSMesa")]
        for name in filter(None, names):
            try:
                lib = ctypes.CDLL(name)
                break
            except OSError:
                continue
        else:
            return None
        lib.OSMesaCreateContextAttribs.restype = ctypes.c_void_p
        lib.OSMesaCreateContextAttribs.argtypes = [ctypes.POINTER(ctypes.c_int), ctypes.c_void_p]
        lib.OSMesaMakeCurrent.restype = ctypes.c_ubyte
        lib.OSMesaMakeCurrent.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint,
                                          ctypes.c_int, ctypes.c_int]
        lib.OSMesaGetProcAddress.restype = ctypes.c_void_p
        lib.OSMesaGetProcAddress.argtypes = [ctypes.c_char_p]
        lib.OSMesaDestroyContext.restype = None
        lib.OSMesaDestroyContext.argtypes = [ctypes.c_void_p]
        _lib = lib
    return _lib


class OSMesaContext:
    """One core-profile OSMesa context, current on the creating thread once made."""

    def __init__(self, glversion: int = 330):
        self.lib = library()
        if self.lib is None:
            raise RuntimeError(f"libOSMesa not found ({INSTALL_HINT})")
        attrs = (ctypes.c_int * 13)(
            OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
            OSMESA_CONTEXT_MAJOR_VERSION, glversion // 100,
            OSMESA_CONTEXT_MINOR_VERSION, glversion % 100 // 10, 0)
        self.handle = self.lib.OSMesaCreateContextAttribs(attrs, None)
        if not self.handle:
            raise RuntimeError(f"OSMesa has no OpenGL {glversion // 100}."
                               f"{glversion % 100 // 10} core profile")
        self.pixel = (ctypes.c_ubyte * 4)()
        self.__enter__()

    def load_opengl_function(self, name: str) -> int:
        return self.lib.OSMesaGetProcAddress(name.encode()) or 0

    def __enter__(self):
        if not self.lib.OSMesaMakeCurrent(self.handle, self.pixel, GL_UNSIGNED_BYTE, 1, 1):
            raise RuntimeError("OSMesaMakeCurrent failed")

    def __exit__(self, *exc):
        self.lib.OSMesaMakeCurrent(None, None, 0, 0, 0)  # none current, as with EGL

    def release(self):
        if self.handle:
            self.__exit__()
            self.lib.OSMesaDestroyContext(self.handle)
            self.handle = None


def create(require: int) -> moderngl.Context:
    """A standalone moderngl context over OSMesa. moderngl finds backends through
    ``glcontext.get_backend_by_name``; this one is offered there only while it is made."""
    import glcontext

    def backend(name: str):
        if name != "osmesa":
            return known(name)
        return lambda *args, **kwargs: OSMesaContext(kwargs.get("glversion", require))

    with _swap:
        known = glcontext.get_backend_by_name
        glcontext.get_backend_by_name = backend
        try:
            return moderngl.create_context(standalone=True, backend="osmesa", require=require)
        finally:
            glcontext.get_backend_by_name = known

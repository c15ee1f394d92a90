"""GPU copies of scene data, cached per renderer and keyed by the scene objects themselves.

A mesh is uploaded once (one call per buffer: interleaved float32 position+normal, uint32
indices, and uvs / vertex colours when it has them); a vertex array is made once per (mesh,
program); a texture once per colour mode. Entries whose mesh or texture was garbage
collected are released on the next ``sweep()``; ``release()`` frees everything.
"""

from __future__ import annotations

import warnings
import weakref

import moderngl
import numpy as np

from ..scene.mesh import Mesh
from ..scene.texture import Texture


class MeshBuffers:
    """The vertex and index buffers of one mesh, and its vertex arrays per program."""

    def __init__(self, ctx: moderngl.Context, mesh: Mesh):
        interleaved = np.hstack([mesh.positions, mesh.normals]).astype(np.float32, copy=False)
        self.vbo = ctx.buffer(interleaved)  # (N, 6) float32: position xyz, normal xyz
        self.ibo = ctx.buffer(mesh.faces)  # (F, 3) uint32
        # Optional per-vertex attributes, one buffer each: attribute -> (buffer, format).
        self.extra: dict[str, tuple[moderngl.Buffer, str]] = {}
        if mesh.uvs is not None:
            self.extra["in_uv"] = (ctx.buffer(mesh.uvs), "2f")
        if getattr(mesh, "uvs1", None) is not None:
            self.extra["in_uv1"] = (ctx.buffer(mesh.uvs1), "2f")
        self.mesh = weakref.ref(mesh)  # tangents are uploaded when a program first wants them
        colors = getattr(mesh, "colors", None)
        if colors is not None:
            self.extra["in_color"] = (ctx.buffer(colors), "4f")
        self.index_count = mesh.faces.size
        self.vaos: dict[int, moderngl.VertexArray] = {}
        # Instanced draws (facet.render.raster.instancing): one per-instance buffer, grown
        # as batches need, and a vertex array per program binding it.
        self.instances: moderngl.Buffer | None = None
        self.instanced_vaos: dict[int, moderngl.VertexArray] = {}
        self.morph: moderngl.Texture | None = None  # morph targets (add_morph)

    def vao(self, ctx: moderngl.Context, program: moderngl.Program) -> moderngl.VertexArray:
        """The vertex array binding this mesh to ``program``'s active attributes; attributes
        the mesh lacks keep GL's default value (0, 0, 0, 1)."""
        key = program.glo
        found = self.vaos.get(key)
        if found is not None:  # (asked for on every draw)
            return found
        self.vaos[key] = ctx.vertex_array(program, self._content(ctx, program),
                                          index_buffer=self.ibo, index_element_size=4)
        return self.vaos[key]

    def _content(self, ctx: moderngl.Context, program: moderngl.Program) -> list:
        """The per-vertex buffers ``program`` reads (tangents uploaded when first wanted)."""
        if "in_tangent" in program and "in_tangent" not in self.extra:
            mesh = self.mesh()
            if mesh is not None and mesh.tangents is not None:
                self.extra["in_tangent"] = (ctx.buffer(mesh.tangents), "4f")
        names = [n for n in ("in_position", "in_normal") if n in program]
        fmt = "3f 3f" if names == ["in_position", "in_normal"] else "3f 3x4"
        content = [(self.vbo, fmt, *names)]
        return content + [(buf, f, name) for name, (buf, f) in self.extra.items()
                          if name in program]

    def add_skin(self, ctx: moderngl.Context, skin) -> None:
        """The joints (as 16-bit integers) and weights of a skinned mesh (facet.scene
        .skinned), uploaded once, for programs that skin (glsl/lib/skin.glsl)."""
        if "in_joints0" in self.extra:
            return
        joints = np.zeros((len(skin.joints), 8), np.uint16)
        weights = np.zeros((len(skin.joints), 8), np.float32)
        k = skin.joints.shape[1]
        joints[:, :k], weights[:, :k] = skin.joints, skin.weights
        for half in (0, 1):
            part = slice(4 * half, 4 * half + 4)
            self.extra[f"in_joints{half}"] = (ctx.buffer(np.ascontiguousarray(
                joints[:, part])), "4u2")
            self.extra[f"in_weights{half}"] = (ctx.buffer(np.ascontiguousarray(
                weights[:, part])), "4f")

    def add_morph(self, ctx: moderngl.Context, skin, width: int) -> None:
        """The morph targets of a morphed mesh as an RGBA32F texture ``width`` texels a
        row: texel 3 (t N + v) target t's position displacement of vertex v, the next its
        normal's and its tangent's (glsl/lib/morph.glsl); uploaded once."""
        if self.morph is not None:
            return
        first = next(iter(skin.targets.values()))
        count, n = first.shape[:2]
        texels = np.zeros((count, n, 3, 4), np.float32)
        for k, name in enumerate(("positions", "normals", "tangents")):
            if name in skin.targets:
                texels[:, :, k, :3] = skin.targets[name]
        flat = texels.reshape(-1, 4)
        rows = -(-len(flat) // width)
        padded = np.zeros((rows * width, 4), np.float32)
        padded[:len(flat)] = flat
        self.morph = ctx.texture((width, rows), 4, padded.tobytes(), dtype="f4")
        self.morph.filter = (moderngl.NEAREST, moderngl.NEAREST)

    def draw_instances(self, ctx: moderngl.Context, program: moderngl.Program,
                       rows: np.ndarray, layout: tuple) -> None:
        """Draw the mesh once per row of ``rows`` (N, K) float32 with ``program``;
        ``layout``: the rows' (format, *attribute names) (per instance: "/i")."""
        if self.instances is None:
            self.instances = ctx.buffer(reserve=max(rows.nbytes, 4096))
        elif self.instances.size < rows.nbytes:
            self.instances.orphan(rows.nbytes * 2)  # the same buffer: vertex arrays hold
        self.instances.write(rows)
        vao = self.instanced_vaos.get(program.glo)
        if vao is None:
            # Attributes the program does not read (optimised away) are skipped bytes.
            fmt, *names = layout
            pieces, kept = fmt.split()[:-1], [n for n in names if n in program]
            fmt = " ".join(p if n in program else f"{p[:-1]}x4"
                           for p, n in zip(pieces, names, strict=True)) + " /i"
            content = [*self._content(ctx, program), (self.instances, fmt, *kept)]
            vao = self.instanced_vaos[program.glo] = ctx.vertex_array(
                program, content, index_buffer=self.ibo, index_element_size=4)
        vao.render(instances=len(rows))

    def release(self) -> None:
        for vao in (*self.vaos.values(), *self.instanced_vaos.values()):
            vao.release()
        self.vaos.clear()
        self.instanced_vaos.clear()
        if self.instances is not None:
            self.instances.release()
            self.instances = None
        if self.morph is not None:
            self.morph.release()
            self.morph = None
        for buf, _ in self.extra.values():
            buf.release()
        self.vbo.release()
        self.ibo.release()


class SpriteBuffers:
    """A point cloud's or line set's per-instance buffers, drawn as one quad per point or
    segment (glsl/mesh/sprite.vert): a point's position (3 floats), its normal and colour
    (4 bytes) where it has them, 16 bytes a coloured point; a segment's two ends and two
    colours in one row."""

    def __init__(self, ctx: moderngl.Context, sprites):
        p = sprites.positions
        colors = None if sprites.colors is None else \
            np.round(np.asarray(sprites.colors) * 255.0).astype(np.uint8)
        # attribute -> (buffer, format); absent ones keep GL's default (0, 0, 0, 1).
        self.buffers: list[tuple[moderngl.Buffer, str, tuple[str, ...]]] = []
        self.kind = sprites.kind
        if sprites.kind == "points":
            self.buffers.append((ctx.buffer(p), "3f", ("in_position",)))
            if sprites.normals is not None:
                self.buffers.append((ctx.buffer(sprites.normals), "3f", ("in_normal",)))
            if colors is not None:
                self.buffers.append((ctx.buffer(colors), "4f1", ("in_color",)))
            self.count = len(p)
        else:
            a, b = sprites.segments[:, 0], sprites.segments[:, 1]
            self.buffers.append((ctx.buffer(np.hstack([p[a], p[b]])), "3f 3f",
                                 ("in_p0", "in_p1")))
            if colors is not None:
                self.buffers.append((ctx.buffer(np.hstack([colors[a], colors[b]])),
                                     "4f1 4f1", ("in_c0", "in_c1")))
            self.count = len(sprites.segments)
        self.vaos: dict[int, moderngl.VertexArray] = {}
        self.instanced_vaos: dict[int, moderngl.VertexArray] = {}  # (none: forget_program)

    def draw_sprites(self, ctx: moderngl.Context, program: moderngl.Program) -> None:
        vao = self.vaos.get(program.glo)
        if vao is None:  # attributes the program does not read are skipped bytes
            content = []
            for buf, fmt, names in self.buffers:
                if not any(n in program for n in names):
                    continue
                pieces = fmt.split()
                skip = {"3f": "12x", "4f1": "4x"}
                fmt = " ".join(f if n in program else skip[f]
                               for f, n in zip(pieces, names, strict=True))
                fmt += "" if self.kind == "points" else " /i"  # lines: per instance
                content.append((buf, fmt, *[n for n in names if n in program]))
            vao = self.vaos[program.glo] = ctx.vertex_array(program, content)
        if self.kind == "points":  # GL points, gl_PointSize across
            ctx.enable(moderngl.PROGRAM_POINT_SIZE)
            vao.render(mode=moderngl.POINTS, vertices=self.count)
        else:
            vao.render(mode=moderngl.TRIANGLE_STRIP, vertices=4, instances=self.count)

    def release(self) -> None:
        for vao in self.vaos.values():
            vao.release()
        self.vaos.clear()
        for buf, _, _ in self.buffers:
            buf.release()


GL_SRGB8_ALPHA8 = 0x8C43


def upload_texture(ctx: moderngl.Context, texture: Texture, srgb: bool,
                   mipmaps: bool = True) -> moderngl.Texture:
    """A mipmapped, trilinear, repeating GL texture of ``texture`` (rows flipped: GL's first
    row is v = 0, the image's bottom). ``srgb``: decode sRGB to linear when sampling.
    ``mipmaps`` False: the base level only (for samplers that read no other: glTF's
    NEAREST / LINEAR minification). Images beyond the GL size limit are downscaled with a
    warning."""
    pixels = texture.pixels
    limit = int(ctx.info["GL_MAX_TEXTURE_SIZE"])
    w, h = texture.size
    if max(w, h) > limit:
        from PIL import Image

        scale = limit / max(w, h)
        size = (max(1, int(w * scale)), max(1, int(h * scale)))
        warnings.warn(f"texture {texture.name} is {w}x{h}, larger than this GL's limit of "
                      f"{limit}; downscaled to {size[0]}x{size[1]}", stacklevel=3)
        pixels = np.asarray(Image.fromarray(pixels).resize(size, Image.Resampling.LANCZOS))
    data = np.ascontiguousarray(pixels[::-1])
    tex = ctx.texture((data.shape[1], data.shape[0]), 4, data.tobytes(),
                      internal_format=GL_SRGB8_ALPHA8 if srgb else None)
    if mipmaps:
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    else:
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    tex.repeat_x = tex.repeat_y = True
    return tex


class ResourceCache:
    """Mesh -> MeshBuffers and Texture -> GL texture, weakly keyed so that dropped meshes and
    textures free their GPU memory."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._entries: dict[int, tuple[weakref.ref, MeshBuffers]] = {}
        self._textures: dict[tuple, tuple[weakref.ref, moderngl.Texture]] = {}
        self.uploads = 0  # meshes uploaded so far (tests check caching with it)
        # The tracers' texture layers (facet.render.rays.layers): CPU copies both ray
        # engines of one renderer share, kept while requested.
        self.ray_layers: dict = {}

    def texture(self, texture: Texture, srgb: bool, mipmaps: bool = True) -> moderngl.Texture:
        """The GL texture of ``texture`` (uploaded once per colour mode; with mip levels
        unless every sampler of it reads the base level only: ``mipmaps`` False)."""
        key = (id(texture), srgb) if mipmaps else (id(texture), srgb, "base")
        entry = self._textures.get(key)
        if entry is not None and entry[0]() is texture:
            return entry[1]
        if entry is not None:
            entry[1].release()
        tex = upload_texture(self.ctx, texture, srgb, mipmaps)
        self._textures[key] = (weakref.ref(texture), tex)
        return tex

    def buffers(self, mesh: Mesh) -> MeshBuffers:
        """The GPU copy of a mesh (or of points or lines: SpriteBuffers), made once."""
        entry = self._entries.get(id(mesh))
        if entry is not None and entry[0]() is mesh:
            return entry[1]
        if entry is not None:  # id reused by a new object: the old mesh is gone
            entry[1].release()
        bufs = MeshBuffers(self.ctx, mesh) if mesh.kind == "mesh" else \
            SpriteBuffers(self.ctx, mesh)
        self._entries[id(mesh)] = (weakref.ref(mesh), bufs)
        self.uploads += 1
        return bufs

    def cube(self, environment) -> moderngl.TextureCube:
        """The environment's cube map (float faces), mipmapped; cached like textures."""
        key = (id(environment), "cube")
        entry = self._textures.get(key)
        if entry is not None and entry[0]() is environment:
            return entry[1]
        if entry is not None:
            entry[1].release()
        s = environment.size
        tex = self.ctx.texture_cube((s, s), 3, environment.faces.astype("f4").tobytes(),
                                    dtype="f4")
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        self._textures[key] = (weakref.ref(environment), tex)
        return tex

    def sweep(self) -> None:
        """Release the GPU copies of meshes and textures that no longer exist."""
        for key in [k for k, (ref, _) in self._entries.items() if ref() is None]:
            self._entries.pop(key)[1].release()
        for key in [k for k, (ref, _) in self._textures.items() if ref() is None]:
            self._textures.pop(key)[1].release()

    def forget_program(self, program: moderngl.Program) -> None:
        for _, bufs in self._entries.values():
            for vaos in (bufs.vaos, bufs.instanced_vaos):
                vao = vaos.pop(program.glo, None)
                if vao is not None:
                    vao.release()

    def __len__(self) -> int:
        return len(self._entries)

    def release(self) -> None:
        for _, bufs in self._entries.values():
            bufs.release()
        self._entries.clear()
        for _, tex in self._textures.values():
            tex.release()
        self._textures.clear()
        self.ray_layers.clear()

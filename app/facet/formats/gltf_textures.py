"""A glTF file's materials and texture slots as facet's (PbrMaterial, TextureSlot): the
core material, the KHR extensions' fields (facet.formats.gltf_materials), each textureInfo's
image, coordinate set, KHR_texture_transform and sampler settings; the images decoded at
once in threads. A part of facet.formats.gltf's reader (``MaterialReading``)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..errors import FacetWarning
from ..guard import carried
from ..scene.pbr import PbrMaterial, TextureSlot, texture_transform
from .gltf_data import KTX2_EXTRA
from .gltf_materials import extension_fields

WRAP = {33071: "clamp", 33648: "mirror", 10497: "repeat"}
NEAREST = {9728, 9984, 9986}  # NEAREST, NEAREST_MIPMAP_*
NO_MIPS = {9728, 9729}

# glTF's texture coordinates have v = 0 at the image's top; facet's (OpenGL's) at its
# bottom: v' = 1 - v, as a matrix on (u, v, 1) for texture transforms (its own inverse).
FLIP_V = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 1.0], [0.0, 0.0, 1.0]])


def _flip_v(uv: np.ndarray) -> np.ndarray:
    return np.stack([uv[:, 0], 1.0 - uv[:, 1]], axis=1).astype(np.float32)


class MaterialReading:
    """The reader's materials and texture slots (its ``gltf``, ``document``, ``data``,
    ``materials``, ``textures`` and ``skipped``: facet.formats.gltf)."""

    def _decode_images(self) -> None:
        """Every image a texture uses, decoded at once in threads (Pillow decodes outside
        the GIL): a model's images cost about the longest one, not their sum. Warnings
        (a missing or broken image) are said in file order afterwards."""
        import os
        import warnings as w
        from concurrent.futures import ThreadPoolExecutor

        sources = []
        for t in self.document.get("textures") or []:
            source = self._source(t.get("extensions") or {}, t.get("source"))
            if isinstance(source, int) and source not in sources:
                sources.append(source)
        if len(sources) < 2:
            return

        workers = min(len(sources), os.cpu_count() or 1, 8)
        with ThreadPoolExecutor(workers, thread_name_prefix="facet-image") as pool:
            # Each decode runs with this thread's confinement (facet.guard.carried); its
            # warning is said here, in file order (warnings are not caught per thread).
            read = pool.map(carried(self.data.read_image), sources)
            for index, (image, why) in zip(sources, read, strict=True):
                self.textures[index] = image
                if why is not None:
                    w.warn(why, FacetWarning, stacklevel=4)

    def _source(self, ext: dict, source):
        """The image a texture reads: EXT_texture_webp's (Pillow decodes WebP), or
        KHR_texture_basisu's KTX2 where the ktx2 extra decodes it, else its own."""
        for name in ("EXT_texture_webp",) + (("KHR_texture_basisu",) if self.ktx2 else ()):
            if isinstance((ext.get(name) or {}).get("source"), int):
                return ext[name]["source"]
        return source

    def _material(self, index: int | None) -> PbrMaterial:
        if index is None:  # glTF's default material: white, metallic 1, roughness 1
            return self.materials.setdefault(-1, PbrMaterial(name="default"))
        if index not in self.materials:
            m = self.gltf.materials[index]
            pbr = m.pbrMetallicRoughness
            ext = m.extensions or {}
            strength = ext.get("KHR_materials_emissive_strength", {})
            kw = dict(
                base_color=np.clip(getattr(pbr, "baseColorFactor", None) or [1, 1, 1, 1],
                                   0, 1),
                metallic=1.0 if pbr is None or pbr.metallicFactor is None
                else float(np.clip(pbr.metallicFactor, 0, 1)),
                roughness=1.0 if pbr is None or pbr.roughnessFactor is None
                else float(np.clip(pbr.roughnessFactor, 0, 1)),
                emissive=np.clip(m.emissiveFactor or [0, 0, 0], 0, 1),
                emissive_strength=float(strength.get("emissiveStrength", 1.0)),
                alpha_mode=m.alphaMode or "OPAQUE",
                alpha_cutoff=0.5 if m.alphaCutoff is None else float(m.alphaCutoff),
                double_sided=bool(m.doubleSided), unlit="KHR_materials_unlit" in ext,
                name=m.name or f"material{index}",
                base_color_texture=self._slot(getattr(pbr, "baseColorTexture", None)),
                metallic_roughness_texture=self._slot(
                    getattr(pbr, "metallicRoughnessTexture", None)),
                normal_texture=self._slot(m.normalTexture),
                occlusion_texture=self._slot(m.occlusionTexture),
                emissive_texture=self._slot(m.emissiveTexture))
            if m.normalTexture is not None and m.normalTexture.scale is not None:
                kw["normal_scale"] = abs(float(m.normalTexture.scale))
            if m.occlusionTexture is not None and m.occlusionTexture.strength is not None:
                kw["occlusion_strength"] = float(np.clip(m.occlusionTexture.strength, 0, 1))
            kw.update(extension_fields(ext, kw["name"], self.data.fail, self._slot))
            self.materials[index] = PbrMaterial(**kw)
        return self.materials[index]

    def _slot(self, info) -> TextureSlot | None:
        """A TextureSlot of a textureInfo (None when absent or its image is missing); the
        extensions' come as dicts (checked as the core's: facet.formats.gltf_check)."""
        if isinstance(info, dict):
            info = SimpleNamespace(index=info.get("index"), texCoord=info.get("texCoord"),
                                   extensions=info.get("extensions"))
        if info is None or info.index is None:
            return None
        tex = self.gltf.textures[info.index]
        source = tex.source
        ext = self.document["textures"][info.index].get("extensions") or {}
        source = self._source(ext, source)
        if source is None:
            if isinstance(ext.get("KHR_texture_basisu"), dict):
                name = _texture_name(self.document["textures"][info.index],
                                     ext["KHR_texture_basisu"],
                                     self.document.get("images") or [], info.index)
                self.skipped.add(f"the KTX2 texture {name}, which has no PNG or JPEG "
                                 f"fallback (KHR_texture_basisu: {KTX2_EXTRA} decodes it; "
                                 "drawn without it)")
            return None
        if source not in self.textures:
            self.textures[source] = self.data.image(source)
        image = self.textures[source]
        if image is None:
            return None
        texcoord = info.texCoord or 0
        transform = np.eye(3)
        tt = (info.extensions or {}).get("KHR_texture_transform")
        if tt is not None:
            transform = texture_transform(tt.get("offset", (0, 0)), tt.get("rotation", 0.0),
                                          tt.get("scale", (1, 1)))
            texcoord = tt.get("texCoord", texcoord)
        wrap, filt, mips = ("repeat", "repeat"), ("linear", "linear"), True
        if tex.sampler is not None:
            s = self.gltf.samplers[tex.sampler]
            wrap = (WRAP.get(s.wrapS, "repeat"), WRAP.get(s.wrapT, "repeat"))
            filt = ("nearest" if s.minFilter in NEAREST else "linear",
                    "nearest" if s.magFilter == 9728 else "linear")
            mips = s.minFilter not in NO_MIPS
        # The transform is defined on glTF's uvs (v down); facet's are flipped (v up).
        transform = FLIP_V @ transform @ FLIP_V
        return TextureSlot(image, min(int(texcoord), 1), transform, wrap, filt, mips)


def _texture_name(texture: dict, ext: dict, images: list, index: int) -> str:
    """A KTX2 texture as a person finds it: its name, else its KTX2 image's file name."""
    source = ext.get("source")
    image = images[source] if isinstance(source, int) and 0 <= source < len(images) else {}
    name = texture.get("name") or (image.get("uri") if isinstance(image, dict) else None)
    return f"'{name}'" if name else f"texture {index}"

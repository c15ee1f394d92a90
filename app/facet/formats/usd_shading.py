"""UsdShade materials -> facet's one material record, PbrMaterial (no GL).

UsdPreviewSurface: diffuseColor (base colour), emissiveColor, metallic, roughness,
clearcoat, clearcoatRoughness, opacity with opacityThreshold (MASK above 0, BLEND below
1), ior, normal, occlusion, and the specular workflow (useSpecularWorkflow = 1: F0 is
specularColor, metallic 0). An input is a constant or a UsdUVTexture's output (rgb, r, g,
b, a): its file (read through facet.guard; a .usdz's member from the package), wrapS/T
(repeat, mirror, clamp; black as clamp, said), scale and bias (applied to the texels
where the record has no place for them), sourceColorSpace, its fallback when the file is
missing, and the st it reads (UsdPrimvarReader_float2's varname, through a
UsdTransform2d's rotation, scale and translation). A network facet cannot read (MaterialX,
another renderer's shader): its displayColor stands in, with one warning naming it.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..scene.pbr import PbrMaterial
from ..scene.texture import Texture
from ..scene.texture_slot import TextureSlot
from ..srgb import linear_to_srgb, srgb_to_linear

WRAPS = {"repeat": "repeat", "mirror": "mirror", "clamp": "clamp", "black": "clamp",
         "useMetadata": "repeat"}
CHANNELS = {"r": 0, "g": 1, "b": 2, "a": 3}
STANDARD_NORMAL = ((2.0, 2.0, 2.0), (-1.0, -1.0, -1.0))  # what facet's normal maps assume


class Shading:
    """Materials of one stage, each made once (by its prim path); ``subdivide``: the
    refinement level its subdivision meshes are read with (they are read with their
    materials, whose st primvar they need)."""

    def __init__(self, stage, time, notes: list, subdivide: int = 0):
        self.stage, self.time, self.notes = stage, time, notes
        self.subdivide = int(subdivide)
        self.made: dict[str, tuple[PbrMaterial, str]] = {}
        self.textures: dict[tuple, Texture] = {}
        self.fallbacks: dict[tuple, PbrMaterial] = {}  # (colour, alpha, double) -> one

    def fallback(self, rgb, alpha: float, double_sided: bool) -> PbrMaterial:
        """``fallback_material``, one per colour, opacity and sidedness of the stage (prims
        of one displayColor share it: less to make, and batched alike when drawn)."""
        key = (None if rgb is None else tuple(float(c) for c in rgb[:3]), float(alpha),
               bool(double_sided))
        if key not in self.fallbacks:
            self.fallbacks[key] = fallback_material(rgb, alpha, double_sided)
        return self.fallbacks[key]

    def material_of(self, prim) -> tuple[PbrMaterial | None, str]:
        """(the bound material or None, the primvar its textures read as st)."""
        from pxr import UsdShade

        bound = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0]
        if not bound:
            return None, "st"
        key = str(bound.GetPath())
        if key not in self.made:
            self.made[key] = self._material(bound, key)
        return self.made[key]

    def _material(self, material, key: str) -> tuple[PbrMaterial | None, str]:
        from pxr import UsdShade

        surface = material.ComputeSurfaceSource()[0]
        if not surface or surface.GetIdAttr().Get() != "UsdPreviewSurface":
            outputs = [o.GetBaseName() for o in material.GetOutputs()]
            what = (surface.GetIdAttr().Get() if surface else None) or \
                ", ".join(outputs) or "no surface"
            self.notes.append(f"material {key}: a {what} network facet cannot read; its "
                              "displayColor stands in")
            return None, "st"
        self.uv_name = "st"
        m = PbrMaterial(name=material.GetPrim().GetName(), metallic=0.0, roughness=0.5,
                        base_color=(0.18, 0.18, 0.18, 1.0))
        read = self._reader(UsdShade.Shader(surface), key)
        diffuse, diffuse_tex = read("diffuseColor", 3, srgb=True)
        opacity, opacity_tex = read("opacity", 1)
        specular_flow = bool(read("useSpecularWorkflow", 1)[0] or 0)
        if diffuse is not None:
            m.base_color = np.array([*np.asarray(diffuse, float)[:3], 1.0])
        if diffuse_tex is not None:
            m.base_color_texture = diffuse_tex
        if opacity is not None:
            m.base_color[3] = float(np.asarray(opacity).reshape(-1)[0])
        threshold = read("opacityThreshold", 1)[0]
        if opacity_tex is not None:
            self._alpha_into(m, opacity_tex)
        if threshold is not None and float(threshold) > 0:
            m.alpha_mode, m.alpha_cutoff = "MASK", float(threshold)
        elif m.base_color[3] < 1.0 or opacity_tex is not None:
            m.alpha_mode = "BLEND"
        emissive, emissive_tex = read("emissiveColor", 3, srgb=True)
        if emissive is not None:
            m.emissive = np.asarray(emissive, float)[:3]
        if emissive_tex is not None:
            m.emissive_texture, m.emissive = emissive_tex, np.ones(3)
        roughness, rough_tex = read("roughness", 1)
        metallic, metal_tex = read("metallic", 1)
        if roughness is not None:
            m.roughness = float(np.asarray(roughness).reshape(-1)[0])
        if not specular_flow and metallic is not None:
            m.metallic = float(np.asarray(metallic).reshape(-1)[0])
        if rough_tex is not None or (metal_tex is not None and not specular_flow):
            m.metallic_roughness_texture = self._packed(
                rough_tex, None if specular_flow else metal_tex)
            m.roughness = 1.0 if rough_tex is not None else m.roughness
            if metal_tex is not None and not specular_flow:
                m.metallic = 1.0
        if specular_flow:
            colour, colour_tex = read("specularColor", 3, srgb=True)
            f0 = np.asarray(colour if colour is not None else (0.0, 0.0, 0.0), float)[:3]
            m.metallic, m.ior = 0.0, 1.5
            m.specular_color = f0 / 0.04  # (KHR_materials_specular: F0 = 0.04 x colour)
            if colour_tex is not None:  # KHR_materials_specular's colour texture slot
                m.specular_color_texture = colour_tex
                m.specular_color = np.full(3, 1.0 / 0.04)
        normal, normal_tex = read("normal", 3, normal=True)
        if normal_tex is not None:
            m.normal_texture = normal_tex
        occlusion, occlusion_tex = read("occlusion", 1)
        if occlusion_tex is not None:
            m.occlusion_texture = occlusion_tex
        clearcoat = read("clearcoat", 1)[0]
        if clearcoat is not None:
            m.clearcoat = float(np.asarray(clearcoat).reshape(-1)[0])
        coat_rough = read("clearcoatRoughness", 1)[0]
        if coat_rough is not None:
            m.clearcoat_roughness = float(np.asarray(coat_rough).reshape(-1)[0])
        ior = read("ior", 1)[0]
        if ior is not None and not specular_flow:
            m.ior = max(float(np.asarray(ior).reshape(-1)[0]), 1.0)
        displacement = read("displacement", 1)
        if displacement[1] is not None or (displacement[0] not in (None, 0.0)):
            self.notes.append(f"material {key}: displacement is not drawn (facet does not "
                              "displace surfaces)")
        m.__post_init__()  # (the record's checks on what was set above)
        return m, self.uv_name

    # -- inputs ----------------------------------------------------------------------------
    def _reader(self, shader, key: str):
        """read(name, width, srgb=False, normal=False) -> (constant or None, TextureSlot or
        None) of one UsdPreviewSurface input."""
        from pxr import UsdShade

        def read(name: str, width: int, srgb: bool = False, normal: bool = False):
            inp = shader.GetInput(name)
            if not inp:
                return None, None
            source = inp.GetConnectedSource() if inp.HasConnectedSource() else None
            if source:
                upstream = UsdShade.Shader(source[0].GetPrim())
                out = source[1]
                if upstream.GetIdAttr().Get() == "UsdUVTexture":
                    return None, self._slot(upstream, out, width, srgb, normal, key, name)
                value = upstream.GetInput("fallback").Get() if upstream.GetInput(
                    "fallback") else None
                self.notes.append(f"material {key}: {name} comes from a "
                                  f"{upstream.GetIdAttr().Get()} node; facet reads "
                                  "UsdUVTexture outputs there")
                return value, None
            value = inp.Get(self.time)
            return (None if value is None else np.asarray(value, float)), None

        return read

    def _slot(self, tex_shader, output: str, width: int, srgb: bool, normal: bool,
              key: str, name: str) -> TextureSlot | None:
        path = tex_shader.GetInput("file").Get(self.time) if tex_shader.GetInput(
            "file") else None
        scale = np.array(_value(tex_shader, "scale", (1, 1, 1, 1)), float)
        bias = np.array(_value(tex_shader, "bias", (0, 0, 0, 0)), float)
        space = _value(tex_shader, "sourceColorSpace", "auto")
        pixels = self._pixels(path, key, name)
        if pixels is None:
            fallback = _value(tex_shader, "fallback", (0, 0, 0, 1))
            self.notes.append(f"material {key}: {name}'s texture "
                              f"{getattr(path, 'path', path) or '(none)'} cannot be read; "
                              f"its fallback {tuple(round(v, 3) for v in fallback)} is used")
            return None
        channel = output.lower()
        img = pixels.astype(np.float64) / 255.0
        linear_file = space == "raw" or (space == "auto" and not srgb)
        # scale and bias apply to the values as read (linear when the file is sRGB).
        if normal:
            if not (np.allclose(scale[:3], STANDARD_NORMAL[0]) and
                    np.allclose(bias[:3], STANDARD_NORMAL[1])):
                n = img[..., :3] * scale[:3] + bias[:3]
                img[..., :3] = np.clip((n + 1.0) / 2.0, 0, 1)
        elif not (np.allclose(scale, 1) and np.allclose(bias, 0)):
            values = img if linear_file else np.concatenate(
                [srgb_to_linear(img[..., :3]), img[..., 3:]], axis=-1)
            values = np.clip(values * scale + bias, 0, 1)
            img = values if linear_file else np.concatenate(
                [linear_to_srgb(values[..., :3]), values[..., 3:]], axis=-1)
        if channel in CHANNELS and width == 1:
            c = img[..., CHANNELS[channel]]
            img = np.stack([c, c, c, np.ones_like(c)], axis=-1)  # R, G, B alike
        elif srgb and space == "raw":  # linear colour in the file: the record wants sRGB
            img = np.concatenate([linear_to_srgb(img[..., :3]), img[..., 3:]], axis=-1)
        texture = Texture((np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8),
                          name=f"{Path(str(getattr(path, 'path', path))).name}")
        wrap = (WRAPS.get(_value(tex_shader, "wrapS", "useMetadata"), "repeat"),
                WRAPS.get(_value(tex_shader, "wrapT", "useMetadata"), "repeat"))
        if "black" in (_value(tex_shader, "wrapS", ""), _value(tex_shader, "wrapT", "")):
            self.notes.append(f"material {key}: wrap mode black is drawn as clamp")
        transform = self._st_transform(tex_shader)
        return TextureSlot(texture, 0, transform, wrap)

    def _st_transform(self, tex_shader) -> np.ndarray:
        """The (3, 3) matrix on (s, t, 1) of the UsdTransform2d between the texture and
        its st reader (identity without); remembers the reader's primvar name."""
        from pxr import UsdShade

        st = tex_shader.GetInput("st")
        if not st or not st.HasConnectedSource():
            return np.eye(3)
        node = UsdShade.Shader(st.GetConnectedSource()[0].GetPrim())
        m = np.eye(3)
        if node.GetIdAttr().Get() == "UsdTransform2d":
            r = np.radians(float(_value(node, "rotation", 0.0)))
            s = np.array(_value(node, "scale", (1.0, 1.0)), float)
            t = np.array(_value(node, "translation", (0.0, 0.0)), float)
            c, n = np.cos(r), np.sin(r)
            m = np.array([[c, -n, t[0]], [n, c, t[1]], [0, 0, 1]]) @ np.diag([s[0], s[1], 1])
            inner = node.GetInput("in")
            if not inner or not inner.HasConnectedSource():
                return m
            node = UsdShade.Shader(inner.GetConnectedSource()[0].GetPrim())
        if node.GetIdAttr().Get() == "UsdPrimvarReader_float2":
            self.uv_name = str(_value(node, "varname", "st") or "st")
        return m

    def _pixels(self, path, key: str, name: str) -> np.ndarray | None:
        """(H, W, 4) uint8 texels of an asset path (None when it cannot be read)."""
        from ..errors import FacetError
        from ..guard import open_image, package_member

        resolved = getattr(path, "resolvedPath", "") or ""
        if not resolved:
            return None
        if resolved not in self.textures:
            try:
                if "[" in resolved:  # a member of a .usdz
                    outer, _, member = resolved.partition("[")
                    data = package_member(outer, member.rstrip("]"), "texture")
                    image = open_image(io.BytesIO(data), resolved)
                    texture = Texture.from_pil(image, Path(member).name)
                else:
                    texture = Texture.load(resolved)
            except FacetError:
                return None
            self.textures[resolved] = texture
        return np.asarray(self.textures[resolved].pixels)

    def _packed(self, rough: TextureSlot | None, metal: TextureSlot | None) -> TextureSlot:
        """One metallic-roughness slot (G roughness, B metallic) of two one-channel slots
        (their images must agree in size: else the roughness one's size, resampled)."""
        from PIL import Image

        base = rough or metal
        assert base is not None
        h, w = base.texture.pixels.shape[:2]

        def channel(slot):
            if slot is None:
                return np.full((h, w), 255, np.uint8)
            px = slot.texture.pixels[..., 0]
            if px.shape != (h, w):
                px = np.asarray(Image.fromarray(px).resize((w, h), Image.BILINEAR))
            return px

        g, b = channel(rough), channel(metal)
        packed = np.stack([np.zeros_like(g), g, b, np.full_like(g, 255)], axis=-1)
        return TextureSlot(Texture(packed, "metallic-roughness"), base.texcoord,
                           base.transform, base.wrap)

    def _alpha_into(self, m: PbrMaterial, opacity: TextureSlot) -> None:
        """An opacity texture as the base colour texture's alpha (a white one without)."""
        a = opacity.texture.pixels[..., 0]
        if m.base_color_texture is None:
            rgb = np.full(a.shape + (3,), 255, np.uint8)
            m.base_color_texture = TextureSlot(Texture(np.dstack([rgb, a]), "opacity"),
                                               opacity.texcoord, opacity.transform,
                                               opacity.wrap)
            return
        px = np.array(m.base_color_texture.texture.pixels)
        if px.shape[:2] == a.shape:
            px[..., 3] = a
            m.base_color_texture.texture = Texture(px, m.base_color_texture.texture.name)
        else:
            self.notes.append(f"material {m.name}: opacity and diffuse textures differ in "
                              "size; the diffuse texture's alpha is used")


def _value(shader, name: str, default):
    inp = shader.GetInput(name)
    value = inp.Get() if inp else None
    return default if value is None else value


def fallback_material(rgb, alpha: float, double_sided: bool) -> PbrMaterial:
    """What a prim without a material readable by facet draws with: its displayColor as
    UsdPreviewSurface's diffuse colour (Hydra's fallback 0.5 grey without), roughness 0.5,
    dielectric."""
    colour = (0.5, 0.5, 0.5) if rgb is None else tuple(float(c) for c in rgb[:3])
    m = PbrMaterial(base_color=(*colour, float(alpha)), metallic=0.0, roughness=0.5,
                    double_sided=double_sided, alpha_mode="BLEND" if alpha < 1 else "OPAQUE")
    return m

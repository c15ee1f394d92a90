"""A glTF file's KHR_materials_variants: the file's variant names and each primitive's
{variant: material} mappings, every type checked with the key path before use. A part of
facet.formats.gltf's reader (``VariantReading``; it uses the reader's ``document``,
``data`` and ``_material``)."""

from __future__ import annotations


class VariantReading:
    """The reader's material variants (see the module docstring)."""

    def _variants(self, prim: dict, where: str) -> dict | None:
        """{variant name: PbrMaterial} of a primitive's KHR_materials_variants mappings."""
        ext = (prim.get("extensions") or {}).get("KHR_materials_variants")
        if not isinstance(ext, dict):
            if ext is not None:
                self.data.fail(f"{where}: KHR_materials_variants: expected an object with "
                               f"mappings, got {type(ext).__name__}")
            return None
        mappings = ext.get("mappings")
        if not mappings:
            return None
        if not isinstance(mappings, list):
            self.data.fail(f"{where}: KHR_materials_variants.mappings: expected a list, got "
                           f"{type(mappings).__name__}")
        names = self._variant_names()
        out = {}
        n_materials = len(self.document.get("materials") or [])
        for k, m in enumerate(mappings):
            at = f"{where}: KHR_materials_variants.mappings[{k}]"
            material = m.get("material") if isinstance(m, dict) else None
            if isinstance(material, bool) or not isinstance(material, int) or \
                    not 0 <= material < n_materials:
                self.data.fail(f"{at}.material: expected an index into the file's "
                               f"{n_materials} materials, got {material!r}")
            listed = m.get("variants") or []
            if not isinstance(listed, list):
                self.data.fail(f"{at}.variants: expected a list of variant indices, got "
                               f"{listed!r}")
            for v in listed:
                if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < len(names):
                    self.data.fail(f"{at}.variants: {v!r} is not one of the file's "
                                   f"{len(names)} variants")
                out[names[v]] = self._material(material)
        return {name: out[name] for name in names if name in out}  # the file's order

    def _variant_names(self) -> list[str]:
        """The names of the file's KHR_materials_variants.variants (each an object with a
        text name), checked with the key path."""
        ext = (self.document.get("extensions") or {}).get("KHR_materials_variants") or {}
        at = "extensions.KHR_materials_variants"
        if not isinstance(ext, dict):
            self.data.fail(f"{at}: expected an object with variants, got "
                           f"{type(ext).__name__}")
        variants = ext.get("variants") or []
        if not isinstance(variants, list):
            self.data.fail(f"{at}.variants: expected a list of {{\"name\": ...}} objects, "
                           f"got {type(variants).__name__}")
        names = []
        for k, v in enumerate(variants):
            name = v.get("name") if isinstance(v, dict) else None
            if not isinstance(v, dict) or not isinstance(name, (str, type(None))):
                self.data.fail(f"{at}.variants[{k}]: expected {{\"name\": TEXT}}, got "
                               f"{str(v)[:80]}")
            names.append(name or f"variant{k}")
        return names

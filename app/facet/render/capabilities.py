"""What each engine honours, declared once (no GL): its defaults for the options a user
leaves unset, the options it cannot honour when they are given, and the material features
it leaves out or draws otherwise.

Options keep "not given" (None) until the engine decides (``decided``): the rasterizer draws
shadow maps only when asked, the tracers cast shadow rays unless told not to; ``max_depth``
is the Whitted tracer's recursion depth (5) and the path tracer's bounces (8) when not given,
and the rasterizer takes none. The path tracer lights only by what a scene declares: the
ambient term a scene leaves at its default lights the rasterizer and the Whitted tracer
(the notes' I_a = 0.1), not the path tracer (``implied_ambient``). An engine's
``unsupported`` lines (facet.render.engine) are made from its row here, so a feature the
table says an engine leaves out is always named in a warning line, and the differential
tests read the same table.

Material features have the names glTF and facet's docs give them (``material_features``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace


@dataclass(frozen=True)
class OptionLimit:
    """An option an engine does not honour as given: ``given(opts)`` on the options before
    the engine decided them; ``line`` the warning."""

    given: object  # (RenderOptions) -> bool
    line: str


@dataclass(frozen=True)
class Capabilities:
    """One engine's row of the table (module docstring)."""

    noun: str  # how warnings name it: "the rasterizer"
    shadows: bool  # shadows when the options do not say
    max_depth: int | None  # recursion depth or bounces when not given; None: takes none
    # lights by the notes' ambient term (0.1) when the scene declares none; False: by what
    # the scene declares only (a physically based engine: no light no one wrote)
    implied_ambient: bool = True
    options: tuple[OptionLimit, ...] = ()
    # material feature -> what the engine draws instead (absent: honoured)
    leaves_out: dict[str, str] = field(default_factory=dict)
    # material feature -> how the engine finds what it stands for itself (honoured without
    # drawing it: no warning, and no picture change expected when it is taken away)
    computes: dict[str, str] = field(default_factory=dict)
    draws_splats: bool = False  # Gaussian splats (facet.scene.splats): the rasterizer's
    # the samples a still view (a window, the widget, the page) refines to when the options
    # name no sample count (no spp); None: the options' own (their aa). Shown as it refines,
    # a view costs nothing more to wait for, and stops at the first change of the view.
    view_samples: int | None = None

    def decided(self, opts):
        """``opts`` with what was not given decided by this engine."""
        return replace(opts, shadows=self.shadows if opts.shadows is None else opts.shadows,
                       max_depth=self.max_depth if opts.max_depth is None else opts.max_depth,
                       pcf=1 if opts.pcf is None else opts.pcf)

    def option_lines(self, opts) -> list[str]:
        return [limit.line for limit in self.options if limit.given(opts)]

    def feature_lines(self, scene) -> list[str]:
        """One line per feature of the scene's materials this engine leaves out, with how
        many objects use it."""
        counts: dict[str, int] = {}
        for obj in scene.objects:
            for feature in material_features(obj.material) + _object_features(obj):
                if feature in self.leaves_out:
                    counts[feature] = counts.get(feature, 0) + 1
        total = len(scene.objects)
        lines = [f"{self.noun} ignores {feature} ({n} of {total} objects): "
                 f"{self.leaves_out[feature]}" for feature, n in counts.items()]
        clouds = [c for c in getattr(scene, "splats", ()) if c.splats.count]
        if clouds and not self.draws_splats:
            n = sum(c.splats.count for c in clouds)
            lines.append(f"{self.noun} leaves out the Gaussian splats ({len(clouds)} "
                         f"cloud{'s' if len(clouds) > 1 else ''}, {n:,} splats): the "
                         "rasterizer draws them (engine = raster)")
        return lines


def material_features(m) -> list[str]:
    """The features a material uses, by the names of glTF (and facet's Phong material)."""
    out = ["users' mesh shaders"] if m.shader is not None else []
    if not hasattr(m, "metallic"):  # a Phong Material (its module needs numpy: --help)
        return out + [name for name, used in (
            ("Phong reflectivity", m.reflectivity > 0), ("Phong ior", m.ior > 0),
            ("Phong gloss", m.gloss > 0 and m.reflectivity > 0),
            ("planar mirrors", m.mirror)) if used]
    return out + [name for name, used in (
        ("baseColorTexture", m.base_color_texture is not None),
        ("metallicRoughnessTexture", m.metallic_roughness_texture is not None),
        ("normalTexture", m.normal_texture is not None),
        ("occlusionTexture", m.occlusion_texture is not None),
        ("emissiveTexture", m.emissive_texture is not None),
        ("alphaMode MASK", m.alpha_mode == "MASK"),
        ("alphaMode BLEND", m.alpha_mode == "BLEND"),
        ("KHR_materials_unlit", m.unlit),
        ("KHR_materials_ior", m.ior != 1.5),
        ("KHR_materials_specular", m.specular != 1.0 or any(m.specular_color != 1.0) or
         m.specular_texture is not None or m.specular_color_texture is not None),
        ("KHR_materials_transmission", m.transmission > 0),
        ("KHR_materials_transmission in BLEND materials",
         m.transmission > 0 and m.alpha_mode == "BLEND"),
        ("KHR_materials_volume", m.transmission > 0 and m.thickness > 0),
        ("thicknessTexture", m.thickness_texture is not None),
        ("KHR_materials_clearcoat", m.clearcoat > 0),
        ("clearcoatNormalTexture", m.clearcoat > 0 and m.clearcoat_normal_texture is not None),
        ("KHR_materials_sheen", bool(any(m.sheen_color > 0))),
        ("KHR_materials_iridescence", m.iridescence > 0),
        ("KHR_materials_anisotropy", m.anisotropy > 0),
        ("KHR_materials_diffuse_transmission", m.diffuse_transmission > 0),
        ("KHR_materials_dispersion", m.dispersion > 0 and m.transmission > 0),
        ("KHR_materials_emissive_strength", m.emissive_strength != 1.0)) if used]


NO_FRAME = "KHR_materials_anisotropy on a mesh without uvs or tangents"
# (every engine: the lobe is stretched along the tangent frame the uvs or tangents give)
_NO_FRAME_LINE = "no tangent frame to stretch the lobe along: drawn isotropic"


def _object_features(obj) -> list[str]:
    """Features an object's material asks of its geometry that the geometry lacks."""
    mesh, m = obj.mesh, obj.material
    if getattr(m, "anisotropy", 0.0) > 0 and obj.shape is None and \
            getattr(mesh, "kind", "mesh") == "mesh" and mesh.uvs is None and \
            getattr(mesh, "_tangents", None) is None:
        return [NO_FRAME]
    return []


VIEW_PATHS = 1024  # paths per pixel a still view of the path tracer refines to (no spp)


def _given(key: str):
    return lambda opts: getattr(opts, key) is not None


_EXACT_SHADOWS = OptionLimit(_given("pcf"), "pcf filters shadow maps; {noun}'s shadow rays are "
                             "exact")
_NO_WIREFRAME = OptionLimit(lambda o: o.wireframe, "{noun} draws no wireframe overlay")
_NO_NOISE = OptionLimit(_given("noise"), "noise is the path tracer's adaptive sampling; "
                        "{noun} takes every sample in every pixel")
_NO_CULL = OptionLimit(lambda o: o.cull == "on", "{noun} culls no back faces for cull = on "
                       "(only single-sided glTF materials lose theirs)")


def _row(noun: str, shadows: bool, max_depth, options=(), leaves_out=None,
         implied_ambient: bool = True, computes=None, splats: bool = False,
         view_samples: int | None = None) -> Capabilities:
    limits = tuple(OptionLimit(o.given, o.line.format(noun=noun)) for o in options)
    return Capabilities(noun, shadows, max_depth, implied_ambient, limits,
                        {NO_FRAME: _NO_FRAME_LINE, **(leaves_out or {})}, computes or {},
                        splats, view_samples)


CAPABILITIES: dict[str, Capabilities] = {
    "raster": _row("the rasterizer", False, None, (
        OptionLimit(_given("max_depth"), "max_depth sets the tracers' recursion and bounces; "
                    "the rasterizer ignores it"), _NO_NOISE), {
        "KHR_materials_transmission in BLEND materials":
            "the transparent pass draws its diffuse part"}, splats=True),
    "trace": _row("the ray tracer", True, 5, (
        _NO_WIREFRAME, _NO_CULL, _EXACT_SHADOWS, _NO_NOISE,
        OptionLimit(lambda o: o.shading == "gouraud",
                    "the ray tracer shades gouraud as phong (per pixel)")), {
        "users' mesh shaders": "the material's Phong terms are traced",
        "KHR_materials_dispersion": "each refraction ray bends at the material's ior (the "
                                    "path tracer and the rasterizer spread it over the "
                                    "colours)"}),
    "path": _row("the path tracer", True, 8, (
        _NO_WIREFRAME, _NO_CULL, _EXACT_SHADOWS,
        OptionLimit(lambda o: o.shadows is False,
                    "the path tracer always traces shadows (shadows = off ignored)"),
        OptionLimit(lambda o: o.shading not in ("auto", "pbr", "phong"),
                    "the path tracer shades by the metallic-roughness model, not the "
                    "shading option's model")), {
        "users' mesh shaders": "traced by the material's metallic-roughness mapping",
        "Phong reflectivity": "mirrors are traced as the metallic-roughness mapping of the "
                              "Phong terms",
        "Phong ior": "refraction is traced as a transparent surface that does not bend "
                     "light"}, implied_ambient=False,
        # (as Mitsuba and Cycles: the texture stands for the occlusion of indirect light,
        # which the bounces find; no baked occlusion is drawn over it)
        computes={"occlusionTexture": "its bounces find the occlusion of indirect light"},
        # (a 4-path picture keeps its fireflies; Blender's viewport refines to 1024 too)
        view_samples=VIEW_PATHS),
}


def decided(opts):
    """``opts`` with what was not given decided by the engine they name.

    Parameters
    ----------
    opts : RenderOptions
        Options as resolved from their layers.

    Returns
    -------
    RenderOptions
        ``shadows``, ``max_depth`` and ``pcf`` set.
    """
    return CAPABILITIES[opts.engine].decided(opts)


def view_sampling(opts):
    """The options a still view refines by (a window, the widget, the page): ``opts`` with
    the engine's own view count (its row's ``view_samples``) when they name no sample
    count (no spp: ``aa`` is msaa or none); with ``noise`` given, as many samples as a
    render takes (facet.geometry.sampling.MAX_SAMPLES), the view stopping once its noise is
    below it.

    Parameters
    ----------
    opts : RenderOptions
        The view's options, resolved.

    Returns
    -------
    RenderOptions
        ``opts``, or ``opts`` with ``aa`` jittered supersampling of that count.
    """
    n = CAPABILITIES[opts.engine].view_samples
    if n is None or opts.aa.kind == "ssaa":
        return opts
    from ..geometry.sampling import MAX_SAMPLES
    from ..options.values import AntiAliasing

    count = MAX_SAMPLES if opts.noise is not None else n
    return replace(opts, aa=AntiAliasing("ssaa", count, "jittered"))

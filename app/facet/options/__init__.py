"""Render options (no GL): every knob of a render parsed and merged in one place
(facet.options.render: RenderOptions and the layers' precedence; facet.options.values: one
parser per key and the vocabularies). "Not given" stays None until an engine decides
(facet.render.capabilities)."""

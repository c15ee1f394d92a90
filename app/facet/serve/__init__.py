"""The viewer in a browser page for machines without a display: ``facet view --serve``
(facet.serve.server; the ``serve`` extra: websockets)."""

"""The interactive viewer without a window system: its scene, options, camera control, keys,
clock and the picture it draws (``facet.viewing.core.ViewerCore``), shared by the glfw window
(facet.window), the notebook widget (facet.notebook) and the served browser page
(facet.serve). ``facet.viewing.session.Session`` is the headless one they render through."""

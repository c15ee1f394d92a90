"""The windows: the only package that imports glfw (the viewer, the live shader window)."""

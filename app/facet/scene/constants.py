"""Numbers the scene model and the render options share, in a module that imports nothing
(the command line's --help reads them without loading numpy)."""

# Files without normals: vertices split where faces meet at more than this many degrees
# (facet.scene.normals; 180: all smooth); the loaders' default and the crease option's.
DEFAULT_CREASE = 60.0

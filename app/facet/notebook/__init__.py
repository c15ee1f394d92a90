"""The viewer in a Jupyter notebook: ``facet.show`` and its widget (facet.notebook.widget,
on jupyter_rfb: the ``notebook`` extra)."""

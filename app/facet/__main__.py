"""``python -m facet`` runs the command-line interface."""

from facet.cli import main

if __name__ == "__main__":  # not when a writer process re-imports this module
    raise SystemExit(main())

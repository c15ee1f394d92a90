"""``python -m facet`` runs the command-line interface."""

from facet.cli import main

raise SystemExit(main())

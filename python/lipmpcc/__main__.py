"""``python -m lipmpcc``: the command-line interface (:mod:`lipmpcc.cli`)."""

from .cli import main

__all__: list[str] = []

raise SystemExit(main())

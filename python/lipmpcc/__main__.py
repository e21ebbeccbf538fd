"""``python -m lipmpcc``: the command-line interface (:mod:`lipmpcc.cli`, through :mod:`lipmpcc._entry`)."""

from ._entry import main

__all__: list[str] = []

main()

"""A progress bar over the steps of a reduced-model loop (the full-body loop counts simulated seconds,
:mod:`lipmpcc.loops.fullbody.loop`)."""

from __future__ import annotations

from contextlib import contextmanager
from typing import Any, Iterator

__all__ = ["step_bar"]


class _NoBar:
    """What :func:`step_bar` yields when no bar is shown: ``update`` does nothing."""

    n = 0

    def update(self, n: int = 1) -> None:
        pass


@contextmanager
def step_bar(total: int, desc: str, show: bool | None = None) -> Iterator[Any]:
    """A tqdm bar over ``total`` steps on stderr, closed on the way out; call ``update(1)`` per step.

    Args:
        total: the steps the run may take.
        desc: the bar's label (``"LIP"``, ``"ALIP"``).
        show: True always, None only on a terminal (a log file or a test gets nothing), False never.
    """
    if show is False:
        yield _NoBar()
        return
    from tqdm import tqdm

    bar = tqdm(total=int(total), unit="step", desc=desc, leave=False, disable=None if show is None else not show)
    try:
        yield bar
    finally:
        bar.close()

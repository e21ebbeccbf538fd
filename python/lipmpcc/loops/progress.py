"""A progress bar over the steps of a reduced-model loop (the full-body loop counts simulated seconds,
:mod:`lipmpcc.loops.fullbody.loop`)."""

from __future__ import annotations

import sys
import time
from contextlib import contextmanager
from typing import Any, Callable, Iterator, TextIO

__all__ = ["step_bar", "PROGRESS_LINE_S", "LineProgress", "line_progress", "progress_lines"]

#: off a terminal (``lipmpcc run`` in a script, a notebook, a log), a progress line this often [s of wall time]
PROGRESS_LINE_S = 30.0
_LINES = [False]  # progress lines on (inside ``with progress_lines():``)


@contextmanager
def progress_lines(on: bool = True) -> Iterator[None]:
    """Within the block, a run whose stderr is not a terminal prints a progress line every
    :data:`PROGRESS_LINE_S` (``lipmpcc run``: a script cannot tell a long run from a hang otherwise)."""
    before = _LINES[0]
    _LINES[0] = on
    try:
        yield
    finally:
        _LINES[0] = before


class LineProgress:
    """Progress as lines on ``stream`` (default stderr), at most one per ``period_s`` [s]: ``lipmpcc: LIP:
    120/1000 steps (12%), 30 s, about 3.5 min left``; nothing for a run shorter than ``period_s``."""

    def __init__(self, total: float, desc: str, unit: str = "steps", period_s: float = PROGRESS_LINE_S,
                 clock: Callable[[], float] = time.monotonic, stream: TextIO | None = None) -> None:
        self.total, self.desc, self.unit, self.period_s = float(total), desc, unit, float(period_s)
        self.clock, self.stream = clock, stream
        self.n = 0.0
        self.t0 = clock()
        self._next = self.t0 + self.period_s
        self.lines = 0

    def update(self, n: float = 1) -> None:
        """``n`` more done; a line when the period has passed."""
        self.update_to(self.n + n)

    def update_to(self, value: float) -> None:
        """``value`` done so far; a line when the period has passed."""
        self.n = float(value)
        now = self.clock()
        if now < self._next:
            return
        elapsed = now - self.t0
        frac = self.n / self.total if self.total > 0 else 0.0
        left = f", about {_seconds(elapsed * (1.0 - frac) / frac)} left" if 0.0 < frac < 1.0 else ""
        shown = f"{self.n:.0f}" if self.unit == "steps" else f"{self.n:.1f}"
        print(f"lipmpcc: {self.desc}: {shown}/{self.total:.0f} {self.unit} ({100.0 * frac:.0f}%), "
              f"{_seconds(elapsed)}{left}", file=self.stream or sys.stderr, flush=True)
        self.lines += 1
        self._next = now + self.period_s

    def close(self) -> None:
        """Nothing to close (the same interface as a tqdm bar)."""

    def set_postfix_str(self, *args: Any, **kwargs: Any) -> None:
        """Ignored (the same interface as a tqdm bar)."""

    def refresh(self) -> None:
        """Ignored (the same interface as a tqdm bar)."""


def _seconds(s: float) -> str:
    """``"42 s"``, ``"3.5 min"``, ``"2.1 h"``."""
    return f"{s:.0f} s" if s < 120 else f"{s / 60:.1f} min" if s < 7200 else f"{s / 3600:.1f} h"


def line_progress(total: float, desc: str, unit: str = "steps") -> LineProgress | None:
    """A :class:`LineProgress` when progress lines are on (:func:`progress_lines`) and stderr is not a
    terminal; else None."""
    if not _LINES[0] or getattr(sys.stderr, "isatty", lambda: False)():
        return None
    return LineProgress(total, desc, unit)


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
    lines = line_progress(total, desc) if show is None else None
    if lines is not None:  # off a terminal, under lipmpcc run: a line now and then
        yield lines
        return
    from tqdm import tqdm

    bar = tqdm(total=int(total), unit="step", desc=desc, leave=False, disable=None if show is None else not show)
    try:
        yield bar
    finally:
        bar.close()

"""The ``lipmpcc`` program (the console script, and ``python -m lipmpcc``): :func:`lipmpcc.cli.main`
behind a light module, so that a Ctrl-C at any moment — while the heavy modules are still being
imported, during the run, or while the process exits — ends it with the one line ``lipmpcc:
interrupted`` and exit code 130, never a traceback or a death by SIGINT.
"""

from __future__ import annotations

import os
import signal
import sys
from typing import NoReturn

__all__ = ["main"]

EXIT_INTERRUPTED = 130  # lipmpcc.cli.EXIT_INTERRUPTED (not imported: this module stays light)


def _interrupted(announce: bool) -> NoReturn:
    """Exit 130 at once, ignoring further Ctrl-Cs.

    ``os._exit`` after flushing: CPython kills itself with SIGINT at exit when a KeyboardInterrupt once
    went through C code that ran Python (an extension module being imported), even after Python code
    handled it; the clean-up of the run (its staging folder, its lock) has already run in ``finally``.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if announce:
        print("lipmpcc: interrupted", file=sys.stderr)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(EXIT_INTERRUPTED)


_EARLY: list[int] = []  # the Ctrl-Cs seen while the heavy modules were imported


def _early_sigint(signum: int, frame: object) -> None:
    _EARLY.append(signum)
    raise KeyboardInterrupt


def _import_cli():  # noqa: ANN202 - the lipmpcc.cli module
    """Import :mod:`lipmpcc.cli` (the heavy modules), noting any Ctrl-C: an extension being imported may
    swallow the KeyboardInterrupt, and the command must not then run as if nothing happened."""
    watch = signal.getsignal(signal.SIGINT) is signal.default_int_handler  # not when SIGINT is ignored
    if watch:
        signal.signal(signal.SIGINT, _early_sigint)
    try:
        from . import cli
    except KeyboardInterrupt:
        _interrupted(True)
    except Exception:
        if _EARLY:  # an extension turned the Ctrl-C into its own error (numpy: an ImportError of "datetime")
            _interrupted(True)
        raise
    finally:
        if watch:
            signal.signal(signal.SIGINT, signal.default_int_handler)
    if _EARLY:
        _interrupted(True)
    return cli


def main() -> NoReturn:
    """Run the command line of ``sys.argv`` and exit with its code (see :mod:`lipmpcc.cli`)."""
    cli = _import_cli()
    try:
        code = cli.main()
    except KeyboardInterrupt:  # one that arrived while main was returning, its answer printed or not
        _interrupted(not cli.interrupt_answered())
    if code == EXIT_INTERRUPTED:
        _interrupted(False)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command is done: a Ctrl-C while Python shuts down changes
    raise SystemExit(code)  # nothing (it killed the process by SIGINT, with no word, after a complete run)

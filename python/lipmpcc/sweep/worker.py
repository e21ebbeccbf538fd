"""What runs in a worker: one case, rebuilt from its plain dict, through the code path of ``lipmpcc run``.

:func:`run_case` turns a case (:meth:`lipmpcc.sweep.spec.SweepSpec.cases`) into a
:class:`~lipmpcc.studies.RunOptions` (:func:`case_options`, the pushes in ``extra["pushes"]`` or
``extra["push_scale"]``), runs :func:`lipmpcc.studies.run`, and returns plain data: the summary, the
wall time, the push actually applied, or the error of a case that raised. Nothing compiled crosses a
process boundary. :func:`worker_env` is the environment a worker process starts with (one BLAS/OpenMP
thread, the package's helper threads to suit, a non-interactive matplotlib).
"""

from __future__ import annotations

import math
import os
import signal
import socket
import threading
import time
from contextlib import contextmanager
from dataclasses import replace
from typing import Any, Iterator

from ..conventions import GRAVITY
from ..push import Push

__all__ = [
    "RETIMEOUT_S",
    "DEFAULT_PUSH_DURATION",
    "DEFAULT_ONSET",
    "PAPER_A_PEAK_IMPULSE",
    "THREAD_VARS",
    "worker_env",
    "prepare_process",
    "default_push_step",
    "nominal_step_duration",
    "robot_mass",
    "case_pushes",
    "case_options",
    "push_extra",
    "run_case",
    "CaseTimeout",
    "deadline",
]

DEFAULT_PUSH_DURATION = 0.1  # [s] paper A's and paper B's push length
DEFAULT_ONSET = 0.1  # [s] after the touch-down (paper B's window starts 0.1 s into the swing)
PAPER_A_PEAK_IMPULSE = 50.0 * 0.1  # [N s] paper A's largest push: 50 N for 0.1 s (lipmpcc.loops.lip.random_pushes)
THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "NUMEXPR_NUM_THREADS")


def worker_env(helper_threads: bool) -> dict[str, str]:
    """The environment variables of a worker: one BLAS/OpenMP thread, ``MPLBACKEND=Agg``, and the package's
    helper threads (``LIPMPCC_LOOP_THREAD``, ``LIPMPCC_WBC_THREAD``) off unless ``helper_threads``."""
    env = {k: "1" for k in THREAD_VARS}
    env["MPLBACKEND"] = "Agg"
    if not helper_threads:
        env["LIPMPCC_LOOP_THREAD"] = "0"
        env["LIPMPCC_WBC_THREAD"] = "0"
    return env


def prepare_process(env: dict[str, str]) -> dict[str, Any]:
    """Set ``env`` in this (worker) process; returns what the worker sees (pid, host, the thread variables),
    for checks. Libraries loaded before this call keep their thread pools: the local pool therefore
    also starts its workers under ``env`` (:mod:`lipmpcc.sweep.runner`)."""
    os.environ.update(env)
    return {"pid": os.getpid(), "host": socket.gethostname(), **{k: os.environ.get(k) for k in (*THREAD_VARS, *env)}}


def default_push_step(study: str) -> int:
    """The footstep a single push hits when the spec gives no ``push_step``: step 10 of ``circle-push`` (4 s
    in, after the start-up), the swing towards stone 5 in ``push`` (paper B's first push) and towards field
    foothold 5 in ``stone-field``."""
    if study in ("push", "stone-field"):  # stone-field: the swing towards field foothold 5
        from ..terrain import N_APPROACH

        return N_APPROACH + 4
    return 10


def nominal_step_duration(case: dict[str, Any]) -> float:
    """The nominal step duration [s] a push ``onset`` in ``fraction`` refers to: the MPCC's T on the LIP
    (0.4 s), the ALIP-MPC's T_nom (0.5 s) in the stepping-stone studies and ``stone-field``."""
    if case["study"] in ("push", "stones", "stone-field"):
        from ..planners.alip_mpc import AlipMpcParams

        return float(AlipMpcParams.paper().T_nom)
    from ..studies.path_scenarios import lip_params

    return float(lip_params(case["study"], case["planner_name"]).model.T)


def robot_mass(robot: str) -> float:
    """The mass [kg] a ``weight_fraction`` refers to: the LIP's 48 kg, the ALIP's 47.9 kg, a full body's total."""
    if robot == "lip":
        from ..loops.lip import DIGIT_MASS

        return float(DIGIT_MASS)
    if robot == "alip":
        from ..models.alip import AlipParams

        return float(AlipParams().mass)
    from ..robots import load_robot

    return float(load_robot(robot).total_mass)


def case_pushes(case: dict[str, Any]) -> tuple[list[Push] | None, dict[str, float | None]]:
    """The case's single push (None: the study's own pushes, maybe scaled) and what it is: ``force_N``,
    ``impulse_Ns`` (for ``push_scale``: the scaled study's largest push's impulse)."""
    p, units = case["params"], case.get("units", {})
    if "push_scale" in p:
        scale = float(p["push_scale"])
        if case["study"] in ("push", "stone-field") or case["options"].get("push_set") == "paper-b":  # paper B's four
            from ..studies import paper

            test = paper.push_test()
            peak = max(math.hypot(*q.force) for q in test.pushes) * (test.window[1] - test.window[0])
        else:
            peak = PAPER_A_PEAK_IMPULSE
        return None, {"force_N": None, "impulse_Ns": scale * peak}
    mag = next((k for k in ("force", "impulse", "weight_fraction") if k in p), None)
    if mag is None:
        return None, {"force_N": None, "impulse_Ns": None}
    duration = float(p.get("duration", DEFAULT_PUSH_DURATION))
    if mag == "force":
        f = float(p["force"])
    elif mag == "impulse":
        f = float(p["impulse"]) / duration
    else:
        f = float(p["weight_fraction"]) * robot_mass(case["robot"]) * GRAVITY
    a = float(p.get("direction", 0.0))
    force = (f * math.cos(a), f * math.sin(a))
    if "push_time" in p:
        push = Push(force, float(p["push_time"]), duration)
    else:
        onset = float(p.get("onset", DEFAULT_ONSET))
        if units.get("onset") == "fraction":
            onset *= nominal_step_duration(case)
        push = Push(force, onset, duration, step=int(p.get("push_step", default_push_step(case["study"]))))
    return [push], {"force_N": f, "impulse_Ns": f * duration}


def case_options(case: dict[str, Any], with_pushes: bool = True) -> Any:
    """The case as :class:`~lipmpcc.studies.RunOptions`: its ``options`` (the spec's, the planner's, and the
    axes that are options) and (``with_pushes``) the push hook in ``extra``."""
    from ..studies import RunOptions

    kw: dict[str, Any] = dict(case["options"])  # the spec's, the planner's and the axes' that are options
    if kw.get("cop_range") is not None:
        kw["cop_range"] = tuple(kw["cop_range"])
    extra = push_extra(case, case_pushes(case)[0]) if with_pushes else {}
    return RunOptions(scenario=case["study"], planner=case["planner_name"], robot=case["robot"], extra=extra, **kw)


def push_extra(case: dict[str, Any], pushes: list[Push] | None) -> dict[str, Any]:
    """The studies' push hook (``RunOptions.extra``): ``pushes`` replace the study's, ``push_scale`` scales them."""
    extra: dict[str, Any] = {}
    if pushes is not None:
        extra["pushes"] = pushes
    if "push_scale" in case["params"]:
        extra["push_scale"] = float(case["params"]["push_scale"])
    return extra


#: after a case's timeout fired and the case goes on (a solver swallowed it), it is raised again this often [s]
RETIMEOUT_S = 0.1


class CaseTimeout(BaseException):
    """A case ran past its ``timeout_s``. A BaseException, like KeyboardInterrupt, so that no
    ``except Exception`` of a loop (a planner's fallback, say) takes it for a solver failure."""


@contextmanager
def deadline(seconds: float | None) -> Iterator[bool]:
    """Raise :class:`CaseTimeout` in the body after ``seconds`` [s] of wall time (SIGALRM). Yields whether
    the limit is enforced: only in a process's main thread (the local pool's workers), not where the case
    runs in a thread (Dask's workers), nor without ``seconds``."""
    if not seconds or threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield False
        return

    from ..studies.outputs import in_finalizer

    message = f"the case ran longer than its timeout_s = {seconds:g} s and was stopped"
    fired = False

    def on_alarm(signum: int, frame: Any) -> None:
        nonlocal fired
        fired = True
        signal.setitimer(signal.ITIMER_REAL, RETIMEOUT_S)  # again until it escapes: a solver may swallow it
        if not in_finalizer(frame):
            raise CaseTimeout(message)

    old = signal.signal(signal.SIGALRM, on_alarm)
    signal.setitimer(signal.ITIMER_REAL, float(seconds))
    try:
        yield True
    except Exception as exc:  # the timeout, turned into an error by a library (CasADi's solvers do)
        if fired:
            raise CaseTimeout(message) from exc
        raise
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)
    if fired:  # swallowed every time, and the body ended
        raise CaseTimeout(message)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}"[:500]


def run_case(case: dict[str, Any], env: dict[str, str] | None = None) -> dict[str, Any]:
    """Run one case (in a worker) and return plain data: ``id``, ``status`` (``"done"``, ``"error"``, or
    ``"timeout"`` for a case stopped at its ``timeout_s``, see :func:`deadline`),
    ``summary`` (summary.json's content), ``push`` (``force_N``, ``impulse_Ns``), ``error`` (one line),
    ``wall_s`` [s], ``worker`` (host:pid). A case that raises is an ``"error"``, never an exception here.

    ``env``: the worker's environment (:func:`worker_env`, set by the local pool); None under another
    executor: the variables of :func:`worker_env` that the worker's environment lacks are set, and the fast
    mode follows the case's."""
    from .. import config

    if env is not None:
        prepare_process(env)
    else:  # under another executor (Dask): what the user set stays
        for k, v in worker_env(config.threads_enabled("LIPMPCC_LOOP_THREAD")).items():
            os.environ.setdefault(k, v)
    with config.fast_mode_as(bool(case.get("fast", False))):  # the case's; the caller's afterwards (in-process executors)
        return _run_case(case)


def _run_case(case: dict[str, Any]) -> dict[str, Any]:
    from .. import studies
    from ..studies.options import jsonable

    t0 = time.perf_counter()
    out: dict[str, Any] = {"id": case["id"], "status": "done", "summary": None, "push": {}, "error": None,
                           "worker": f"{socket.gethostname()}:{os.getpid()}"}
    try:
        with deadline(case.get("timeout_s")):
            pushes, out["push"] = case_pushes(case)
            opts = replace(case_options(case, with_pushes=False), extra=push_extra(case, pushes))
            res = studies.run(opts)
        out["summary"] = jsonable(res.summary)
        import matplotlib.pyplot as plt

        for fig in res.figures.values():
            plt.close(fig)
    except CaseTimeout as exc:
        out["status"], out["error"] = "timeout", _one_line(exc)
    except Exception as exc:  # noqa: BLE001 - a case that raises is a result
        out["status"], out["error"] = "error", _one_line(exc)
    out["wall_s"] = time.perf_counter() - t0
    return out

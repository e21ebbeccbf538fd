"""A small results.json of both papers, out of the papers' order, with real PNG figures (for the report's tests)."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def _entry(title: str, paper_id: str, item: str, robot: str, planner: str | None, ours: dict[str, Any], claim: Any,
           meets: bool | None, outcome: str = "completed", figures: tuple[str, ...] = (), course: str | None = None,
           **extra: Any) -> dict[str, Any]:
    return {"title": title, "paper_id": paper_id, "item": item, "robot": robot, "planner": planner, "course": course,
            "cop_range": None, "ours": ours, "paper": claim, "criterion": "c", "meets_criterion": meets,
            "figures": list(figures), "outcome": outcome, "expected_outcome": None, "solver_failures": 0,
            "relaxed_solves": 0, "warnings": [], **extra}


def results() -> dict[str, Any]:
    """Paper B's studies before paper A's (the report must put A first), one of each mark."""
    stones = {"fell": False, "fall_step": None, "steps_completed": 16, "step_rmse_m": 0.0031, "step_duration_min_s": 0.46,
              "step_duration_max_s": 0.51, "solver_failures": 0}
    return {"fast": True, "status": "complete", "not_run": [], "wall_s": 12.0, "studies": {
        "alip-stones-II-alip-mpc": _entry("Paper B Table II, profile II, alip-mpc, ALIP", "B", "Table II", "alip", "alip-mpc",
                                          stones, 0.023, True, course="II",
                                          figures=("alip-stones-II-alip-mpc/footprints.png",
                                                   "alip-stones-II-alip-mpc/durations_dcm.png")),
        "alip-stones-I_L0.2_W+0.15-alip-qp": _entry("Paper B Table II, profile I, alip-qp, ALIP", "B", "Table II", "alip",
                                                    "alip-qp", {**stones, "step_rmse_m": 0.037}, 0.040, None,
                                                    course="I L=0.2 W=+0.15",
                                                    figures=("alip-stones-I_L0.2_W+0.15-alip-qp/footprints.png",)),
        "alip-push-alip-mpc": _entry("Paper B Fig. 7: push test, alip-mpc, ALIP", "B", "Fig. 7", "alip", "alip-mpc",
                                     {"fell": True, "fall_step": 11, "solver_failures": 27}, "survives", False, "fell",
                                     expected_failure="a point foot cannot", figures=("alip-push-alip-mpc/push_response.png",)),
        "digit-push-alip-mpc": {**_entry("Paper B Fig. 7: push test, alip-mpc, digit_like", "B", "Fig. 7", "digit_like",
                                         "alip-mpc", {"fell": False, "steps_completed": 22}, "survives", True),
                                "solver_failures": 11, "relaxed_solves": 11},
        "lip-circle": _entry("Paper A Fig. 5(a,b): circle r = 2 m, LIP", "A", "Fig. 5(a,b)", "lip", "mpcc",
                             {"contouring_error_max_m": 0.0124, "solve_ms": {"median": 1.29, "p90": 1.49}}, "followed",
                             True, figures=("lip-circle/circle.png",)),
        "digit-overtake-mpcc": {**_entry("Paper A Fig. 6(e-h): MPCC, obstacle 0.6 m/s, digit_like", "A", "Fig. 6(e-h)",
                                         "digit_like", "mpcc", {"fell": False, "overtook": True, "collided": True},
                                         {"overtook": True, "lag_error": "near zero"}, False, "collided",
                                         figures=("digit-overtake-mpcc/overtake.png",)), "solver_failures": 4},
        "digit-walk": _entry("Walking under the whole-body QP", "", "", "digit_like", None, {"fell": False}, "(not in the papers)",
                             True, figures=("digit-walk/walk_top.png",)),
    }}


def write_figures(res: dict[str, Any], out: Path) -> None:
    """A small real PNG at every figure path of ``res`` under ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for e in res["studies"].values():
        for f in e.get("figures", []):
            (out / f).parent.mkdir(parents=True, exist_ok=True)
            fig, ax = plt.subplots(figsize=(2, 1))
            ax.plot([0, 1], [0, 1], label=f)
            fig.savefig(out / f, dpi=40)
            plt.close(fig)

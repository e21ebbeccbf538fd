"""Notebook 10b's exercise, the centre of pressure that cancels a push: its own check grades the shipped solution
full, the stub 0, an unclipped CoP and a flipped sign 0 with a message that says where. No simulation (< 1 s)."""

from __future__ import annotations

import math

import numpy as np

from lipmpcc.course import Exercises

from .notebook_exercise import NOTEBOOKS, grade, solution


def _grade(student):  # noqa: ANN001, ANN202
    return grade("10b_digit_paper_b_deep_dive", "cop_to_cancel", student, {"np": np, "math": math, "Exercises": Exercises})


def test_notebook_10bs_check_grades_solution_stub_unclipped_and_flipped(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)
    monkeypatch.delenv("LIPMPCC_GRADE_LOG", raising=False)
    right = solution("10b_digit_paper_b_deep_dive", "cop_to_cancel")
    solved = _grade(right)
    assert solved.status == "solved" and solved.fraction == 1.0, solved

    def stub(dz, sigma, lam, t, box):  # noqa: ANN001, ANN202
        raise NotImplementedError

    def unclipped(dz, sigma, lam, t, box):  # noqa: ANN001, ANN202
        return np.asarray(dz, dtype=float) / (sigma * math.exp(-lam * t) - 1.0)

    def flipped(dz, sigma, lam, t, box):  # noqa: ANN001, ANN202
        return -right(dz, sigma, lam, t, box)

    assert (_grade(stub).status, _grade(stub).fraction) == ("unsolved", 0.0)
    over = _grade(unclipped)
    assert over.status == "wrong" and over.fraction == 0.0 and "leaves the sole's box" in over.message, over
    wrong = _grade(flipped)
    assert wrong.status == "wrong" and wrong.fraction == 0.0 and "axis" in wrong.message, wrong
    # the forward push of paper B (150 N, 0.1–0.2 s into a 0.5 s step) needs more than digit_like's ±6 cm
    lam = math.sqrt(9.81 / 0.953)
    sig = math.exp(0.5 * lam)
    dz = sig * 150.0 * (math.exp(-0.1 * lam) - math.exp(-0.2 * lam)) / (48.0 * lam**2)
    d = right([dz, 0.0], sig, lam, 0.2, [0.06, 0.025])
    assert d[0] == 0.06 and d[1] == 0.0 and 0.2 < dz < 0.4
    assert (NOTEBOOKS / "solutions" / "10b_digit_paper_b_deep_dive.py").is_file()

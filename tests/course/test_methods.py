"""lipmpcc.course.methods: a one-step stone planner assembled from a student's functions; the ALIP loop walks
on them (right pieces: every stone; the foothold's sign flipped in the step map: a fall), and bad pieces are
one-line errors. Two short loops, about 4 s."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.course import Exercises, library_calls
from lipmpcc.course.methods import StudentStonePlanner
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.alip import AlipLoopConfig, loop_metrics, run_alip_loop
from lipmpcc.models import alip
from lipmpcc.studies import stepping_stones as study
from lipmpcc.terrain import make_profile


def step_map(z, sigma, u):
    return sigma * np.asarray(z, float) - np.asarray(u, float)


def sigma_bounds(lam, lo, hi):
    return math.exp(lam * lo), math.exp(lam * hi)


def stone_box(u_nom, size, klo, khi):
    lo = np.maximum(np.asarray(u_nom) - np.asarray(size) / 2, klo)
    hi = np.minimum(np.asarray(u_nom) + np.asarray(size) / 2, khi)
    return lo, np.maximum(hi, lo)


def _walk(planner: StudentStonePlanner, profile: str = "IV") -> dict:
    a = alip.AlipParams()
    seq, _ = study.make_course(make_profile(profile, seed=0, n=6))
    log = run_alip_loop(planner, seq, config=AlipLoopConfig(alip=a), approach_planner=study.make_planner("alip-mpc", a),
                        approach_steps=study.N_APPROACH, progress=False)
    return loop_metrics(log)


def test_the_right_pieces_walk_the_stones_and_a_flipped_sign_falls() -> None:
    good = _walk(StudentStonePlanner(step_map, sigma_bounds, stone_box))
    assert good["completed"] and not good["fell"] and good["stones_violated"] == 0, good
    flipped = _walk(StudentStonePlanner(lambda z, s, u: s * np.asarray(z) + np.asarray(u), sigma_bounds, stone_box))
    assert flipped["fell"] and not flipped["completed"], flipped


def test_bad_pieces_are_one_line_errors() -> None:
    with pytest.raises(InvalidInputError, match="three functions"):
        StudentStonePlanner(step_map, None, stone_box)
    pl = StudentStonePlanner(step_map, lambda lam, lo, hi: (math.exp(lam * hi), math.exp(lam * lo)), stone_box)
    stones = make_profile("I", seed=0, n=3)
    with pytest.raises(InvalidInputError, match="sigma_lo <= sigma_hi"):
        pl.solve([0.05, -0.1], [0.0, -0.1], "left", 0.05, stones)


def test_a_step_map_that_calls_the_library_scores_zero(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_SOLUTIONS", raising=False)

    def lazy(z, sigma, u):
        return alip.step_to_step(z, sigma, u)

    assert library_calls(lazy, ("step_to_step",)) == ["step_to_step"] and library_calls(step_map, ("step_to_step",)) == []
    ex = Exercises("probe")
    res = ex.check(lazy, stars=1, minutes=5, own_code=("step_to_step",))(lambda f: None)
    assert res.status == "wrong" and "calls the library's step_to_step" in res.message

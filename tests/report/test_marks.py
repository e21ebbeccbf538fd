"""Marks beside the paper (pass, expected-fail, differs) and the reasons, read from paper_results.json."""

from __future__ import annotations

from fnmatch import fnmatchcase

import pytest

from lipmpcc.report.marks import better_factor, exit_failures, judge, reasons

from .synthetic import results


def test_every_reason_is_complete_and_names_studies_that_exist() -> None:
    from lipmpcc.reproduce import POINT_FOOT_PUSH, all_studies

    names = [s.name for s in all_studies()]
    known = reasons()
    assert {"point-foot-push", "same-approach", "reduced-loop-lands-exactly", "swept-legs", "solve-times"} <= set(known)
    for r in known.values():
        assert r.short and r.text and r.doc.startswith("docs/") and r.when, r.key
        assert all(any(fnmatchcase(n, p) for n in names) for p in r.studies), r.key
        assert set(r.when) <= {"expected-fail", "outcome", "number", "solve-time"}, r.key
    assert known["point-foot-push"].text == POINT_FOOT_PUSH  # one definition: reproduce reads it from the data


def test_an_expected_failure_is_marked_as_such_with_its_reason() -> None:
    j = judge("alip-push-alip-mpc", results()["studies"]["alip-push-alip-mpc"])
    assert (j.mark, j.label) == ("expected-fail", "expected-fail: fell")
    assert [r.key for r in j.reasons] == ["point-foot-push"] and "point foot" in j.why


def test_a_collision_differs_with_its_reason() -> None:
    j = judge("digit-overtake-mpcc", results()["studies"]["digit-overtake-mpcc"])
    assert j.label == "differs: collided" and j.kinds == ("outcome",)
    assert [r.key for r in j.reasons] == ["swept-legs"] and "thigh" in j.why


def test_a_number_far_better_than_the_papers_passes_better_one_far_worse_differs_one_near_it_passes() -> None:
    e = results()["studies"]["alip-stones-II-alip-mpc"]  # 3.1 mm against the paper's 23 mm
    j = judge("alip-stones-II-alip-mpc", e)
    assert j.mark == "better" and j.kinds == () and j.factor == pytest.approx(0.023 / e["ours"]["step_rmse_m"])
    assert j.label == f"pass, better than the paper ({0.023 / e['ours']['step_rmse_m']:.1f}×)"
    assert [r.key for r in j.reasons] == ["reduced-loop-lands-exactly"] and "exactly" in j.why  # why it is better
    assert better_factor(e) == j.factor
    e["ours"]["step_rmse_m"] = 0.02
    assert judge("alip-stones-II-alip-mpc", e).mark == "pass" and judge("alip-stones-II-alip-mpc", e).why == ""
    e["ours"]["step_rmse_m"] = 0.05  # more than twice the paper's: a worse number still differs
    j = judge("alip-stones-II-alip-mpc", e)
    assert j.mark == "differs" and j.kinds == ("number",) and better_factor(e) is None
    e["ours"].update(step_rmse_m=0.003, fell=True)  # a better number on a run that fell is not better
    assert judge("alip-stones-II-alip-mpc", {**e, "outcome": "fell"}).mark == "differs"
    missed = {**e, "ours": {"fell": False, "step_rmse_m": 0.003}, "meets_criterion": False}
    assert judge("alip-stones-II-alip-mpc", missed).mark == "differs"  # a missed criterion is never better


def test_a_baseline_is_judged_against_the_papers_outcome() -> None:
    base = {"ours": {"fell": False, "step_rmse_m": 0.03}, "meets_criterion": None, "outcome": "completed"}
    completes = judge("alip-stones-II-alip-qp", {**base, "paper": "falls at step 14"})
    assert completes.mark == "differs" and [r.key for r in completes.reasons] == ["same-approach"]
    fell = {**base, "ours": {"fell": True, "fall_step": 8}, "outcome": "fell"}
    assert judge("alip-stones-III-alip-qp", {**fell, "paper": "falls"}).label == "pass: fell"  # as the paper's
    early = judge("alip-push-alip-qp", {**fell, "paper": "fails on the lateral pushes"})  # stone 8 < 15: before them
    assert early.mark == "differs" and [r.key for r in early.reasons] == ["point-foot-push-qp"]
    late = {**fell, "ours": {"fell": True, "fall_step": 16}}
    assert judge("alip-push-alip-qp", {**late, "paper": "fails on the lateral pushes"}).mark == "pass"


def test_a_difference_no_reason_explains_says_so() -> None:
    j = judge("my-study", {"ours": {}, "paper": None, "meets_criterion": False, "outcome": "stopped_early"})
    assert j.label == "differs: stopped early" and j.reasons == () and j.why == "**no reason recorded**"
    named = judge("my-study", {"ours": {}, "paper": None, "meets_criterion": False, "outcome": "completed",
                               "criterion": "no fall; max abs contouring error after 3 s <= 0.10 m"})
    assert named.why == ("misses its criterion: no fall; max abs contouring error after 3 s <= 0.10 m "
                         "(no reason recorded)")
    # a study that names its criterion's parts (results.json's criterion_missed): only the parts it missed
    parts = judge("my-study", {"ours": {}, "paper": None, "meets_criterion": False, "outcome": "collided",
                               "criterion": "no fall; trails; no part of the body in the obstacle",
                               "criterion_missed": ["no part of the body in the obstacle (min_body_clearance_m = -0.009)"]})
    assert parts.why == ("misses its criterion: no part of the body in the obstacle (min_body_clearance_m = -0.009) "
                         "(no reason recorded)")


def test_errors_and_the_studies_that_make_the_command_exit_1() -> None:
    assert judge("x", {"error": "ValueError: boom", "status": "error"}).mark == "error"
    assert judge("x", {"error": "skipped: no WBC", "status": "skipped"}).mark == "skipped"
    assert exit_failures(results()) == ["digit-overtake-mpcc"]

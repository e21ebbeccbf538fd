"""A study's numbers as text: labelled, with units, never a raw dict."""

from __future__ import annotations

from lipmpcc.report.values import describe, length, model_name, paper_text, run_text


def test_describe_labels_every_number_with_its_unit_and_no_raw_dict() -> None:
    ours = {"fell": False, "fall_step": None, "steps_completed": 16, "step_rmse_m": 0.0030575, "stones_violated": 0,
            "step_duration_min_s": 0.4585, "step_duration_max_s": 0.5116, "solver_failures": 0,
            "solve_ms": {"median": 0.134, "p90": 0.22}}
    text = describe(ours)
    assert text == ("no fall; 16 steps; step RMSE 0.003 m; every foothold on its stone; step durations 0.46–0.51 s; "
                    "solve time median 0.13 ms, p90 0.22 ms")
    assert "{" not in text and "=" not in text and "solver" not in text  # the solver counts have their own columns


def test_describe_a_fall_a_collision_and_pushes() -> None:
    assert describe({"fell": True, "fall_step": 11}) == "**falls at stone 11**"
    assert describe({"overtook": True, "collided": True, "min_body_clearance_m": -0.0669}) == (
        "overtakes the obstacle; **collides with the obstacle**; min clearance of the body -0.067 m")
    assert describe({"push_recovery_s": [0.03, None, 0.4]}) == (
        "3 pushes, error back below 0.05 m within 0.40 s at worst, **1 not recovered**")
    assert describe({"some_new_field": 1.23456, "fall_step": None}) == "some new field: 1.235"


def test_the_papers_claims_read_as_text() -> None:
    assert paper_text(0.036) == "0.036 m" and paper_text("falls at step 14") == "falls at step 14"
    assert paper_text({"cartesian_error_max_m": 0.06, "overtook": False}) == "Cartesian error below 0.060 m; trails the obstacle"
    assert paper_text(None) == "–" and length(None) == "–"


def test_how_a_run_ended_and_the_models_names() -> None:
    assert run_text({"outcome": "fell", "ours": {"fall_step": 9}}) == "fell at stone 9"
    assert run_text({"outcome": "stopped_early"}) == "stopped early" and run_text({}) == "–"
    assert model_name("alip") == "ALIP (point foot)" and model_name("digit_like") == "digit_like (MuJoCo)"
    assert model_name("alip", [0.06, 0.025]) == "ALIP with a foot (CoP within ±6 × ±2.5 cm)"


def test_run_text_tells_how_far_a_path_run_came_and_why() -> None:
    from lipmpcc.report.values import run_text

    stall = {"binding": {"obstacles": [5, 6]}}
    assert run_text({"outcome": "stalled", "progress_m": 0.63, "path_length_m": 4.0, "stall": stall}) == (
        "stalled at 0.6 of 4.0 m (obstacles 5, 6)")
    assert run_text({"outcome": "incomplete", "progress_m": 10.5, "path_length_m": 19.0}) == "incomplete at 10.5 of 19.0 m"
    assert run_text({"outcome": "trailing", "trailing_obstacle": 0, "trailing_gap_m": 0.818}) == "trailing obstacle 0 by 0.82 m"

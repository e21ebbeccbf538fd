"""lipmpcc.loops.progress: the reduced loops' step bar — shown when asked, silent off a terminal."""

from __future__ import annotations

import numpy as np

from lipmpcc.loops.progress import step_bar


def test_a_bar_counts_steps_on_stderr_when_asked(capsys) -> None:
    with step_bar(5, "LIP", True) as bar:
        for _ in range(5):
            bar.update(1)
        assert bar.n == 5
    assert "LIP" in capsys.readouterr().err


def test_no_bar_off_a_terminal_or_when_refused(capsys) -> None:
    for show in (None, False):  # pytest's stderr is not a terminal
        with step_bar(5, "LIP", show) as bar:
            bar.update(1)
    assert capsys.readouterr().err == ""


def test_the_lip_loop_shows_its_steps(capsys) -> None:
    from lipmpcc.loops.lip import run_lip_loop
    from tests.loops.test_student_planner import StudentPlanner

    log = run_lip_loop(StudentPlanner(), np.zeros(5), 6, progress=True)
    assert log.steps == 6
    err = capsys.readouterr().err
    assert "LIP" in err and "/6 " in err  # the bar over the 6 steps (tqdm redraws at most every 0.1 s)

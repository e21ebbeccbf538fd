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


def test_line_progress_prints_at_most_one_line_per_period_with_the_time_left() -> None:
    import io

    from lipmpcc.loops.progress import LineProgress

    now = [0.0]
    out = io.StringIO()
    bar = LineProgress(1000, "LIP", period_s=30.0, clock=lambda: now[0], stream=out)
    for k in range(1000):
        now[0] = 0.3 * (k + 1)  # 0.3 s a step: 300 s in all
        bar.update(1)
    lines = out.getvalue().splitlines()
    assert len(lines) == 10 and bar.lines == 10  # every 30 s of the 300 s
    assert lines[0] == "lipmpcc: LIP: 100/1000 steps (10%), 30 s, about 4.5 min left"
    short = io.StringIO()
    quick = LineProgress(10, "LIP", period_s=30.0, clock=lambda: 1.0, stream=short)
    quick.update(10)
    assert short.getvalue() == ""  # a run shorter than the period prints nothing


def test_step_bar_gives_lines_off_a_terminal_only_under_progress_lines(monkeypatch) -> None:
    import io

    from lipmpcc.loops.progress import LineProgress, progress_lines, step_bar

    monkeypatch.setattr("sys.stderr", io.StringIO())  # not a terminal
    with step_bar(5, "LIP") as bar:
        assert not isinstance(bar, LineProgress)
    with progress_lines(), step_bar(5, "LIP") as bar:
        assert isinstance(bar, LineProgress)
    with progress_lines(), step_bar(5, "LIP", show=False) as bar:
        assert not isinstance(bar, LineProgress)

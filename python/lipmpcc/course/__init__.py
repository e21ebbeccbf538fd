"""The course's helpers: exercises with checked solutions (:mod:`lipmpcc.course.exercises`), used by the
notebooks in ``notebooks/`` and their solutions in ``notebooks/solutions/``."""

from __future__ import annotations

from .exercises import GRADE_LOG_ENV, SOLUTIONS_ENV, STAR_LABELS, CheckResult, ExerciseError, Exercises, library_calls, solutions_dir

__all__ = ["Exercises", "ExerciseError", "CheckResult", "SOLUTIONS_ENV", "GRADE_LOG_ENV", "STAR_LABELS", "solutions_dir",
           "library_calls"]

"""The course's helpers: exercises with checked solutions (:mod:`lipmpcc.course.exercises`), used by the
notebooks in ``notebooks/`` and their solutions in ``notebooks/solutions/``."""

from __future__ import annotations

from .exercises import SOLUTIONS_ENV, CheckResult, ExerciseError, Exercises, solutions_dir

__all__ = ["Exercises", "ExerciseError", "CheckResult", "SOLUTIONS_ENV", "solutions_dir"]

"""The full-body loop: MuJoCo (the plant) + the whole-body QP + a footstep planner."""

from .loop import FullBodyLoop, LoopLog, LoopParams, LoopResult, TouchDown

__all__ = ["FullBodyLoop", "LoopParams", "LoopLog", "LoopResult", "TouchDown"]

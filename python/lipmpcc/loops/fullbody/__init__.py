"""The full-body loop: MuJoCo (the plant) + the whole-body QP + a footstep planner.

Modules: :mod:`.loop` (:class:`FullBodyLoop`), :mod:`.params` (:class:`LoopParams`), :mod:`.gait`
(the gait state machine), :mod:`.references` (the whole-body references of a tick), :mod:`.log`
(the per-tick log and the run's result), :mod:`.overlap` (the helper thread), :mod:`.angles`
(angles of rotation matrices).
"""

from .gait import Gait, GaitMode
from .log import LoopLog, LoopResult, TouchDown
from .loop import FullBodyLoop
from .params import LoopParams

__all__ = ["FullBodyLoop", "LoopParams", "LoopLog", "LoopResult", "TouchDown", "Gait", "GaitMode"]

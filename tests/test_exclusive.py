"""lipmpcc.exclusive: a second thread inside a guarded object gets ConcurrentUseError, never a crash."""

from __future__ import annotations

import threading

import pytest

from lipmpcc.exceptions import ConcurrentUseError
from lipmpcc.exclusive import exclusive


class _Slow:
    def __init__(self) -> None:
        self.inside = threading.Event()
        self.go = threading.Event()
        self.calls = 0

    @exclusive("widget")
    def work(self) -> int:
        self.inside.set()
        self.go.wait(5)
        self.calls += 1
        return self.calls

    @exclusive("widget")
    def outer(self) -> int:
        return self.quick() + 1  # re-entering from the same thread is allowed

    @exclusive("widget")
    def quick(self) -> int:
        return 1


def test_second_thread_is_refused_naming_object_and_method() -> None:
    obj = _Slow()
    t = threading.Thread(target=obj.work)
    t.start()
    assert obj.inside.wait(5)
    with pytest.raises(ConcurrentUseError, match=r"_Slow\(id=.*\)\.quick\(\).*use one widget per thread") as info:
        obj.quick()
    assert info.value.method == "quick"
    obj.go.set()
    t.join()
    assert obj.quick() == 1 and obj.calls == 1  # free again once the first call returned


def test_same_thread_may_reenter_and_objects_are_independent() -> None:
    a, b = _Slow(), _Slow()
    assert a.outer() == 2
    t = threading.Thread(target=a.work)
    t.start()
    assert a.inside.wait(5)
    assert b.quick() == 1  # another object of the same class is not locked
    a.go.set()
    t.join()


def test_lock_is_released_when_the_method_raises() -> None:
    class _Fails:
        @exclusive("thing")
        def boom(self) -> None:
            raise KeyError("x")

    f = _Fails()
    for _ in range(2):
        with pytest.raises(KeyError):
            f.boom()


def test_robot_sim_from_two_threads_refuses_instead_of_crashing() -> None:
    import numpy as np

    from lipmpcc.robots import load_robot
    from lipmpcc.sim.robot_sim import RobotSim

    sim = RobotSim(load_robot("digit_like"))
    u, errors, done = np.zeros(sim.nu), [], []

    def run() -> None:
        try:
            for _ in range(400):
                sim.step(u, 1)
            done.append(1)
        except ConcurrentUseError as exc:
            errors.append(exc)

    ts = [threading.Thread(target=run) for _ in range(2)]
    [t.start() for t in ts]
    [t.join() for t in ts]
    assert len(errors) + len(done) == 2 and done  # one finished; the other either finished or was refused
    assert all("RobotSim" in str(e) and "use one simulator per thread" in str(e) for e in errors)


@pytest.mark.parametrize("kind", ["mpcc", "alip-mpc", "alip-qp"])
def test_a_planner_in_use_refuses_a_second_thread(kind: str) -> None:
    """The planners hold CasADi buffers / solver workspaces: a second thread entering solve or plan while
    the first is inside gets ConcurrentUseError (two MPCC solves at once crashed the process)."""
    from lipmpcc.exclusive import _lock_of
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.alip_mpc import AlipMpc
    from lipmpcc.planners.alip_qp import AlipQp
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner

    planner = {"mpcc": lambda: MpccPlanner(ArcPath.circle(2.0), MpccParams.circle()),
               "alip-mpc": AlipMpc, "alip-qp": AlipQp}[kind]()
    held = threading.Event()
    release = threading.Event()

    def hold() -> None:  # stands for a long solve in another thread
        with _lock_of(planner):
            held.set()
            release.wait(5)

    t = threading.Thread(target=hold)
    t.start()
    assert held.wait(5)
    try:
        for method in ("solve", "plan"):
            with pytest.raises(ConcurrentUseError, match=f"{method}\\(\\).*use one planner per thread"):
                getattr(planner, method)(None)
    finally:
        release.set()
        t.join()

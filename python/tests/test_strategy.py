"""Python strategies and cost models inside the Rust mission loop: the examples run."""

import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

import strider

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def example(name):
    sys.path.insert(0, str(EXAMPLES))
    try:
        return runpy.run_path(str(EXAMPLES / name), run_name="example")
    finally:
        sys.path.remove(str(EXAMPLES))


def test_the_python_strategy_explores():
    r = example("python_strategy.py")["main"](time_limit=30)
    assert r.strategy == "python" and r.decisions >= 20
    assert r.driven_m > 0.5 and r.observed_cells > 1000
    assert int(r.layers["observed"].sum()) == r.observed_cells


def test_the_python_cost_model_learns_and_steers():
    r, model = example("python_cost_model.py")["main"](time_limit=30)
    assert r.cost_samples > 0 and model.updates > 0 and model.gps
    X, Y = next(iter(model.data.values()))
    assert X.shape[1] == 5 and np.isfinite(Y).all()


class Raises:
    def decide(self, snap):
        raise RuntimeError("strategy bug")


class BadAnswer:
    def decide(self, snap):
        return {"goal": (0.0, 0.0), "speed": 3}


class RaisesLater:
    """Drives towards a goal for three decisions, then fails."""

    def __init__(self):
        self.calls = 0

    def decide(self, snap):
        self.calls += 1
        if self.calls > 3:
            raise RuntimeError("strategy bug at decision 4")
        x, y = snap.get("pose", (1.0, 1.0, 0.0))[:2]
        return {"goal": (x + 2.0, y)}


def test_strategy_errors_reach_the_caller():
    with pytest.raises(RuntimeError, match="strategy bug"):
        strider.run_python(Raises(), time_limit=5)
    with pytest.raises(RuntimeError, match="decision 4") as failed:
        strider.run_python(RaisesLater(), time_limit=60)
    # The mission up to the failure comes with the exception.
    r = failed.value.report
    assert r.termination == "StrategyFailed" and r.decisions == 4
    assert r.exploration_time_s < 60 and r.observed_cells > 0
    assert int(r.layers["observed"].sum()) == r.observed_cells
    with pytest.raises(ValueError, match="unknown key \"speed\""):
        strider.run_python(BadAnswer(), time_limit=5)
    with pytest.raises(ValueError, match="decide"):
        strider.run_python(object(), time_limit=5)
    with pytest.raises(ValueError, match="decision_period"):
        strider.run_python(BadAnswer(), time_limit=5, decision_period=0)


class FarAway:
    """Asks for a goal no known route reaches, and records what the next snapshots say."""

    def __init__(self):
        self.seen = []

    def decide(self, snap):
        self.seen.append(snap["goal_reachable"])
        return {"goal": (500.0, 500.0)}


def test_goals_are_planned_on_the_map_and_unreachable_ones_are_reported():
    s = FarAway()
    r = strider.run_python(s, time_limit=5)
    assert s.seen[0] is None and s.seen[1:] and not any(s.seen[1:])
    # No route: the robot stays where it is rather than drive blind.
    assert r.driven_m < 0.05

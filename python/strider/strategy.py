"""Strategies and cost models written in Python, run inside the Rust mission loop.

A strategy is any object with ``decide(snapshot) -> dict | None``. ``snapshot`` is a dict:
``time_s``, ``pose`` (x, y, yaw), ``gait``, ``gaits`` (their count), ``layers`` (the map's
numpy layers, as :attr:`strider.Report.layers`) and, with a cost model, ``cost`` and
``cost_variance`` (the model's prediction for every observed cell, NaN elsewhere), and
``goal_reachable`` (whether the last goal had a route; None before the first goal). The answer
may hold ``goal`` (x, y) — driven along the shortest route on the map that keeps the robot's
footprint off obstacles, planned as the built-in explorers plan; with no known route the robot
stops —, ``path`` [(x, y), …] (driven as given), ``gait`` (an index) and ``done`` (True ends
the mission); ``None`` keeps the current course.

A cost model is any object with ``update(descriptors, costs, gaits)`` (the samples measured
since the last decision: an (n, 5) float64 array of Prágr19 shape + Lab descriptors of the
cells the robot crossed, the inverse-velocity costs and the gait indices) and
``predict(descriptors) -> (mean, variance)`` (two float64 arrays, one value per row), so a
PyTorch or scikit-learn model can steer the robot.
"""

from __future__ import annotations

from typing import Any, Optional

from . import _strider
from .report import Report


def run_python(
    strategy: Any,
    scenario: str = "courtyard-small",
    cost_model: Any = None,
    seed: int = 1,
    world_seed: int = 1,
    time_limit: Optional[float] = None,
    decision_period: float = 1.0,
) -> Report:
    """Runs a mission of the Python ``strategy`` (and ``cost_model``) on ``scenario``, one
    decision every ``decision_period`` simulated seconds. Returns a :class:`Report` with
    ``exploration_time_s``, ``driven_m``, ``observed_cells``, ``termination``,
    ``cost_samples``, ``decisions``, ``python_s`` (wall time inside Python), ``mission_wall_s``
    and the final ``layers``. An exception raised by the strategy or the model ends the mission
    (termination ``StrategyFailed``) and is raised here, with the mission up to that point as its
    ``report`` attribute (a :class:`Report`, when the exception takes attributes)."""
    if not callable(getattr(strategy, "decide", None)):
        raise _strider.StriderError("strategy: needs a decide(snapshot) method")
    if cost_model is not None:
        for m in ("update", "predict"):
            if not callable(getattr(cost_model, m, None)):
                raise _strider.StriderError(f"cost_model: needs an {m}(...) method")
    from . import _seed, _time_limit  # the package's one check of each

    tl = _time_limit(time_limit)
    try:
        d = _strider.run_python(
            str(scenario),
            strategy,
            cost_model,
            _seed("seed", seed),
            _seed("world_seed", world_seed),
            tl,
            float(decision_period),
        )
    except Exception as e:
        partial = getattr(e, "strider_report", None)
        if isinstance(partial, dict):
            del e.strider_report
            e.report = _report(partial)
        raise
    return _report(d)


def _report(d: dict) -> Report:
    layers = d.pop("layers")
    return Report(d, layers)

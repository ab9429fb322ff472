"""Sweeps of missions as Ray tasks: ``strider bench compare`` and ``strider bench table5``
spread over a Ray cluster.

Every trial of a comparison is a pure function of scenario, strategy, world seed and mission
seed, so each runs as its own Ray task wherever Ray places it; the table is assembled from the
trials by the same code as the command's, so the result is ``compare.json`` of
``strider bench compare`` for the same options (only the trials' ``wall_s`` differ), and
likewise ``table5.json`` of ``strider bench table5`` (wall times and latencies differ).
"""

from __future__ import annotations

import json
import time
from typing import Any, Dict, Optional, Sequence

from . import _strider


def _options(scenarios, strategies, trials, world_seeds, time_limit) -> str:
    from . import _time_limit  # the package's one check

    if isinstance(scenarios, str) or isinstance(strategies, str):
        raise _strider.StriderError("scenarios and strategies: give lists of names")
    for name, v in (("trials", trials), ("world_seeds", world_seeds)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise _strider.StriderError(f"{name} {v!r}: must be an integer ≥ 1")
    return json.dumps(
        {
            "scenarios": [str(s) for s in scenarios],
            "strategies": [str(s) for s in strategies],
            "trials": trials,
            "world_seeds": world_seeds,
            "time_limit": _time_limit(time_limit),
        }
    )


def _trial(options: str, trial: str) -> str:
    # Imported in the Ray worker: the package must be installed where the task runs.
    from strider import _strider as native

    return native.compare_trial(options, trial)


def _table5_trial(options: str, index: int) -> str:
    from strider import _strider as native

    return native.table5_trial(options, index)


def _run_all(fn, options: str, tasks: list, ray_address: Optional[str], local: bool) -> list:
    """``fn(options, task)`` for every task: here one after another, or as Ray tasks."""
    if local:
        return [fn(options, t) for t in tasks]
    import ray

    if not ray.is_initialized():
        ray.init(address=ray_address)
    remote = ray.remote(num_cpus=1)(fn)
    return ray.get([remote.remote(options, t) for t in tasks])


def sweep(
    scenarios: Sequence[str] = ("courtyard-small", "lab-track"),
    strategies: Sequence[str] = ("gtsp", "greedy", "spatial-only", "rbcm-greedy"),
    trials: int = 5,
    world_seeds: int = 5,
    time_limit: Optional[float] = None,
    ray_address: Optional[str] = None,
    local: bool = False,
) -> Dict[str, Any]:
    """Runs ``strider bench compare`` for these options with every trial a Ray task (trial i
    of a cell: world seed 1 + (i mod world_seeds), mission seed 1 + i) and returns its
    ``compare.json`` as a dict. Uses the running Ray (``ray.init()`` or
    ``ray.init(address=…)`` beforehand), else starts one at ``ray_address``. ``local=True``
    runs the trials in this process instead, one after another, without Ray."""
    options = _options(scenarios, strategies, trials, world_seeds, time_limit)
    plan = json.loads(_strider.compare_plan(options))
    tasks = [json.dumps(t) for t in plan["trials"]]
    results = _run_all(_trial, options, tasks, ray_address, local)
    return json.loads(_strider.compare_assemble(options, results, plan["skipped"]))


def sweep_table5(
    trials: int = 25,
    large_trials: Optional[int] = None,
    world_seeds: int = 5,
    time_limit: Optional[float] = None,
    ray_address: Optional[str] = None,
    local: bool = False,
) -> Dict[str, Any]:
    """Runs ``strider bench table5`` (Prágr22 Table 5: ``trials`` per small-world row,
    ``large_trials`` per large-world row, default ``trials``) with every trial a Ray task and
    returns its ``table5.json`` as a dict; Ray and ``local`` as in :func:`sweep`."""
    from . import _time_limit

    large = trials if large_trials is None else large_trials
    for name, v, low in (("trials", trials, 1), ("large_trials", large, 0),
                         ("world_seeds", world_seeds, 1)):
        if isinstance(v, bool) or not isinstance(v, int) or v < low:
            raise _strider.StriderError(f"{name} {v!r}: must be an integer ≥ {low}")
    options = json.dumps({"trials": trials, "large_trials": large, "world_seeds": world_seeds,
                          "time_limit": _time_limit(time_limit)})
    wall = time.perf_counter()
    tasks = list(range(_strider.table5_plan(options)))
    results = _run_all(_table5_trial, options, tasks, ray_address, local)
    return json.loads(_strider.table5_assemble(options, results, time.perf_counter() - wall))

"""Strider from Python: the Rust crates' missions, maps, GPs and GTSP solver, numpy in and out.

>>> import strider
>>> r = strider.run("courtyard-small", "gtsp", seed=1, time_limit=120)
>>> r.exploration_time_s, r.layers["elevation"].shape

Every error of the library is raised as :class:`StriderError` (a ``ValueError``) with the
one-line message the ``strider`` command prints. See ``docs/python.md``.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

from . import _strider, gtsp
from ._strider import GP, RBCM, CostModel, StriderError
from .report import Report
from .strategy import run_python
from .sweep import sweep, sweep_table5

__all__ = [
    "GP",
    "RBCM",
    "CostModel",
    "ElevationMap",
    "Report",
    "StriderError",
    "gtsp",
    "replay",
    "run",
    "run_python",
    "scenario_layers",
    "scenarios",
    "strategies",
    "sweep",
    "sweep_table5",
]

PathLike = Union[str, "os.PathLike[str]"]
_U64 = 2**64


def _seed(name: str, v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < _U64:
        raise StriderError(f"{name} {v!r}: must be an integer in [0, 2^64)")
    return v


_MAX_TIME_LIMIT_S = 1e6


def _time_limit(v: Any) -> Optional[float]:
    """``time_limit`` checked where it enters: None (the scenario's) or simulated seconds."""
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise StriderError(f"time_limit {v!r}: must be a number of simulated seconds")
    t = float(v)
    if not (0.0 < t <= _MAX_TIME_LIMIT_S):  # also refuses NaN
        raise StriderError(
            f"time_limit {v!r}: must be a finite number of simulated seconds > 0 and ≤ 1e6"
        )
    return t


def _set_value(key: str, v: Any) -> str:
    """A parameter value as the text `--set key=value` takes."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float, str)):
        return str(v) if not isinstance(v, float) else repr(v)
    raise StriderError(f"params[{key!r}] = {v!r}: must be a bool, number or string")


def _sets(params: Optional[Mapping[str, Any]]) -> List[Tuple[str, str]]:
    if params is None:
        return []
    if not isinstance(params, Mapping):
        raise StriderError("params: expected a dict of strategy parameter names")
    return [(str(k), _set_value(str(k), v)) for k, v in params.items()]


def scenarios() -> List[str]:
    """The names of the built-in scenarios (``strider scenario list``)."""
    return [name for name, _ in _strider.scenarios()]


def strategies() -> List[Dict[str, str]]:
    """Every registered strategy: its name, paper key and summary (``strider strategies``)."""
    return [{"name": n, "paper": k, "summary": s} for n, k, s in _strider.strategies()]


def scenario_layers(scenario: str, world_seed: int = 1) -> Dict[str, Any]:
    """A scenario's world as numpy arrays: ``color`` (rows, cols, 3) uint8, ``elevation``
    float32 m, ``terrain`` uint8 index into ``terrains``, with ``cell_size`` and ``origin``
    (row 0 is the lowest y). ``scenario`` is a built-in name or a scenario file."""
    return _strider.scenario_layers(str(scenario), _seed("world_seed", world_seed))


def _run_in(out: Optional[PathLike], work) -> Any:
    """Runs ``work(dir)`` in ``out``, or in a temporary folder removed afterwards."""
    if out is not None:
        return work(os.fspath(out))
    tmp = tempfile.mkdtemp(prefix="strider-")
    try:
        return work(os.path.join(tmp, "run"))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def run(
    scenario: str = "courtyard-small",
    strategy: str = "gtsp",
    seed: int = 1,
    time_limit: Optional[float] = None,
    params: Optional[Mapping[str, Any]] = None,
    world_seed: int = 1,
    out: Optional[PathLike] = None,
) -> Report:
    """One mission, as ``strider run``: ``strategy`` explores ``scenario`` (a built-in name,
    with ``world_seed``, or a scenario file) with mission seed ``seed`` for at most
    ``time_limit`` simulated seconds (default: the scenario's), strategy parameters ``params``
    (as ``--set``; unknown names are an error). The report files are written to ``out``
    (default: a temporary folder, removed). Returns a :class:`Report`."""
    seed = _seed("seed", seed)
    world_seed = _seed("world_seed", world_seed)
    tl = _time_limit(time_limit)
    sets = _sets(params)

    def work(d: str) -> Report:
        (text, large), layers = _strider.run(
            str(scenario), str(strategy), seed, world_seed, tl, sets, d
        )
        return Report(json.loads(text), layers, lazy=dict(large))

    return _run_in(out, work)


def replay(mcap_path: PathLike, config: PathLike, out: Optional[PathLike] = None) -> Report:
    """A recorded MCAP log through the mission's mapping and learning, as ``strider replay``:
    ``config`` is the replay configuration file (TOML). Returns a :class:`Report` (without
    layers)."""
    log, cfg = os.fspath(mcap_path), os.fspath(config)
    return _run_in(out, lambda d: Report(json.loads(_strider.replay(log, cfg, d)), None))


class ElevationMap(_strider.ElevationMap):
    """The colored 2.5D elevation map on its own.

    ``ElevationMap(params=None, scenario=None, world_seed=1)``: the map parameters of
    ``scenario`` (or the defaults) updated by ``params`` (e.g. ``{"cell_size": 0.1}``; unknown
    names are an error). ``fuse(points, colors, pose)`` fuses N × 3 float32 points with N × 3
    uint8 colours seen from ``pose`` = (x, y, z[, yaw]); ``layers()`` returns numpy arrays.
    """

    def __new__(
        cls,
        params: Optional[Mapping[str, Any]] = None,
        scenario: Optional[str] = None,
        world_seed: int = 1,
    ):
        text = None if params is None else json.dumps(dict(params))
        return super().__new__(cls, text, scenario, _seed("world_seed", world_seed))

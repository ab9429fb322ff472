"""The generalized-TSP solver (``strider gtsp solve``): GTSPLIB/TSPLIB files or a cost matrix
with vertex sets. Tours are 0-based vertex indices (the command prints them 1-based, as in the
file)."""

from __future__ import annotations

import os
from typing import Optional, Sequence, Union

import numpy as np

from . import _strider
from ._strider import Instance, Solution, StriderError

__all__ = ["Instance", "Solution", "read", "solve"]


def read(path: Union[str, "os.PathLike[str]"]) -> Instance:
    """Reads a GTSPLIB (``.gtsp``) or TSPLIB (``.tsp``) file."""
    return _strider.read(os.fspath(path))


def solve(
    instance,
    sets: Optional[Sequence[Sequence[int]]] = None,
    seed: int = 1,
    time_limit: float = 60.0,
    mode: str = "default",
    target_cost: Optional[int] = None,
) -> Solution:
    """Solves an :class:`Instance` (from :func:`read`), or an n × n integer cost matrix with
    ``sets`` (lists of 0-based vertex indices; every vertex its own set when omitted), with the
    solver's ``seed``, wall-time limit ``time_limit`` s and ``mode`` (fast, default, slow).
    With ``target_cost`` the search stops as soon as a tour costing at most that is found
    (e.g. a known optimum). Returns a :class:`Solution` with ``.cost`` and ``.tour``."""
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**64:
        raise StriderError(f"seed {seed!r}: must be an integer in [0, 2^64)")
    if target_cost is not None and (
        isinstance(target_cost, bool)
        or not isinstance(target_cost, int)
        or not -(2**63) <= target_cost < 2**63
    ):
        raise StriderError(f"target_cost {target_cost!r}: must be an integer in [-2^63, 2^63)")
    if isinstance(instance, Instance):
        if sets is not None:
            raise StriderError("sets: an Instance has its own sets")
        return _strider.solve(instance, seed, float(time_limit), mode, target_cost)
    m = np.asarray(instance)
    if m.ndim != 2 or not np.issubdtype(m.dtype, np.integer):
        raise StriderError("the cost matrix must be a 2-D integer array")
    if sets is None:
        sets = [[v] for v in range(m.shape[0])]
    sets = [[int(v) for v in s] for s in sets]
    if any(v < 0 for s in sets for v in s):
        raise StriderError("sets: vertex indices must be ≥ 0")
    m = np.ascontiguousarray(m, dtype=np.int64)
    return _strider.solve_matrix(m, sets, seed, float(time_limit), mode, "matrix", target_cost)

"""The report of a mission: the fields of ``report.json`` as attributes, the map layers as
numpy arrays."""

from __future__ import annotations

import json
from typing import Any, Dict, Optional


class Report:
    """A mission's report.

    Every top-level field of ``report.json`` is an attribute (``r.exploration_time_s``,
    ``r.termination``, ``r.models``, …) and ``r.json`` is the whole document as a dict.
    ``r.layers`` holds the final map and model layers as numpy arrays (``elevation``,
    ``elevation_variance``, ``color``, ``observed``, ``passability`` and, per learned model,
    ``models[name]["cost"|"variance"|"measured"]`` and, for models with terrain classes,
    ``models[name]["classes"]``: the planning class of each cell, −1 for none), indexed ``[row, col]`` with row 0 the
    lowest y, with ``cell_size`` (m) and ``origin`` (the world x, y of the lower-left corner).
    """

    def __init__(
        self,
        fields: Dict[str, Any],
        layers: Optional[Dict[str, Any]],
        lazy: Optional[Dict[str, str]] = None,
    ):
        self._fields = fields
        # Large fields (a mission's tours) as JSON text, parsed when first read.
        self._lazy = dict(lazy or {})
        self.layers = layers

    def _field(self, name: str) -> Any:
        if name in self._lazy:
            self._fields[name] = json.loads(self._lazy.pop(name))
        return self._fields[name]

    @property
    def json(self) -> Dict[str, Any]:
        """The whole ``report.json`` as a dict."""
        for name in list(self._lazy):
            self._field(name)
        return self._fields

    def __getattr__(self, name: str) -> Any:
        # Only called for names that are not ordinary attributes: the report's fields.
        d = self.__dict__
        if name in d.get("_fields", {}) or name in d.get("_lazy", {}):
            return self._field(name)
        raise AttributeError(f"the report has no field {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._fields) | set(self._lazy))

    @property
    def cell_size(self) -> Optional[float]:
        """The map's cell size, m."""
        return None if self.layers is None else self.layers["cell_size"]

    @property
    def origin(self):
        """The world (x, y) of the lower-left corner of layer cell [0, 0], m."""
        return None if self.layers is None else self.layers["origin"]

    def __repr__(self) -> str:
        keys = ("scenario", "strategy", "seed", "termination", "exploration_time_s")
        inner = ", ".join(f"{k}={self._fields[k]!r}" for k in keys if k in self._fields)
        return f"Report({inner})"

"""The report of a mission: the fields of ``report.json`` as attributes, the map layers as
numpy arrays."""

from __future__ import annotations

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

    def __init__(self, fields: Dict[str, Any], layers: Optional[Dict[str, Any]]):
        self.json = fields
        self.layers = layers

    def __getattr__(self, name: str) -> Any:
        # Only called for names that are not ordinary attributes: the report's fields.
        fields = self.__dict__.get("json", {})
        if name in fields:
            return fields[name]
        raise AttributeError(f"the report has no field {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.json))

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
        inner = ", ".join(f"{k}={self.json[k]!r}" for k in keys if k in self.json)
        return f"Report({inner})"

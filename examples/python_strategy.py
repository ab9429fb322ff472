"""An exploration strategy written in Python: drive to the nearest frontier.

A frontier cell is an unobserved cell next to an observed passable one; the robot drives to the
nearest one at least `min_dist` away and keeps it until it is reached, seen, or stale. With a
cost model (see python_cost_model.py), frontiers next to cells predicted expensive are
avoided. Run: python examples/python_strategy.py [time_limit]
"""

import sys

import numpy as np

import strider


class NearestFrontier:
    def __init__(self, min_dist=0.4, cost_weight=1.0, patience=8):
        self.min_dist = min_dist
        self.cost_weight = cost_weight
        self.patience = patience
        self.goal = None
        self.age = 0

    def decide(self, snap):
        L = snap["layers"]
        obs, pas = L["observed"], L["passability"]
        if obs.size == 0 or "pose" not in snap:
            return None
        x, y, _ = snap["pose"]
        if self.goal is not None:
            self.age += 1
            if self.age < self.patience and np.hypot(self.goal[0] - x, self.goal[1] - y) > 0.2:
                return None
        free = obs & (pas == 1)
        near = np.zeros_like(free)
        near[1:, :] |= free[:-1, :]
        near[:-1, :] |= free[1:, :]
        near[:, 1:] |= free[:, :-1]
        near[:, :-1] |= free[:, 1:]
        frontier = near & ~obs
        # Cells at the layers' edge have unmapped neighbours beyond it: frontiers too.
        edge = np.zeros_like(free)
        edge[[0, -1], :] = True
        edge[:, [0, -1]] = True
        frontier |= free & edge
        rows, cols = np.nonzero(frontier)
        if rows.size == 0:
            return {"done": True}
        cs, (ox, oy) = L["cell_size"], L["origin"]
        gx, gy = ox + (cols + 0.5) * cs, oy + (rows + 0.5) * cs
        score = np.hypot(gx - x, gy - y)
        score[score < self.min_dist] = np.inf
        if "cost" in snap:
            # A frontier cell is unobserved: it takes the dearest prediction of its neighbours.
            c = np.nan_to_num(snap["cost"], nan=0.0)
            nb = c.copy()
            nb[1:, :] = np.maximum(nb[1:, :], c[:-1, :])
            nb[:-1, :] = np.maximum(nb[:-1, :], c[1:, :])
            nb[:, 1:] = np.maximum(nb[:, 1:], c[:, :-1])
            nb[:, :-1] = np.maximum(nb[:, :-1], c[:, 1:])
            score = score + self.cost_weight * nb[rows, cols]
        k = int(np.argmin(score))
        if not np.isfinite(score[k]):
            return {"done": True}
        self.goal, self.age = (float(gx[k]), float(gy[k])), 0
        return {"goal": self.goal}


def main(time_limit=60.0):
    r = strider.run_python(NearestFrontier(), "courtyard-small", seed=1, time_limit=time_limit)
    print(f"{r.termination} after {r.exploration_time_s:.0f} s simulated, {r.driven_m:.1f} m driven, "
          f"{r.observed_cells} cells observed, {r.decisions} decisions, "
          f"{1e3 * r.python_s / max(r.decisions, 1):.2f} ms per decision in Python")
    return r


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 60.0)

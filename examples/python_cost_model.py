"""A traversal-cost model written in Python, learning inside the Rust mission loop.

One GP per gait (strider.GP here; any regressor with the same two methods works, e.g. a PyTorch
module) on the Prágr19 shape + Lab descriptors of the cells the robot crossed, with the
inverse-velocity cost the kernel measured there. The frontier strategy of python_strategy.py
uses its predictions to avoid frontiers next to expensive terrain.
Run: python examples/python_cost_model.py [time_limit]
"""

import os
import sys

import numpy as np

import strider

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from python_strategy import NearestFrontier  # noqa: E402


class PerGaitGP:
    """update(descriptors, costs, gaits) and predict(descriptors) -> (mean, variance)."""

    def __init__(self, max_points=300, prior_cost=1.0):
        self.max_points = max_points
        self.prior_cost = prior_cost
        self.data = {}
        self.gps = {}
        self.updates = 0

    def update(self, descriptors, costs, gaits):
        self.updates += 1
        for g in np.unique(gaits):
            x, y = descriptors[gaits == g], costs[gaits == g]
            X, Y = self.data.get(int(g), (np.empty((0, x.shape[1])), np.empty(0)))
            X, Y = np.vstack([X, x])[-self.max_points:], np.concatenate([Y, y])[-self.max_points:]
            self.data[int(g)] = (X, Y)
            # Costs are modelled around the prior cost of 1 (the fastest gait at full speed).
            self.gps[int(g)] = strider.GP(lengthscale=0.4, noise_variance=0.25).fit(X, Y - self.prior_cost)

    def predict(self, descriptors):
        n = descriptors.shape[0]
        if not self.gps or n == 0:
            return np.full(n, self.prior_cost), np.ones(n)
        means, variances = zip(*(gp.predict(descriptors) for gp in self.gps.values()))
        # The cheapest gait's prediction: the robot would choose that gait there.
        k = np.argmin(np.stack(means), axis=0)
        mean = np.take_along_axis(np.stack(means), k[None], 0)[0] + self.prior_cost
        var = np.take_along_axis(np.stack(variances), k[None], 0)[0]
        return mean, var


def main(time_limit=60.0):
    model = PerGaitGP()
    r = strider.run_python(NearestFrontier(), "courtyard-small", cost_model=model, seed=1,
                           time_limit=time_limit)
    print(f"{r.termination} after {r.exploration_time_s:.0f} s simulated: {r.cost_samples} cost samples "
          f"learned in {model.updates} updates, {r.decisions} decisions, "
          f"{1e3 * r.python_s / max(r.decisions, 1):.2f} ms per decision in Python")
    return r, model


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 60.0)

"""Type stubs of the native module (the Rust crate strider-py)."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike]

class StriderError(ValueError):
    """An error of the Strider library, with the one-line message the command prints."""

def scenarios() -> List[Tuple[str, str]]: ...
def strategies() -> List[Tuple[str, str, str]]: ...
def scenario_layers(scenario: str, world_seed: int = 1) -> Dict[str, Any]: ...
def run(
    scenario: str,
    strategy: str,
    seed: int,
    world_seed: int,
    time_limit: Optional[float],
    sets: List[Tuple[str, str]],
    out: _Path,
) -> Tuple[Tuple[str, List[Tuple[str, str]]], Dict[str, Any]]: ...
def replay(log: _Path, config: _Path, out: _Path) -> str: ...
def run_python(
    scenario: str,
    strategy: Any,
    model: Any,
    seed: int,
    world_seed: int,
    time_limit: Optional[float],
    decision_period: float,
) -> Dict[str, Any]: ...
def read(path: _Path) -> Instance: ...
def solve(
    instance: Instance,
    seed: int = 1,
    time_limit: float = 60.0,
    mode: str = "default",
    target_cost: Optional[int] = None,
) -> Solution: ...
def solve_matrix(
    matrix: npt.NDArray[np.int64],
    sets: Sequence[Sequence[int]],
    seed: int = 1,
    time_limit: float = 60.0,
    mode: str = "default",
    name: str = "matrix",
    target_cost: Optional[int] = None,
) -> Solution: ...
def compare_plan(options_json: str) -> str: ...
def compare_trial(options_json: str, trial_json: str) -> str: ...
def compare_assemble(options_json: str, trials_json: List[str], skipped: List[Tuple[str, str, str]]) -> str: ...
def table5_plan(options_json: str) -> int: ...
def table5_trial(options_json: str, index: int) -> str: ...
def table5_assemble(options_json: str, trials_json: List[str], wall_s: float) -> str: ...

class GP:
    """Exact GP regression with an isotropic kernel (se, exp, matern32, matern52)."""

    def __init__(
        self,
        kernel: str = "se",
        lengthscale: float = 0.4,
        signal_variance: float = 1.0,
        noise_variance: float = 0.25,
        prior_mean: float = 0.0,
    ) -> None: ...
    def fit(self, x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> "GP":
        """Conditions on the rows of X (n × d) and targets y (n); replaces earlier data."""
    def predict(self, q: npt.NDArray[np.float64]) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Mean and latent variance (without noise) at the rows of Q."""
    def add_point(self, x: Sequence[float], y: float) -> None: ...
    def remove_point(self, index: int) -> None: ...
    def fit_hyperparameters(self) -> None:
        """Maximises the log marginal likelihood over lengthscale, signal and noise variance."""
    def log_marginal_likelihood(self) -> float: ...
    def __len__(self) -> int: ...
    @property
    def lengthscale(self) -> float: ...
    @property
    def signal_variance(self) -> float: ...
    @property
    def noise_variance(self) -> float: ...

class RBCM:
    """The robust Bayesian committee machine of GP experts (Prágr19 Eq. 7–9)."""

    def __init__(
        self,
        dim: int,
        kernel: str = "se",
        lengthscale: float = 0.4,
        signal_variance: float = 1.0,
        noise_variance: float = 0.25,
        prior_mean: float = 0.0,
        m_max: int = 50,
        m_min: int = 25,
        variant: str = "robust",
        fit_experts: bool = False,
    ) -> None: ...
    def add(self, x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> "RBCM":
        """Adds the rows of X (n × dim) with targets y in order; experts fill m_max points each."""
    def predict(self, q: npt.NDArray[np.float64]) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The committee's mean and latent variance at the rows of Q."""
    def __len__(self) -> int: ...
    @property
    def experts(self) -> Tuple[int, int]:
        """(experts, experts taking part in predictions)."""

class CostModel:
    """The traversal cost model of one gait over an ElevationMap (Prágr22, IGNG classes)."""

    def __init__(
        self,
        map: "ElevationMap",
        gait: int = 0,
        seed: int = 1,
        lengthscale: float = 0.4,
        signal_variance: float = 1.0,
        noise_variance: float = 0.25,
        prior_mean: float = 1.0,
        c_max: float = 20.0,
    ) -> None: ...
    def measure(self, x: float, y: float, cost: float) -> bool:
        """Fuses a cost measured at (x, y) when it is novel; returns whether it was stored."""
    def update(self) -> Dict[str, Any]:
        """Relearns regressor and classes; returns classes, h_gt, goals and pruned classes."""
    def costs(self) -> npt.NDArray[np.float32]:
        """Planning cost per cell of the map's layers rectangle."""
    def classes(self) -> npt.NDArray[np.int32]:
        """Planning terrain class per cell of the map's layers rectangle, −1 for none."""
    def predict(self, d: npt.NDArray[np.float64]) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The regressor's mean and latent variance at 9-bin colour histograms (n × 9)."""
    @property
    def measured_cells(self) -> int: ...
    @property
    def learning_set(self) -> int: ...

class Instance:
    """A GTSP instance: n vertices, 0-based vertex sets, an integer cost matrix."""

    name: str
    n: int
    sets: List[List[int]]
    symmetric: bool
    def matrix(self) -> npt.NDArray[np.int64]: ...

class Solution:
    """A GTSP tour: one 0-based vertex per set in visiting order, and its cost."""

    cost: int
    tour: List[int]
    time_s: float
    optimal: bool

class ElevationMap:
    """The colored 2.5D elevation map (see strider.ElevationMap)."""

    def __init__(self, params_json: Optional[str] = None, scenario: Optional[str] = None, world_seed: int = 1) -> None: ...
    def fuse(
        self,
        points: npt.NDArray[np.float32],
        colors: npt.NDArray[np.uint8],
        pose: Sequence[float],
        world_frame: bool = False,
    ) -> Dict[str, int]: ...
    def layers(self) -> Dict[str, Any]: ...
    @property
    def observed_cells(self) -> int: ...
    @property
    def cell_size(self) -> float: ...

#!/usr/bin/env python3
"""Strider's exact GP (`strider gp predict`) against scikit-learn's GaussianProcessRegressor.

For n = 500, 2000, 4000 training points in d = 9 (Dirichlet-distributed, like the 9-colour
histogram descriptor), y = a smooth function + N(0, 0.5^2) noise, and 10 000 query points (fixed
seed), both fit a GP with the same fixed hyperparameters (SE kernel, l = 0.4, sigma_s^2 = 1,
sigma_n^2 = 0.25, prior mean 0) and predict the mean and the latent variance. Printed per n:
the largest absolute and relative differences of mean and variance, and fit+predict wall time
of each, measured inside each process (Strider: `--timing-json`, around `Gp::fit` and
`Gp::predict_batch`; sklearn: around `fit` and `predict(return_std=True)`), so neither includes
reading or writing files.

Relative difference: max_i |a_i - b_i| / max(|b_i|, floor), with floor = 1e-12 (b = sklearn).

If ``import sklearn`` fails, a venv is created at ``--venv`` (default ``bench/.venv``),
scikit-learn and numpy are pip-installed there and the script re-executes itself with it.

    python3 bench/gp_vs_sklearn.py [--sizes 500,2000,4000] [--queries 10000] [--seed 1]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
REEXEC_MARKER = "STRIDER_GP_BENCH_REEXEC"

LENGTHSCALE = 0.4
SIGNAL_VARIANCE = 1.0
NOISE_VARIANCE = 0.25
DIM = 9


def ensure_sklearn(venv: Path) -> None:
    """Make ``import sklearn`` work, re-executing inside ``venv`` if needed."""
    try:
        import numpy  # noqa: F401
        import sklearn  # noqa: F401

        return
    except ImportError:
        pass
    if os.environ.get(REEXEC_MARKER):
        sys.exit(f"error: scikit-learn still not importable inside {venv}")
    python = venv / "bin" / "python"
    if not python.exists():
        print(f"# creating venv {venv}", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    probe = subprocess.run([str(python), "-c", "import sklearn, numpy"], capture_output=True)
    if probe.returncode != 0:
        print(f"# installing scikit-learn and numpy into {venv}", file=sys.stderr)
        subprocess.run(
            [str(python), "-m", "pip", "install", "-q", "scikit-learn", "numpy"], check=True
        )
    env = dict(os.environ, **{REEXEC_MARKER: "1"})
    os.execve(str(python), [str(python), str(Path(__file__).resolve()), *sys.argv[1:]], env)


def build_strider() -> Path:
    subprocess.run(
        ["cargo", "build", "--release", "-p", "strider-cli"], cwd=REPO, check=True
    )
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    if not target.is_absolute():
        target = REPO / target
    exe = target / "release" / "strider"
    if not exe.exists():
        sys.exit(f"error: {exe} not found after the build")
    return exe


def make_data(n: int, q: int, seed: int):
    import numpy as np

    rng = np.random.default_rng(seed)
    x = rng.dirichlet(np.ones(DIM), size=n)
    xq = rng.dirichlet(np.ones(DIM), size=q)

    def f(z):
        return np.sin(2 * np.pi * z[:, 0]) + 2.0 * z[:, 1] * z[:, 2] + np.cos(3.0 * z[:, 3])

    y = f(x) + rng.normal(0.0, NOISE_VARIANCE**0.5, size=n)
    return x, y, xq


def run_strider(exe: Path, x, y, xq, work: Path):
    import numpy as np

    train, query = work / "train.csv", work / "query.csv"
    out, timing = work / "pred.csv", work / "timing.json"
    header = ",".join(f"h{k}" for k in range(DIM))
    np.savetxt(train, np.column_stack([x, y]), delimiter=",", fmt="%.17g",
               header=header + ",y", comments="")
    np.savetxt(query, xq, delimiter=",", fmt="%.17g", header=header, comments="")
    subprocess.run(
        [str(exe), "gp", "predict", "--train", str(train), "--query", str(query),
         "--kernel", "se", "--lengthscale", repr(LENGTHSCALE),
         "--signal-variance", repr(SIGNAL_VARIANCE), "--noise-variance", repr(NOISE_VARIANCE),
         "--prior-mean", "0", "--out", str(out), "--timing-json", str(timing)],
        check=True,
    )
    pred = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    t = json.loads(timing.read_text())
    return pred[:, 0], pred[:, 1], t["fit_s"] + t["predict_s"]


def run_sklearn(x, y, xq):
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel

    gpr = GaussianProcessRegressor(
        kernel=ConstantKernel(SIGNAL_VARIANCE, "fixed") * RBF(LENGTHSCALE, "fixed"),
        alpha=NOISE_VARIANCE,
        optimizer=None,
        normalize_y=False,
    )
    t0 = time.perf_counter()
    gpr.fit(x, y)
    mean, std = gpr.predict(xq, return_std=True)
    return mean, std**2, time.perf_counter() - t0


def rel(a, b, floor=1e-12):
    import numpy as np

    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), floor)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="500,2000,4000")
    ap.add_argument("--queries", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--venv", type=Path, default=REPO / "bench" / ".venv")
    args = ap.parse_args()
    ensure_sklearn(args.venv)
    import numpy as np

    exe = build_strider()
    print(f"# d={DIM} queries={args.queries} SE l={LENGTHSCALE} s2={SIGNAL_VARIANCE} "
          f"noise={NOISE_VARIANCE} seed={args.seed} cpus={os.cpu_count()}")
    print(f"{'n':>5} {'max|dmu|':>10} {'rel dmu':>10} {'max|dvar|':>10} {'rel dvar':>10} "
          f"{'strider_s':>10} {'sklearn_s':>10} {'ratio':>6}")
    worst = 0.0
    for n in (int(s) for s in args.sizes.split(",")):
        x, y, xq = make_data(n, args.queries, args.seed + n)
        with tempfile.TemporaryDirectory(prefix="strider-gp-bench-") as d:
            ms, vs, ts = run_strider(exe, x, y, xq, Path(d))
        mk, vk, tk = run_sklearn(x, y, xq)
        rm, rv = rel(ms, mk), rel(vs, vk)
        worst = max(worst, rm, rv)
        print(f"{n:>5} {np.max(np.abs(ms - mk)):>10.3e} {rm:>10.3e} "
              f"{np.max(np.abs(vs - vk)):>10.3e} {rv:>10.3e} {ts:>10.3f} {tk:>10.3f} "
              f"{tk / ts:>6.2f}", flush=True)
    print(f"# worst relative difference {worst:.3e} ({'ok' if worst <= 1e-6 else 'ABOVE 1e-6'})")


if __name__ == "__main__":
    main()

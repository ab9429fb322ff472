"""What driving Strider from Python costs: the wall time of one mission run by `strider.run`
against the same mission run by the `strider` command, and a Python strategy's overhead per
decision. Prints figures; asserts nothing (timings depend on the machine).

  python bench/python_overhead.py --strider target/release/strider [--repeats 5] [--time-limit 120]

Build both from the same tree and profile: `cargo build --release -p strider-cli` and
`pip install ./python` (release by default).
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import strider

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from python_strategy import NearestFrontier  # noqa: E402


class Idle:
    """Decides nothing: the cost of the snapshot handed to Python and of the call itself."""

    def decide(self, snap):
        return None


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--strider", required=True, help="the strider binary")
    ap.add_argument("--scenario", default="courtyard-small")
    ap.add_argument("--strategy", default="gtsp")
    ap.add_argument("--time-limit", type=float, default=120.0)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    cli, py = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(a.repeats):
            # Alternate, so that a drift of the machine's speed hits both alike.
            out = os.path.join(tmp, f"cli{i}")
            cmd = [a.strider, "run", "--scenario", a.scenario, "--strategy", a.strategy,
                   "--seed", "1", "--time-limit", str(a.time_limit), "--out", out]
            cli.append(timed(lambda: subprocess.run(cmd, check=True, capture_output=True)))
            out = os.path.join(tmp, f"py{i}")
            py.append(timed(lambda: strider.run(a.scenario, a.strategy, seed=1,
                                                time_limit=a.time_limit, out=out)))
    mc, mp = statistics.median(cli), statistics.median(py)
    print(f"{a.scenario} / {a.strategy}, {a.time_limit:.0f} s simulated, {a.repeats} runs each:")
    print(f"  strider run (command)  median {mc:.3f} s  [{min(cli):.3f}-{max(cli):.3f}]")
    print(f"  strider.run (Python)   median {mp:.3f} s  [{min(py):.3f}-{max(py):.3f}]")
    print(f"  Python over command: {100 * (mp / mc - 1):+.1f} % wall time")
    for name, strategy in (("idle", Idle()), ("nearest-frontier", NearestFrontier())):
        r = strider.run_python(strategy, a.scenario, seed=1, time_limit=a.time_limit)
        per = 1e3 * r.python_s / max(r.decisions, 1)
        print(f"  Python strategy {name}: {r.decisions} decisions, {per:.2f} ms each "
              f"(snapshot to numpy + decide), {100 * r.python_s / r.mission_wall_s:.1f} % of "
              f"the mission's {r.mission_wall_s:.2f} s wall")


if __name__ == "__main__":
    main()

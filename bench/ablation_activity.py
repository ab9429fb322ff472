#!/usr/bin/env python3
"""Prágr22 ablations: where the robot's time goes under each combination of our design choices.

Runs `strider run` for each configuration (default; look-around, goal commitment or stuck
windows as samples switched off; all three off), each exploration strategy and each mission
seed on `courtyard-small` (gtsp, greedy) and `courtyard-large` (gtsp, spatial-only), and
prints, per configuration, world and strategy, the mean exploration time and the mean robot
time per activity (`activity_s` of report.json) as a markdown table.

    cargo build --release -p strider-cli
    python3 bench/ablation_activity.py --strider target/release/strider \\
        --small-trials 10 --large-trials 5 --world-seeds 5

Trial k (1-based) runs mission seed k on world seed (k - 1) mod W + 1, as `strider bench
table5` does.
"""

import argparse
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

CONFIGS = [
    ("default", []),
    ("no look-around", ["look_around=false"]),
    ("no commitment", ["commit_to_goal=false"]),
    ("no stuck samples", ["stuck_windows_as_samples=false"]),
    ("none of the three", ["look_around=false", "commit_to_goal=false",
                           "stuck_windows_as_samples=false"]),
]
WORLDS = [("courtyard-small", ["gtsp", "greedy"]), ("courtyard-large", ["gtsp", "spatial-only"])]
ACTIVITIES = ["driving", "turning", "look_around", "sampling", "stuck_reflex", "waiting"]


def run_one(strider, scenario, strategy, world, seed, sets):
    with tempfile.TemporaryDirectory() as out:
        cmd = [strider, "run", "--scenario", scenario, "--strategy", strategy,
               "--world-seed", str(world), "--seed", str(seed), "--out", out]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        r = json.loads((Path(out) / "report.json").read_text())
    return r["exploration_time_s"], r["activity_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--strider", default="target/release/strider")
    ap.add_argument("--small-trials", type=int, default=10)
    ap.add_argument("--large-trials", type=int, default=5)
    ap.add_argument("--world-seeds", type=int, default=5)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--configs", default=",".join(str(k) for k in range(len(CONFIGS))),
                    help="which configurations, as indices into the list above (default: all)")
    ap.add_argument("--worlds", default="courtyard-small,courtyard-large")
    a = ap.parse_args()
    chosen = [CONFIGS[int(k)] for k in a.configs.split(",")]
    worlds = [w for w in WORLDS if w[0] in a.worlds.split(",")]
    jobs = []
    for name, sets in chosen:
        for scenario, strategies in worlds:
            n = a.small_trials if scenario == "courtyard-small" else a.large_trials
            for strategy in strategies:
                for k in range(1, n + 1):
                    world = (k - 1) % a.world_seeds + 1
                    jobs.append((name, scenario, strategy, world, k, sets))
    with ThreadPoolExecutor(a.jobs) as pool:
        results = list(pool.map(lambda j: run_one(a.strider, *j[1:]), jobs))
    rows = {}
    for (name, scenario, strategy, *_), (t, act) in zip(jobs, results):
        rows.setdefault((name, scenario, strategy), []).append((t, act))
    print(f"`python3 bench/ablation_activity.py --small-trials {a.small_trials} "
          f"--large-trials {a.large_trials} --world-seeds {a.world_seeds} --configs {a.configs} "
          f"--worlds {a.worlds}`; mean robot time per activity, simulated seconds.\n")
    print("| configuration | world | strategy | runs | exploration s | "
          + " | ".join(x.replace("_", " ") for x in ACTIVITIES) + " |")
    print("|" + "---|" * (5 + len(ACTIVITIES)))
    for (name, scenario, strategy), rs in rows.items():
        mean = lambda f: sum(f(r) for r in rs) / len(rs)
        cells = [f"{mean(lambda r, x=x: r[1][x]):.0f}" for x in ACTIVITIES]
        print(f"| {name} | {scenario} | {strategy} | {len(rs)} | {mean(lambda r: r[0]):.0f} | "
              + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

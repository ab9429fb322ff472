#!/usr/bin/env python3
"""`003` repeated tours over the energy-arena world family.

``strider tours --seeds K`` varies the simulator's noise on one world; this script varies the
world: it runs ``strider tours --world-seed W --seed S`` for W = 1..N and prints one markdown
row per world (tour 1, converged tour, drop from tour 1 and against the always-shortest mean,
convergence and overtaking tours, and the drop of the tour planned on the true costs, which
bounds what learning can gain on that world), then the acceptance counts.

Usage (from the repository root)::

    cargo build --release -p strider-cli
    python3 bench/tours_worlds.py --worlds 10 --out out/tours-worlds

Only the standard library is used.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worlds", type=int, default=10, help="world seeds 1..N")
    ap.add_argument("--seed", type=int, default=1, help="noise seed of every run")
    ap.add_argument("--scenario", default="energy-arena")
    ap.add_argument("--bin", default="target/release/strider", help="the strider binary")
    ap.add_argument("--out", default="out/tours-worlds")
    a = ap.parse_args()
    out = Path(a.out)
    rows = []
    for w in range(1, a.worlds + 1):
        d = out / f"world-{w}"
        cmd = [a.bin, "tours", "-s", a.scenario, "--world-seed", str(w), "--seed", str(a.seed),
               "--out", str(d)]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            print(f"world {w}: {r.stderr.strip()}", file=sys.stderr)
            return 1
        rows.append((w, json.loads((d / "tours.json").read_text())["summary"]))

    def fmt(v):
        return "never" if v is None else str(v)

    print("| world | tour 1 J | converged J | drop from tour 1 | below always-shortest "
          "| convergence tour | overtakes at | true-cost tour below always-shortest |")
    print("|---|---|---|---|---|---|---|---|")
    for w, s in rows:
        print(f"| {w} | {s['first_tour_j']:.1f} | {s['converged_j']:.1f} | {100 * s['drop']:.1f} % "
              f"| {100 * s['drop_vs_always_shortest']:.1f} % | {fmt(s['convergence_tour'])} "
              f"| {fmt(s['overtaking_tour'])} | {100 * s['known_costs_drop']:.1f} % |")
    print()
    n = len(rows)
    for key in ("first_tour_is_shortest", "drop_at_least_30_percent", "converged_within_10_tours",
                "overtakes_before_tour_10"):
        k = sum(1 for _, s in rows if s["acceptance"][key])
        print(f"{key}: {k} of {n}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

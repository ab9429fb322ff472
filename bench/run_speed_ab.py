#!/usr/bin/env python3
"""Compare the mission speed of two `strider` binaries by interleaved runs.

On a shared 2-core machine the speed drifts by up to a quarter within minutes, so two
binaries are only comparable when their runs alternate. Each round runs A then B (the order
flips every round) on the same `strider run` arguments and reads `report.json`: the speed-up
over real time (`exploration_time_s / mission wall`) and the wall time per part of the loop
(`phase_wall_s`). A round whose two runs simulate different times (the binaries do not run
the same mission) is flagged. Standard library only.

    python3 bench/run_speed_ab.py OLD_BIN NEW_BIN --rounds 5 -- --scenario courtyard-small
"""

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def run(binary: str, args: list[str], out: Path) -> dict:
    cmd = [binary, "run", *args, "--out", str(out)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.loads((out / "report.json").read_text())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a", help="first binary (e.g. the baseline)")
    ap.add_argument("b", help="second binary")
    ap.add_argument("--rounds", type=int, default=5)
    ap.epilog = "Arguments after `--` go to `strider run`."
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    opt = ap.parse_args(argv[:cut])
    args = argv[cut + 1 :]
    speed = {"a": [], "b": []}
    phases = {"a": [], "b": []}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(opt.rounds):
            order = ["a", "b"] if r % 2 == 0 else ["b", "a"]
            times = {}
            for k in order:
                rep = run(getattr(opt, k), args, Path(tmp) / k)
                times[k] = rep["exploration_time_s"]
                speed[k].append(rep["speedup"])
                phases[k].append(rep["phase_wall_s"])
                print(f"round {r + 1} {k}: {rep['speedup']:.0f}x real time, "
                      f"{rep['mission_wall_s']:.2f} s mission wall", flush=True)
            if abs(times["a"] - times["b"]) > 1e-6:
                print(f"warning: the binaries ran different missions ({times['a']:.1f} s vs "
                      f"{times['b']:.1f} s simulated); speed-ups compare unequal work",
                      file=sys.stderr)
    for k in "ab":
        s = speed[k]
        print(f"{k}: speed-up median {statistics.median(s):.0f}x, range {min(s):.0f}-{max(s):.0f}x")
        for part in phases[k][0]:
            vals = [p[part] for p in phases[k]]
            print(f"    {part:9s} median {statistics.median(vals):6.2f} s")
    ratio = [b / a for a, b in zip(speed["a"], speed["b"])]
    print(f"b/a speed-up per round: median {statistics.median(ratio):.3f}, "
          f"range {min(ratio):.3f}-{max(ratio):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

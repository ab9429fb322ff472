#!/usr/bin/env python3
"""Replay speed of `strider replay` on a real log, and whether two binaries learn the same.

Runs `strider replay LOG --config CONFIG` for `--rounds` rounds and prints, per binary, the
speed-up of the mission loop over the log's duration (`speedup` of `report.json`: log seconds
per second of mapping and learning, reading and decoding the file excluded) with its median
and range, and the median wall time per part of the loop (`phase_wall_s`). With two binaries
the runs alternate (A B, B A, ...) because this machine's speed drifts within minutes, and the
script checks that both produce the same result: `report.json` equal outside its timing
fields, and every figure (maps, classes, predicted and measured costs) byte for byte.
Standard library only.

    python3 bench/replay_speed.py LOG.mcap --config replay.toml BIN [BIN2] --rounds 5
"""

import argparse
import filecmp
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

# Fields that measure the machine, not the replay.
TIMING = {"phase_wall_s", "mission_wall_s", "speedup", "wall_time_s", "goal_identification_ms"}


def replay(binary: str, log: str, config: str, out: Path) -> dict:
    cmd = [binary, "replay", log, "--config", config, "--out", str(out)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.loads((out / "report.json").read_text())


def differences(a: dict, b: dict, da: Path, db: Path) -> list[str]:
    """What differs between two replays' results, timing aside."""
    out = [k for k in sorted(set(a) | set(b)) if k not in TIMING and a.get(k) != b.get(k)]
    for png in sorted(p.name for p in da.glob("*.png")):
        if not (db / png).exists() or not filecmp.cmp(da / png, db / png, shallow=False):
            out.append(png)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log", help="the MCAP log")
    ap.add_argument("--config", required=True, help="the replay configuration (TOML)")
    ap.add_argument("binaries", nargs="+", help="one or two strider binaries")
    ap.add_argument("--rounds", type=int, default=5)
    opt = ap.parse_args()
    if len(opt.binaries) > 2:
        ap.error("give one or two binaries")
    names = [chr(ord("a") + i) for i in range(len(opt.binaries))]
    speed = {k: [] for k in names}
    phases = {k: [] for k in names}
    mismatches = 0
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(opt.rounds):
            order = names if r % 2 == 0 else names[::-1]
            reports = {}
            for k in order:
                out = Path(tmp) / f"{k}{r}"
                rep = replay(opt.binaries[names.index(k)], opt.log, opt.config, out)
                reports[k] = (rep, out)
                speed[k].append(rep["speedup"])
                phases[k].append(rep["phase_wall_s"])
                print(f"round {r + 1} {k}: {rep['speedup']:.0f}x real time, "
                      f"{rep['mission_wall_s']:.2f} s mission loop for "
                      f"{rep['log_duration_s']:.0f} s of log", flush=True)
            if len(names) == 2:
                (ra, da), (rb, db) = reports["a"], reports["b"]
                diff = differences(ra, rb, da, db)
                if diff:
                    mismatches += 1
                    print(f"round {r + 1}: results differ in {', '.join(diff)}", file=sys.stderr)
    for k in names:
        s = speed[k]
        print(f"{k} ({opt.binaries[names.index(k)]}): speed-up median {statistics.median(s):.0f}x, "
              f"range {min(s):.0f}-{max(s):.0f}x")
        for part in phases[k][0]:
            vals = [p[part] for p in phases[k]]
            if max(vals) > 0:
                print(f"    {part}: median {statistics.median(vals):.3f} s")
    if len(names) == 2:
        ratios = [b / a for a, b in zip(speed["a"], speed["b"])]
        print(f"b/a speed-up per round: {', '.join(f'{x:.2f}' for x in ratios)}")
        print("results identical in every round" if mismatches == 0
              else f"results differ in {mismatches} of {opt.rounds} rounds")
    return 1 if mismatches else 0


if __name__ == "__main__":
    sys.exit(main())

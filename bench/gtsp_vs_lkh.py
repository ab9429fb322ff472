#!/usr/bin/env python3
"""Strider's GTSP solver against the Noon-Bean + LKH route (via elkai).

Both solvers get the same GTSPLIB instances and the same wall-clock budget:

* **lkh**: the instance is turned into an asymmetric TSP by the Noon-Bean
  transform and solved with LKH through the ``elkai`` package. The g-tour is
  read off the ATSP tour and its cost is recomputed from the *original*
  distances (the transformed cost is never trusted).
* **strider**: ``strider gtsp solve FILE --time-limit S --seed N --json``.
  Its tour is also checked (one vertex per set) and its cost recomputed.

Usage (from the repository root)::

    python3 bench/gtsp_vs_lkh.py --only 11berlin52,20kroA100 --time-limit 5

If ``import elkai`` fails, a venv is created at ``--venv`` (default
``bench/.venv``), ``elkai`` is pip-installed there and the script re-executes
itself with that interpreter. Only the standard library and elkai are used.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import multiprocessing as mp
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
REEXEC_MARKER = "GTSP_VS_LKH_IN_VENV"
SECTIONS = {
    "NODE_COORD_SECTION",
    "EDGE_WEIGHT_SECTION",
    "GTSP_SET_SECTION",
    "DISPLAY_DATA_SECTION",
    "EOF",
}


# --------------------------------------------------------------------------
# environment


def ensure_elkai(venv: Path) -> None:
    """Make ``import elkai`` work, re-executing inside ``venv`` if needed.

    If elkai is importable nothing happens. Otherwise the venv is created
    (``python3 -m venv``) if missing, elkai is installed with its pip, and the
    current process is replaced by the venv's interpreter running this script
    with the same arguments.
    """
    try:
        import elkai  # noqa: F401

        return
    except ImportError:
        pass
    if os.environ.get(REEXEC_MARKER):
        sys.exit(f"error: elkai still not importable inside {venv}")
    python = venv / "bin" / "python"
    if not python.exists():
        print(f"# creating venv {venv}", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    probe = subprocess.run([str(python), "-c", "import elkai"], capture_output=True)
    if probe.returncode != 0:
        print(f"# installing elkai into {venv}", file=sys.stderr)
        subprocess.run([str(python), "-m", "pip", "install", "-q", "elkai"], check=True)
    env = dict(os.environ, **{REEXEC_MARKER: "1"})
    os.execve(str(python), [str(python), str(Path(__file__).resolve()), *sys.argv[1:]], env)


# --------------------------------------------------------------------------
# GTSPLIB parsing


@dataclass
class Instance:
    """A parsed GTSP instance: 0-based distance matrix and 0-based sets."""

    name: str
    dist: list[list[int]]
    sets: list[list[int]]


def _nint(x: float) -> int:
    """TSPLIB nint: round half up, ``(int)(x + 0.5)``."""
    return int(x + 0.5)


def _geo_radians(x: float) -> float:
    """TSPLIB GEO coordinate (DDD.MM) to radians, with PI = 3.141592."""
    deg = int(x)
    minutes = x - deg
    return 3.141592 * (deg + 5.0 * minutes / 3.0) / 180.0


def coord_matrix(kind: str, coords: list[tuple[float, float]]) -> list[list[int]]:
    """Full distance matrix for EUC_2D, CEIL_2D, ATT or GEO coordinates."""
    n = len(coords)
    d = [[0] * n for _ in range(n)]
    if kind == "GEO":
        rad = [(_geo_radians(x), _geo_radians(y)) for x, y in coords]
    for i in range(n):
        xi, yi = coords[i]
        row = d[i]
        for j in range(n):
            if i == j:
                continue
            if kind == "GEO":
                lat_i, lon_i = rad[i]
                lat_j, lon_j = rad[j]
                q1 = math.cos(lon_i - lon_j)
                q2 = math.cos(lat_i - lat_j)
                q3 = math.cos(lat_i + lat_j)
                arg = 0.5 * ((1.0 + q1) * q2 - (1.0 - q1) * q3)
                row[j] = int(6378.388 * math.acos(max(-1.0, min(1.0, arg))) + 1.0)
                continue
            dx, dy = xi - coords[j][0], yi - coords[j][1]
            if kind == "EUC_2D":
                row[j] = _nint(math.sqrt(dx * dx + dy * dy))
            elif kind == "CEIL_2D":
                row[j] = math.ceil(math.sqrt(dx * dx + dy * dy))
            elif kind == "ATT":
                r = math.sqrt((dx * dx + dy * dy) / 10.0)
                t = _nint(r)
                row[j] = t + 1 if t < r else t
            else:
                raise ValueError(f"unsupported EDGE_WEIGHT_TYPE {kind}")
    return d


def explicit_matrix(fmt: str, n: int, values: list[float]) -> list[list[int]]:
    """Full matrix from EDGE_WEIGHT_SECTION values in the given format."""
    d = [[0] * n for _ in range(n)]
    it = iter(int(round(v)) for v in values)
    if fmt == "FULL_MATRIX":
        for i in range(n):
            for j in range(n):
                d[i][j] = next(it)
        return d
    if fmt == "UPPER_ROW":
        pairs = ((i, j) for i in range(n) for j in range(i + 1, n))
    elif fmt == "UPPER_DIAG_ROW":
        pairs = ((i, j) for i in range(n) for j in range(i, n))
    elif fmt == "LOWER_DIAG_ROW":
        pairs = ((i, j) for i in range(n) for j in range(i + 1))
    elif fmt == "LOWER_ROW":
        pairs = ((i, j) for i in range(n) for j in range(i))
    else:
        raise ValueError(f"unsupported EDGE_WEIGHT_FORMAT {fmt}")
    for i, j in pairs:
        d[i][j] = d[j][i] = next(it)
    return d


def parse_gtsp(path: Path) -> Instance:
    """Parse a GTSPLIB file (header keys with or without colon, see README)."""
    header: dict[str, str] = {}
    tokens: dict[str, list[str]] = {s: [] for s in SECTIONS}
    section = None
    with open(path, encoding="utf-8", errors="replace") as fh:
        for raw in fh:
            line = raw.strip()
            if not line:
                continue
            key = line.rstrip(":").strip().upper()
            if key in SECTIONS:
                section = key
                if key == "EOF":
                    break
                continue
            if section is None:
                if ":" in line:
                    k, v = line.split(":", 1)
                else:  # e.g. "TYPE  AGTSP"
                    k, _, v = line.partition(" ")
                header[k.strip().upper()] = v.strip()
                continue
            tokens[section].extend(line.split())
    n = int(header["DIMENSION"])
    kind = header.get("EDGE_WEIGHT_TYPE", "").split()[0].upper()
    if kind == "EXPLICIT":
        fmt = header.get("EDGE_WEIGHT_FORMAT", "FULL_MATRIX").split()[0].upper()
        dist = explicit_matrix(fmt, n, [float(t) for t in tokens["EDGE_WEIGHT_SECTION"]])
    else:
        vals = tokens["NODE_COORD_SECTION"]
        coords = [(0.0, 0.0)] * n
        for k in range(0, len(vals), 3):
            coords[int(vals[k]) - 1] = (float(vals[k + 1]), float(vals[k + 2]))
        dist = coord_matrix(kind, coords)
    sets: list[list[int]] = []
    current: list[int] | None = None
    for tok in tokens["GTSP_SET_SECTION"]:
        v = int(tok)
        if current is None:  # the token is a set id
            current = []
        elif v == -1:
            sets.append(current)
            current = None
        else:
            current.append(v - 1)
    if current:
        sets.append(current)
    return Instance(path.stem, dist, sets)


def gtsp_cost(inst: Instance, tour: list[int]) -> int:
    """Closed-tour cost of a 0-based g-tour; raises if not one vertex per set."""
    owner = {v: s for s, vs in enumerate(inst.sets) for v in vs}
    hit = sorted(owner.get(v, -1) for v in tour)
    if hit != list(range(len(inst.sets))):
        raise ValueError("tour does not visit exactly one vertex per set")
    return sum(inst.dist[tour[k - 1]][tour[k]] for k in range(len(tour)))


# --------------------------------------------------------------------------
# Noon-Bean + LKH


def noon_bean(inst: Instance) -> tuple[list[list[int]], list[int], list[int]]:
    """Noon-Bean transform of the GTSP into an ATSP matrix.

    The ATSP nodes are the GTSP vertices. Each set's vertices are ordered in
    a cycle ``c_0 -> c_1 -> ... -> c_{k-1} -> c_0`` (file order), and

    * the cycle arcs ``c_i -> c_{i+1}`` cost 0;
    * an inter-set arc ``c_i -> w`` costs ``d(next(c_i), w) + M`` with
      ``M = 1 + sum over sets of the largest arc leaving that set``, so any
      tour with more than one entry per set is dearer than every tour with
      exactly one;
    * every other arc (intra-set, off the cycle) costs ``INF = (m + 1) * M``.

    Returns the matrix, the set index of each node and ``nxt`` (the cycle
    successor of each node).
    """
    n, m = len(inst.dist), len(inst.sets)
    owner = [0] * n
    nxt = list(range(n))
    for s, vs in enumerate(inst.sets):
        for k, v in enumerate(vs):
            owner[v] = s
            nxt[v] = vs[(k + 1) % len(vs)]
    big_m = 1 + sum(
        max(inst.dist[v][w] for v in vs for w in range(n) if owner[w] != s)
        for s, vs in enumerate(inst.sets)
    )
    inf = (m + 1) * big_m
    matrix = [[inf] * n for _ in range(n)]
    for v in range(n):
        row, src, sv = matrix[v], inst.dist[nxt[v]], owner[v]
        for w in range(n):
            if owner[w] != sv:
                row[w] = src[w] + big_m
        row[v] = 0
        if nxt[v] != v:
            row[nxt[v]] = 0
    return matrix, owner, nxt


def gtour_from_atsp(atsp_tour: list[int], owner: list[int], n_sets: int) -> list[int]:
    """Read the g-tour off a Noon-Bean ATSP tour (0-based nodes).

    Mapping: the tour is rotated so that it starts where the set changes; it
    then splits into blocks of consecutive same-set nodes. A set entered at
    ``c_j`` is traversed ``c_j, c_{j+1}, ..., c_{j-1}`` and left by an arc
    priced ``d(c_j, w)``, so the **first node of each block** is the
    visited vertex. Raises if some set is split over several blocks.
    """
    k = len(atsp_tour)
    start = next((i for i in range(k) if owner[atsp_tour[i]] != owner[atsp_tour[i - 1]]), 0)
    rotated = atsp_tour[start:] + atsp_tour[:start]
    gtour = [rotated[i] for i in range(k) if i == 0 or owner[rotated[i]] != owner[rotated[i - 1]]]
    if len(gtour) != n_sets or len({owner[v] for v in gtour}) != n_sets:
        raise ValueError("ATSP tour does not enter each set exactly once")
    return gtour


def _lkh_child(conn, matrix: list[list[int]], runs: int, seed: int, err_fd: int) -> None:
    """Child process: solve the ATSP with elkai's LKH, send the 0-based tour.

    stdout goes to /dev/null and stderr to ``err_fd`` (LKH prints progress
    and, on failed assertions, aborts with a message on stderr).
    """
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(err_fd, 2)
    try:
        from elkai import _elkai  # elkai 2.x: solve_problem(params, problem)

        n = len(matrix)
        problem = (
            f"TYPE : ATSP\nDIMENSION : {n}\nEDGE_WEIGHT_TYPE : EXPLICIT\n"
            "EDGE_WEIGHT_FORMAT : FULL_MATRIX\nEDGE_WEIGHT_SECTION\n"
            + "\n".join(" ".join(map(str, row)) for row in matrix)
            + "\nEOF\n"
        )
        params = f"RUNS = {runs}\nSEED = {seed}\nPROBLEM_FILE = :stdin:\n"
        tour = _elkai.solve_problem(params, problem)
        conn.send(("ok", [v - 1 for v in tour]))
    except BaseException as exc:  # noqa: BLE001 - report everything
        conn.send(("error", f"{type(exc).__name__}: {exc}"))
    finally:
        conn.close()


def solve_lkh(inst: Instance, runs: int, seed: int, timeout: float) -> dict:
    """Noon-Bean + LKH on one instance, isolated in a killable child process.

    Returns ``{"cost", "time_s"}`` or ``{"error", "time_s"}``. A crash of LKH
    (it may call ``exit``), an exception or exceeding ``timeout`` seconds is a
    failure. The wall time includes the transform.
    """
    t0 = time.monotonic()
    matrix, owner, _ = noon_bean(inst)
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    with tempfile.TemporaryFile() as err:
        proc = ctx.Process(target=_lkh_child, args=(child, matrix, runs, seed, err.fileno()),
                           daemon=True)
        proc.start()
        child.close()
        del matrix
        remaining = max(0.0, timeout - (time.monotonic() - t0))
        ready = parent.poll(remaining)  # True on a message or when the child died
        msg = None
        if ready:
            try:
                msg = parent.recv()
            except EOFError:
                pass
        elapsed = time.monotonic() - t0
        if not ready:
            proc.kill()
            proc.join()
            return {"error": f"timeout>{timeout:g}s", "time_s": elapsed}
        proc.join()
        if msg is None:
            err.seek(0)
            lines = err.read().decode(errors="replace").strip().splitlines()
            why = lines[-1][-160:] if lines else ""
            return {"error": f"lkh crashed (exit {proc.exitcode}) {why}", "time_s": elapsed}
    if msg[0] != "ok":
        return {"error": msg[1], "time_s": elapsed}
    try:
        gtour = gtour_from_atsp(msg[1], owner, len(inst.sets))
        return {"cost": gtsp_cost(inst, gtour), "time_s": elapsed}
    except ValueError as exc:
        return {"error": str(exc), "time_s": elapsed}


# --------------------------------------------------------------------------
# strider


def solve_strider(binary: Path, path: Path, inst: Instance, limit: float, seed: int) -> dict:
    """Run ``strider gtsp solve --json``; verify the tour and recompute cost.

    Returns ``{"cost", "time_s"}`` (``time_s`` is the wall time measured
    here) or ``{"error", "time_s"}``.
    """
    cmd = [str(binary), "gtsp", "solve", str(path), "--time-limit", f"{limit:g}",
           "--seed", str(seed), "--json"]
    t0 = time.monotonic()
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=limit * 2 + 30)
    except subprocess.TimeoutExpired:
        return {"error": "timeout", "time_s": time.monotonic() - t0}
    elapsed = time.monotonic() - t0
    if res.returncode != 0:
        return {"error": f"exit {res.returncode}: {res.stderr.strip()[-200:]}", "time_s": elapsed}
    try:
        out = json.loads(res.stdout)
        cost = gtsp_cost(inst, [v - 1 for v in out["tour"]])
    except (ValueError, KeyError, TypeError) as exc:
        return {"error": f"bad output: {exc}", "time_s": elapsed}
    if cost != round(out["cost"]):
        return {"error": f"reported cost {out['cost']} != recomputed {cost}", "time_s": elapsed}
    return {"cost": cost, "time_s": elapsed}


# --------------------------------------------------------------------------
# driver


def load_best_known(directory: Path) -> list[dict]:
    """Rows of ``best_known.csv`` (instance, sets, vertices, best_known)."""
    with open(directory / "best_known.csv", newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def select(rows: list[dict], only: str | None, min_sets: int | None,
           max_sets: int | None) -> list[dict]:
    """Filter instances by ``--only``, ``--min-sets`` and ``--max-sets``."""
    names = {s.strip() for s in only.split(",") if s.strip()} if only else None
    if names:
        missing = names - {r["instance"] for r in rows}
        if missing:
            sys.exit(f"error: unknown instance(s): {', '.join(sorted(missing))}")
    out = []
    for r in rows:
        sets = int(r["sets"])
        if names is not None and r["instance"] not in names:
            continue
        if (min_sets is not None and sets < min_sets) or (max_sets is not None and sets > max_sets):
            continue
        out.append(r)
    return sorted(out, key=lambda r: (int(r["sets"]), r["instance"]))


def gap_pct(cost: int, best: float) -> float:
    """Percentage gap of ``cost`` above ``best``."""
    return 100.0 * (cost - best) / best if best else 0.0


def fmt_result(res: dict, best: float) -> str:
    """``cost gap time`` fields for one solver result."""
    if "cost" in res:
        return f"{res['cost']} {gap_pct(res['cost'], best):.2f} {res['time_s']:.2f}"
    reason = "_".join(str(res["error"]).split())
    return f"FAIL({reason}) - {res['time_s']:.2f}"


def summary(solver: str, results: list[tuple[dict, float]]) -> str:
    """Summary line for one solver over (result, best_known) pairs."""
    gaps = [gap_pct(r["cost"], b) for r, b in results if "cost" in r]
    total = sum(r["time_s"] for r, _ in results)
    mean = f"{sum(gaps) / len(gaps):.2f}" if gaps else "nan"
    worst = f"{max(gaps):.2f}" if gaps else "nan"
    return (f"solver={solver} instances={len(results)} solved={len(gaps)} "
            f"mean_gap_pct={mean} max_gap_pct={worst} total_s={total:.1f}")


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """Command-line options."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dir", type=Path, default=REPO_ROOT.parent / "shared" / "data" / "gtsplib",
                   help="GTSPLIB directory with best_known.csv (default: ../shared/data/gtsplib)")
    p.add_argument("--strider", type=Path, default=REPO_ROOT / "target" / "release" / "strider",
                   help="strider binary (default: target/release/strider)")
    p.add_argument("--venv", type=Path, default=REPO_ROOT / "bench" / ".venv",
                   help="venv used for elkai if it is not importable (default: bench/.venv)")
    p.add_argument("--time-limit", type=float, default=10.0,
                   help="wall-clock budget per instance and solver, seconds (default 10)")
    p.add_argument("--lkh-timeout", type=float, default=None,
                   help="hard kill time for LKH (default: --time-limit). elkai's LKH "
                        "ignores TIME_LIMIT, so a run over the budget counts as a failure")
    p.add_argument("--runs", type=int, default=1, help="elkai/LKH RUNS (default 1)")
    p.add_argument("--seed", type=int, default=1, help="seed for both solvers (default 1)")
    p.add_argument("--only", help="comma-separated instance names")
    p.add_argument("--min-sets", type=int, help="skip instances with fewer sets")
    p.add_argument("--max-sets", type=int, help="skip instances with more sets")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    """Run both solvers on the selected instances and print the table."""
    args = parse_args(argv)
    if not args.strider.exists():
        sys.exit(f"error: {args.strider} not found; run `cargo build --release` first")
    ensure_elkai(args.venv.resolve())
    rows = select(load_best_known(args.dir), args.only, args.min_sets, args.max_sets)
    lkh_timeout = args.lkh_timeout if args.lkh_timeout is not None else args.time_limit
    print(f"# time_limit={args.time_limit:g}s lkh_timeout={lkh_timeout:g}s "
          f"runs={args.runs} seed={args.seed} instances={len(rows)}")
    print("name sets best_known lkh_cost lkh_gap_pct lkh_time_s "
          "strider_cost strider_gap_pct strider_time_s")
    lkh_all, strider_all = [], []
    for r in rows:
        path = args.dir / f"{r['instance']}.gtsp"
        best = float(r["best_known"])
        inst = parse_gtsp(path)
        lkh = solve_lkh(inst, args.runs, args.seed, lkh_timeout)
        strider = solve_strider(args.strider, path, inst, args.time_limit, args.seed)
        lkh_all.append((lkh, best))
        strider_all.append((strider, best))
        print(f"{r['instance']} {r['sets']} {r['best_known']} "
              f"{fmt_result(lkh, best)} {fmt_result(strider, best)}", flush=True)
    print(summary("lkh", lkh_all))
    print(summary("strider", strider_all))
    return 0


if __name__ == "__main__":
    sys.exit(main())

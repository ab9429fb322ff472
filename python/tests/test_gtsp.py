"""strider.gtsp against `strider gtsp solve --json` on the same file and seed."""

import json

import numpy as np
import pytest

import strider


def gtsp_file(path, n=48, sets=12, seed=3):
    rng = np.random.default_rng(seed)
    xy = rng.integers(0, 1000, size=(n, 2))
    owner = np.arange(n) % sets
    lines = [f"NAME: py{n}", "TYPE: GTSP", f"DIMENSION: {n}", f"GTSP_SETS: {sets}",
             "EDGE_WEIGHT_TYPE: EUC_2D", "NODE_COORD_SECTION"]
    lines += [f"{i + 1} {x} {y}" for i, (x, y) in enumerate(xy)]
    lines.append("GTSP_SET_SECTION")
    for s in range(sets):
        members = " ".join(str(i + 1) for i in np.flatnonzero(owner == s))
        lines.append(f"{s + 1} {members} -1")
    lines.append("EOF")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("seed", [1, 5])
def test_solve_equals_the_command(tmp_path, strider_cli, seed):
    f = gtsp_file(tmp_path / "py48.gtsp")
    inst = strider.gtsp.read(f)
    assert (inst.n, len(inst.sets)) == (48, 12)
    sol = strider.gtsp.solve(inst, seed=seed, time_limit=60)
    cli = json.loads(strider_cli("gtsp", "solve", f, "--seed", seed, "--time-limit", 60, "--json"))
    assert sol.cost == cli["cost"]
    # The command prints the file's 1-based vertex ids.
    assert [v + 1 for v in sol.tour] == cli["tour"]


def test_a_matrix_and_sets_solve_as_the_same_instance(tmp_path):
    inst = strider.gtsp.read(gtsp_file(tmp_path / "py48.gtsp"))
    a = strider.gtsp.solve(inst, seed=2, time_limit=60)
    b = strider.gtsp.solve(inst.matrix(), inst.sets, seed=2, time_limit=60)
    assert (a.cost, a.tour) == (b.cost, b.tour)
    m = inst.matrix()
    assert a.cost == sum(m[a.tour[i], a.tour[(i + 1) % len(a.tour)]] for i in range(len(a.tour)))


def test_bad_instances_are_value_errors(tmp_path):
    with pytest.raises(ValueError, match="square"):
        strider.gtsp.solve(np.zeros((2, 3), dtype=np.int64), [[0], [1]])
    with pytest.raises(ValueError, match="vertex 1 is in sets 0 and 1"):
        strider.gtsp.solve(np.zeros((3, 3), dtype=np.int64), [[0, 1], [1, 2]])
    with pytest.raises(ValueError, match="arc cost -1"):
        strider.gtsp.solve(-np.ones((3, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="time_limit"):
        strider.gtsp.solve(np.zeros((3, 3), dtype=np.int64), time_limit=float("nan"))
    bad = tmp_path / "bad.gtsp"
    bad.write_text("NAME: x\nTYPE: GTSP\nDIMENSION: two\nEOF\n")
    with pytest.raises(strider.StriderError, match="bad.gtsp"):
        strider.gtsp.read(bad)


def test_a_target_cost_is_passed_as_the_command_passes_it(tmp_path, strider_cli):
    f = gtsp_file(tmp_path / "py96.gtsp", n=96, sets=30, seed=4)
    inst = strider.gtsp.read(f)
    free = strider.gtsp.solve(inst, seed=3, time_limit=60)
    target = free.cost + 50
    sol = strider.gtsp.solve(inst, seed=3, time_limit=60, target_cost=target)
    cli = json.loads(strider_cli("gtsp", "solve", f, "--seed", 3, "--time-limit", 60,
                                 "--target", target, "--json"))
    assert sol.cost == cli["cost"] <= target
    assert [v + 1 for v in sol.tour] == cli["tour"]
    m = strider.gtsp.solve(inst.matrix(), inst.sets, seed=3, time_limit=60, target_cost=target)
    assert (m.cost, m.tour) == (sol.cost, sol.tour)
    with pytest.raises(strider.StriderError, match="target_cost"):
        strider.gtsp.solve(inst, target_cost=1.5)

"""Shards merged and the Ray sweep both reproduce `strider bench compare` for the same seeds."""

import json

import pytest

import strider

# 4 short missions: 2 strategies x 2 trials (world seeds 1, 2; mission seeds 1, 2).
OPTS = dict(scenarios=["courtyard-small"], strategies=["gtsp", "greedy"], trials=2,
            world_seeds=2, time_limit=10)


def cli_args(o):
    return ["--scenarios", ",".join(o["scenarios"]), "--strategies", ",".join(o["strategies"]),
            "--trials", o["trials"], "--world-seeds", o["world_seeds"],
            "--time-limit", o["time_limit"], "--jobs", 1]


def without_timing(v):
    """Drops what measures the computer: wall times, latencies, the job count."""
    if isinstance(v, dict):
        return {k: without_timing(x) for k, x in v.items()
                if "wall" not in k and "_ms" not in k and k != "jobs"}
    if isinstance(v, list):
        return [without_timing(x) for x in v]
    return v


@pytest.fixture(scope="module")
def unsharded(tmp_path_factory, strider_cli):
    out = tmp_path_factory.mktemp("compare")
    strider_cli("bench", "compare", *cli_args(OPTS), "--out", out)
    c = json.loads((out / "compare.json").read_text())
    assert len(c["trials"]) == 4 and c["complete"]
    return c


def test_merged_shards_equal_the_unsharded_bench(unsharded, strider_cli, tmp_path):
    dirs = []
    for k in (1, 2, 3):
        d = tmp_path / f"shard{k}"
        strider_cli("bench", "compare", *cli_args(OPTS), "--shard", f"{k}/3", "--out", d)
        shard = json.loads((d / "compare.json").read_text())
        assert shard["shard"]["k"] == k and len(shard["trials"]) in (1, 2)
        dirs.append(d)
    strider_cli("bench", "merge", *reversed(dirs), "--out", tmp_path / "merged")
    merged = json.loads((tmp_path / "merged" / "compare.json").read_text())
    assert without_timing(merged) == without_timing(unsharded)
    md = (tmp_path / "merged" / "compare.md").read_text()
    assert "strider bench compare --scenarios courtyard-small --strategies gtsp,greedy" in md


def test_local_sweep_equals_the_bench(unsharded):
    c = strider.sweep(**OPTS, local=True)
    assert without_timing(c) == without_timing(unsharded)


def test_ray_sweep_equals_the_bench(unsharded):
    ray = pytest.importorskip("ray", reason="ray is not installed (pip install ray)")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        c = strider.sweep(**OPTS)
    finally:
        ray.shutdown()
    assert without_timing(c) == without_timing(unsharded)


def test_bad_sweep_options_are_value_errors():
    with pytest.raises(ValueError, match="trials"):
        strider.sweep(["courtyard-small"], ["gtsp"], trials=0, local=True)
    with pytest.raises(ValueError, match="no-such"):
        strider.sweep(["courtyard-small"], ["no-such"], trials=1, local=True)
    with pytest.raises(ValueError, match="lists"):
        strider.sweep("courtyard-small", ["gtsp"], trials=1, local=True)


# Table 5 of 4 short trials: gtsp (with its tours) and greedy on 2 small-world seeds.
T5 = dict(trials=2, large_trials=0, world_seeds=1, time_limit=10)


def t5_args(o):
    return ["--trials", o["trials"], "--large-trials", o["large_trials"],
            "--world-seeds", o["world_seeds"], "--time-limit", o["time_limit"], "--jobs", 1]


@pytest.fixture(scope="module")
def table5_unsharded(tmp_path_factory, strider_cli):
    out = tmp_path_factory.mktemp("table5")
    strider_cli("bench", "table5", *t5_args(T5), "--out", out)
    t = json.loads((out / "table5.json").read_text())
    assert len(t["trial_results"]) == 4 and t["complete"] and "shard" not in t
    return t


def test_merged_table5_shards_equal_the_unsharded_table(table5_unsharded, strider_cli, tmp_path):
    dirs = []
    for k in (1, 2):
        d = tmp_path / f"shard{k}"
        strider_cli("bench", "table5", *t5_args(T5), "--shard", f"{k}/2", "--out", d)
        shard = json.loads((d / "table5.json").read_text())
        assert shard["shard"] == {"k": k, "n": 2} and len(shard["trial_results"]) == 2
        dirs.append(d)
    strider_cli("bench", "merge", *dirs, "--out", tmp_path / "merged")
    merged = json.loads((tmp_path / "merged" / "table5.json").read_text())
    assert without_timing(merged) == without_timing(table5_unsharded)


def test_local_table5_sweep_equals_the_bench(table5_unsharded):
    t = strider.sweep_table5(**T5, local=True)
    assert without_timing(t) == without_timing(table5_unsharded)

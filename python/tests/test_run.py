"""strider.run: the report's fields and numpy layers against the report the command writes for
the same mission, and errors as ValueError."""

import json

import numpy as np
import pytest

import strider

# Fields that measure the computer rather than the mission.
WALL = {"phase_wall_s", "mission_wall_s", "speedup", "wall_time_s", "replan_latency_ms",
        "goals_to_tour_ms", "replan_parts_ms", "goal_identification_ms"}


@pytest.fixture(scope="module")
def mission(tmp_path_factory):
    out = tmp_path_factory.mktemp("py-run")
    return strider.run("courtyard-small", "gtsp", seed=3, time_limit=15, out=out), out


def test_report_fields_are_attributes_equal_to_report_json(mission):
    r, out = mission
    written = json.loads((out / "report.json").read_text())
    assert r.json == written
    assert r.exploration_time_s == written["exploration_time_s"]
    assert r.strategy == "gtsp" and r.scenario == "courtyard-small" and r.seed == 3
    assert 0 < r.exploration_time_s <= 15.0 + 1e-9
    with pytest.raises(AttributeError):
        r.no_such_field


def test_layers_are_numpy_and_agree_with_the_report(mission):
    r, _ = mission
    L = r.layers
    rows, cols = L["elevation"].shape
    assert L["elevation"].dtype == np.float32 and L["color"].shape == (rows, cols, 3)
    assert L["observed"].dtype == np.bool_ and L["passability"].dtype == np.uint8
    assert r.cell_size == pytest.approx(0.05) and len(r.origin) == 2
    # The report counts the observed cells of the same final map.
    assert int(L["observed"].sum()) == r.observed_cells
    assert np.isfinite(L["elevation"][L["observed"]]).all()
    assert (L["passability"][~L["observed"]] == 0).all()
    # One model layer per gait the report lists.
    assert sorted(L["models"]) == sorted(m["gait"] for m in r.models)
    for m in L["models"].values():
        assert m["cost"].shape == (rows, cols)
        # The planning classes: −1 or a class id; a classified cell has a planning cost.
        c = m["classes"]
        assert c.dtype == np.int32 and c.shape == (rows, cols) and c.min() >= -1
        assert np.isfinite(m["cost"][c >= 0]).all()


def test_the_same_mission_from_the_command_writes_the_same_report(mission, strider_cli, tmp_path):
    r, _ = mission
    strider_cli("run", "--scenario", "courtyard-small", "--strategy", "gtsp", "--seed", 3,
                "--time-limit", 15, "--out", tmp_path)
    cli = json.loads((tmp_path / "report.json").read_text())
    strip = lambda d: {k: v for k, v in d.items() if k not in WALL}
    assert strip(r.json) == strip(cli)


def test_bad_arguments_are_value_errors():
    with pytest.raises(ValueError, match="no-such-world"):
        strider.run("no-such-world", "gtsp", time_limit=1)
    with pytest.raises(ValueError, match="unknown"):
        strider.run("courtyard-small", "no-such-strategy", time_limit=1)
    with pytest.raises(ValueError, match="no_such_param"):
        strider.run("courtyard-small", "gtsp", time_limit=1, params={"no_such_param": 1})
    with pytest.raises(ValueError, match="time_limit nan"):
        strider.run("courtyard-small", "gtsp", time_limit=float("nan"))
    with pytest.raises(ValueError, match="time_limit"):
        strider.run("courtyard-small", "gtsp", time_limit="10")
    with pytest.raises(ValueError, match="seed"):
        strider.run("courtyard-small", "gtsp", seed=-1, time_limit=1)


def test_scenarios_and_their_layers():
    names = strider.scenarios()
    assert "courtyard-small" in names and "lab-track" in names
    assert {"gtsp", "greedy", "rbcm-greedy"} <= {s["name"] for s in strider.strategies()}
    w = strider.scenario_layers("courtyard-small")
    rows, cols = w["terrain"].shape
    assert w["color"].shape == (rows, cols, 3) and w["elevation"].shape == (rows, cols)
    assert int(w["terrain"].max()) < len(w["terrains"])


def test_replay_equals_the_command(strider_cli, tmp_path):
    log = tmp_path / "run.mcap"
    strider_cli("run", "--scenario", "courtyard-small", "--seed", 2, "--time-limit", 10,
                "--mcap", log, "--out", tmp_path / "rec")
    cfg = tmp_path / "replay.toml"
    cfg.write_text('[mission]\nscenario = "courtyard-small"\n')
    r = strider.replay(log, cfg)
    strider_cli("replay", log, "--config", cfg, "--out", tmp_path / "cli")
    cli = json.loads((tmp_path / "cli" / "report.json").read_text())
    timing = WALL | {"ingest_wall_s"}
    strip = lambda d: {k: v for k, v in d.items() if k not in timing and "wall" not in k}
    assert r.exploration_time_s > 0 and strip(r.json) == strip(cli)
    with pytest.raises(ValueError, match="no-such.mcap"):
        strider.replay(tmp_path / "no-such.mcap", cfg)

"""Campaigns from Python: the same database rows as `uascma campaign` for the same seed, read into pandas
with parsed columns."""
import sqlite3

import numpy as np
import pandas as pd
import pytest

import uascma
from conftest import cli_json, example, run_cli

RUNS = 3
SEED = 11


@pytest.fixture(scope="module")
def databases(tmp_path_factory):
    folder = tmp_path_factory.mktemp("campaign")
    python_db, cli_db = folder / "python.db", folder / "cli.db"
    outcome = uascma.run_campaign(example("campaign.yaml"), str(python_db), runs=RUNS, seed=SEED, jobs=1)
    assert outcome["flights_flown"] == RUNS * 2
    run_cli("campaign", example("campaign.yaml"), "--db", cli_db, "--runs", RUNS, "--seed", SEED, "--jobs", 1)
    return python_db, cli_db


def test_python_campaign_equals_the_cli(databases):
    python_db, cli_db = databases
    mine = uascma.read_campaign(str(python_db)).drop(columns=["wall_time_s"])
    theirs = uascma.read_campaign(str(cli_db)).drop(columns=["wall_time_s"])
    pd.testing.assert_frame_equal(mine, theirs)
    assert len(mine) == RUNS * 2


def test_runs_in_flight_change_no_row(databases, tmp_path):
    """Lockstep (four runs in flight per thread, the default) and one run at a time store the same rows."""
    alone = tmp_path / "alone.db"
    uascma.run_campaign(example("campaign.yaml"), alone, runs=RUNS, seed=SEED, jobs=1, runs_in_flight=1)
    mine = uascma.read_campaign(str(alone)).drop(columns=["wall_time_s"])
    theirs = uascma.read_campaign(str(databases[0])).drop(columns=["wall_time_s"])
    pd.testing.assert_frame_equal(mine, theirs)


def test_read_campaign_parses_every_column(databases):
    frame = uascma.read_campaign(str(databases[0]))
    assert list(frame["policy"].unique()) == ["cma", "noop"]
    assert frame.groupby("run_index").size().eq(2).all()  # paired: every run flown by both policies
    assert frame["failure"].dtype == bool and frame["fault"].dtype == bool
    assert frame["run_seed"].dtype == np.uint64
    assert frame["fault_onset_s"].dtype == float
    assert frame.loc[~frame["fault"], "fault_onset_s"].isna().all()
    cells = [f"initial_cell_voltage_p{p}c{c}_v" for p in (1, 2) for c in (1, 2, 3)]
    voltages = frame[cells].to_numpy()
    assert voltages.shape == (len(frame), 6)
    assert ((voltages >= 4.05) & (voltages <= 4.12)).all()  # Table 4.4's range (V)
    np.testing.assert_allclose(voltages.min(axis=1), frame["initial_cell_voltage_min_v"])
    assert all(isinstance(a, list) for a in frame["actions"])
    # No emergency action: missing (None), not an empty string; its time NaN.
    none = frame["first_emergency_action"].isna()
    assert (none == frame["first_emergency_action_s"].isna()).all()
    assert (frame["actions"].map(len) == frame["num_actions"]).all()
    # No JSON text left in any column.
    for column in frame.columns:
        if frame[column].dtype == object:
            assert not frame[column].map(lambda v: isinstance(v, str) and v.startswith(("[", "{"))).any(), column
    assert frame.attrs["campaign"]["seed"] == SEED
    assert frame.attrs["campaign"]["runs_requested"] == RUNS


def test_records_match_the_frame(databases):
    records = uascma.read_records(str(databases[0]))
    frame = uascma.read_campaign(str(databases[0]))
    assert [r["outcome"] for r in records] == list(frame["outcome"])


def test_errors_name_the_file_or_field(tmp_path):
    with pytest.raises(uascma.InputError, match="db"):
        uascma.read_campaign(str(tmp_path / "missing.db"))
    other = tmp_path / "other.db"
    sqlite3.connect(other).execute("CREATE TABLE t (x)").connection.commit()
    with pytest.raises(uascma.InputError, match="campaign"):
        uascma.read_campaign(str(other))
    with pytest.raises(uascma.InputError, match="runs"):
        uascma.run_campaign({"runs": -3}, str(tmp_path / "x.db"))
    with pytest.raises(uascma.InputError, match="policies"):
        uascma.run_campaign(None, str(tmp_path / "y.db"), runs=1, policies=["cma", "cma"])
    for bad in (0, 65):
        with pytest.raises(uascma.InputError, match="runs_in_flight"):
            uascma.run_campaign(None, str(tmp_path / "z.db"), runs=1, runs_in_flight=bad)
        assert not (tmp_path / "z.db").exists()


def test_the_cli_and_python_share_the_summaries(databases):
    """The report (campaign/report.h) and the run summary (campaign/run_summary.h) are formatted once, in the
    library: Python returns what `uascma report` / `campaign --json` print."""
    python_db, _ = databases
    assert uascma.campaign_report(str(python_db), text=True) == run_cli("report", python_db).stdout
    assert uascma.campaign_report(str(python_db)) == cli_json("report", python_db)
    resumed = uascma.run_campaign(example("campaign.yaml"), str(python_db), runs=RUNS, seed=SEED, jobs=1, resume=True)
    assert resumed["flights_flown"] == 0 and resumed["flights_before"] == RUNS * 2
    assert {"flights_by_others", "flights_per_s", "jobs_per_rank", "ranks", "campaign_hash"} <= set(resumed)


def test_campaign_config_properties_come_from_the_field_table():
    config = uascma.load_campaign_config(example("campaign.yaml"))
    keys = [row["key"] for row in uascma.CampaignConfig.fields]
    assert keys[:4] == ["name", "seed", "runs", "policies"] and "mission.cruise_speed_mps" in keys
    assert config.mission_cruise_speed_mps == (1.0, 9.0)  # Table 4.4
    assert config.fault_time_per_growth_step_s == 0.7128
    before = config.hash
    config.mission_cruise_speed_mps = (2.0, 4.0)
    config.wind_turbulence = ["none"]
    assert config.hash != before
    again = uascma.load_campaign_config(config.to_yaml())
    assert again.mission_cruise_speed_mps == (2.0, 4.0) and again.wind_turbulence == ["none"]
    assert again.hash == config.hash

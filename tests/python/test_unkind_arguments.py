"""Unkind arguments to the Python module: every one raises the documented uascma.InputError (a ValueError) whose
message names what was wrong, never a TypeError, OverflowError, SystemError or a crash; an edited database given
to the readers is an InputError naming the damage."""
import os
import shutil
import sqlite3

import pytest

import uascma
from conftest import example

HUGE = 2**200

# The ranges the messages state (bindings.h IntegerArgument, SeedArgument): seeds as on the command line, runs as a
# campaign file's `runs` (campaign/config.h kRuns), jobs and runs_in_flight as the CLI's --jobs and --runs-in-flight
# (campaign/runner.h). An int out of its range and a value of another type (pybind11 would raise TypeError for
# both) are the same InputError.
SEED = "0 to 2^64-1"
RUNS = "0 to 1e+07 runs"
JOBS = "0 to 1024 threads"
IN_FLIGHT = "1 to 64 runs"

# (arguments of run_campaign beyond config and db, words the message must hold)
CAMPAIGN_CASES = [
    (dict(seed=-1), ("seed", SEED)),
    (dict(seed=2**64), ("seed", SEED)),
    (dict(seed=HUGE), ("seed", SEED)),
    (dict(seed=-HUGE), ("seed", SEED)),
    (dict(seed="1"), ("seed", SEED, "str")),
    (dict(seed=1.5), ("seed", SEED, "float")),
    (dict(seed=True), ("seed", SEED, "bool")),
    (dict(runs=-1), ("runs", RUNS)),
    (dict(runs=HUGE), ("runs", RUNS)),
    (dict(runs=10**8), ("runs", RUNS)),
    (dict(runs="3"), ("runs", RUNS, "str")),
    (dict(runs=2.0), ("runs", RUNS, "float")),
    (dict(jobs=-1), ("jobs", JOBS)),
    (dict(jobs=HUGE), ("jobs", JOBS)),
    (dict(jobs=10**6), ("jobs", JOBS)),
    (dict(jobs=1025), ("jobs", JOBS)),
    (dict(jobs=None), ("jobs", JOBS, "NoneType")),
    (dict(runs_in_flight=0), ("runs_in_flight", IN_FLIGHT)),
    (dict(runs_in_flight=65), ("runs_in_flight", IN_FLIGHT)),
    (dict(runs_in_flight=HUGE), ("runs_in_flight", IN_FLIGHT)),
    (dict(runs_in_flight="4"), ("runs_in_flight", IN_FLIGHT, "str")),
    (dict(policies=["no-such-policy"]), ("no-such-policy",)),
    (dict(policies=[""]), ("polic",)),
    (dict(policies=[]), ("polic",)),
    (dict(progress=3), ("progress",)),
]


def campaign_case_id(case):
    return repr(case) if isinstance(case, dict) else "-"


@pytest.mark.parametrize("arguments,words", CAMPAIGN_CASES, ids=campaign_case_id)
def test_bad_campaign_arguments_are_input_errors(tmp_path, arguments, words):
    db = tmp_path / "c.db"
    arguments = dict(arguments)
    arguments.setdefault("runs", 1)
    with pytest.raises(uascma.InputError) as error:
        uascma.run_campaign(example("campaign.yaml"), db, jobs=arguments.pop("jobs", 1), **arguments)
    for word in words:
        assert word in str(error.value)
    assert not db.exists()  # refused before the database


def test_numpy_integers_are_taken_where_an_int_is(tmp_path):
    numpy = pytest.importorskip("numpy")
    db = tmp_path / "c.db"
    outcome = uascma.run_campaign(example("campaign.yaml"), db, runs=numpy.int64(1), seed=numpy.uint64(2**64 - 1),
                                  jobs=numpy.int32(1), runs_in_flight=numpy.int16(2), progress=False)
    assert outcome["flights_total"] == 2


def test_a_campaign_samplers_error_names_the_file(tmp_path):
    # The sampler knows no file: its errors named "campaign". A clearance that leaves no open ground for a home.
    config = tmp_path / "wide.yaml"
    config.write_text("runs: 2\nmap: {procedural_seed: 3}\nmission: {wall_clearance_m: 100}\n")
    db = tmp_path / "c.db"
    with pytest.raises(uascma.InputError) as error:
        uascma.run_campaign(config, db, jobs=1, progress=False)
    assert str(error.value).startswith(f"{config}: mission.wall_clearance_m: "), str(error.value)
    assert not db.exists()


# Policy callables whose answers are no action: neither 0-3 nor an action's name ("NoOp" is one); a bool is none.
BAD_ANSWERS = [True, False, None, "Hover", "", 1.5, -1, 4, HUGE, -HUGE, [0], float("nan")]


@pytest.mark.parametrize("answer", BAD_ANSWERS, ids=[repr(a) for a in BAD_ANSWERS])
def test_a_policy_callable_answering_no_action_is_an_input_error(answer):
    with pytest.raises(uascma.InputError):
        uascma.run(example("nominal.yaml"), policy=lambda inputs: answer, telemetry=False)


def test_a_policy_callable_that_raises_passes_its_exception_through():
    def policy(inputs):
        raise RuntimeError("from the policy")

    with pytest.raises(RuntimeError, match="from the policy"):
        uascma.run(example("nominal.yaml"), policy=policy, telemetry=False)


RUN_CASES = [
    (dict(seed=-1), ("seed", SEED)),
    (dict(seed=2**64), ("seed", SEED)),
    (dict(seed=HUGE), ("seed", SEED)),
    (dict(seed="7"), ("seed", SEED, "str")),
    (dict(policy="no-such-policy"), ("no-such-policy",)),
    (dict(policy=""), ("polic",)),
    (dict(mission=""), ("mission", ".plan")),
]


@pytest.mark.parametrize("arguments,words", RUN_CASES, ids=campaign_case_id)
def test_bad_run_arguments_are_input_errors(arguments, words):
    with pytest.raises(uascma.InputError) as error:
        uascma.run(example("nominal.yaml"), telemetry=False, **arguments)
    for word in words:
        assert word in str(error.value)


def test_a_seed_out_of_range_is_an_input_error_for_scenarios_and_environments():
    scenario = uascma.load_scenario(example("nominal.yaml"))
    with pytest.raises(uascma.InputError, match="seed"):
        scenario.seed = -1
    scenario.seed = 2**64 - 1
    assert scenario.seed == 2**64 - 1
    environment = uascma.Environment(example("nominal.yaml"))
    with pytest.raises(uascma.InputError, match="seed"):
        environment.reset(seed=2**64)


@pytest.fixture(scope="module")
def sound_db(tmp_path_factory):
    db = tmp_path_factory.mktemp("sound") / "c.db"
    uascma.run_campaign(example("campaign.yaml"), db, runs=2, jobs=1, progress=False)
    return db


# Edits of a sound database, each a damage the store check names.
EDITS = [
    ("UPDATE runs SET failure = 1 WHERE outcome = 'completed'", "contradicts itself"),
    ("UPDATE runs SET energy_wh = -1", "energy_wh"),
    ("UPDATE runs SET min_cell_voltage_v = -2", "min_cell_voltage_v"),
    ("UPDATE runs SET run_seed = run_seed + 1", "run_seed"),
    ("UPDATE campaign SET seed = 3", "seed"),
    ("UPDATE runs SET outcome = 'won'", "outcome"),
    ("UPDATE runs SET actions = '[[0,'", "actions"),
    ("UPDATE runs SET reason = CAST(X'66FF6F' AS TEXT)", "UTF-8"),
    ("DELETE FROM policies WHERE slot = 1", "policies"),
    ("UPDATE runs SET energy_wh = 'lots'", "energy_wh"),
]


@pytest.mark.parametrize("sql,word", EDITS, ids=[e[0] for e in EDITS])
def test_edited_databases_are_input_errors_for_every_reader(tmp_path, sound_db, sql, word):
    db = tmp_path / "edited.db"
    shutil.copy(sound_db, db)
    with sqlite3.connect(db) as connection:
        connection.execute(sql)
    connection.close()
    for reader in (uascma.read_campaign, uascma.read_records, uascma.campaign_report):
        with pytest.raises(uascma.InputError) as error:
            reader(os.fspath(db))
        assert word in str(error.value), reader

"""pandas readers for uascma's result files.

* :func:`read_campaign` — a campaign's SQLite database (``uascma campaign --db``, :func:`uascma.run_campaign`):
  one row per flight (run and policy), every column parsed (no JSON text).
* :func:`read_telemetry` — a flight record folder (``uascma simulate --out``, ``Flight.write``): one row per
  telemetry sample, the CMA state, action and IMM mode as names, missing values as NaN.

The database schema is documented in docs/results-database.md. This module imports pandas; ``import uascma``
does not (the readers are loaded on first use).
"""
import io
import json
import os
import sqlite3

import numpy as np
import pandas as pd

from ._names import ACTION_NAMES, IMM_MODE_NAMES  # noqa: F401

# Columns of the runs table holding JSON text, parsed by read_campaign.
_CELLS = tuple(f"p{pack}c{cell}" for pack in (1, 2) for cell in (1, 2, 3))
_BOOLEAN_COLUMNS = ("fault", "failure")


def read_campaign(db):
    """Reads a campaign database into a DataFrame, one row per flight (run_index, policy).

    Columns: every field of the runs table (campaign/record.h) with
      * ``initial_cell_voltage_v`` (a JSON list in the database) split into ``initial_cell_voltage_p1c1_v`` …
        ``initial_cell_voltage_p2c3_v`` (V, pack 1 cells 1-3, pack 2 cells 1-3);
      * ``actions`` (JSON in the database) as a list of ``(time_s, action name)`` tuples per row;
      * ``substitutions`` (JSON in the database) as a list of ``"Chosen->Taken"`` strings per row
        (docs/modelling-choices.md#unavailable-actions: an action unavailable at run time and the one executed
        instead);
      * ``first_emergency_action`` and ``first_action_state`` (the CMA state the policy read then) None when there
        was none (the database's ""),
      * ``fault`` and ``failure`` as booleans, ``run_seed`` as the unsigned 64-bit seed, optional times
        (``fault_onset_s``, ``jam_time_s``, ``isolation_time_s``, ``first_emergency_action_s``) NaN when absent;
      * ``policy_slot``, ``policy_kind`` and ``policy_source`` from the policies table.
    Rows are ordered by run_index, then policy slot. ``df.attrs["campaign"]`` holds the campaign row (name,
    seed, hashes, runs_requested, code_version, created_utc, config_yaml).

    Raises uascma.InputError when the file is missing or is not a uascma campaign database.
    """
    from ._uascma import InputError

    path = os.fspath(db)
    if not os.path.isfile(path):
        raise InputError(f"{path}: db: an existing campaign database (SQLite), but the file is missing")
    # The store check of every uascma reader (campaign/store.h: CheckStore): a damaged or edited database
    # (text in a numeric column, JSON that is not, text that is not UTF-8, a deleted policies row) is an
    # InputError naming what is wrong, never a JSONDecodeError, ValueError or UnicodeDecodeError below.
    from ._uascma import check_store
    check_store(path)
    connection = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        try:
            campaign = connection.execute(
                "SELECT name, seed, config_hash, campaign_hash, runs_requested, code_version, created_utc, "
                "config_yaml FROM campaign WHERE id = 1").fetchone()
        except sqlite3.DatabaseError as error:
            raise InputError(f"{path}: campaign: a uascma campaign database ({error})") from None
        if campaign is None:
            raise InputError(f"{path}: campaign: a uascma campaign database (the campaign row is missing)")
        frame = pd.read_sql_query(
            "SELECT r.*, p.slot AS policy_slot, p.kind AS policy_kind, p.source AS policy_source "
            "FROM runs AS r JOIN policies AS p ON p.name = r.policy "
            "WHERE r.campaign_hash = ? ORDER BY r.run_index, p.slot",
            connection, params=(campaign[3],))
    finally:
        connection.close()
    frame = frame.drop(columns=["campaign_hash"])
    voltages = np.array([json.loads(text) for text in frame["initial_cell_voltage_v"]], dtype=float).reshape(-1, 6)
    position = frame.columns.get_loc("initial_cell_voltage_v")
    frame = frame.drop(columns=["initial_cell_voltage_v"])
    for k, cell in enumerate(_CELLS):
        frame.insert(position + k, f"initial_cell_voltage_{cell}_v", voltages[:, k])
    frame["actions"] = [[(float(t), str(a)) for t, a in json.loads(text)] for text in frame["actions"]]
    # docs/modelling-choices.md#unavailable-actions: the distinct "Chosen->Taken" pairs of a flight
    if "substitutions" in frame.columns:
        frame["substitutions"] = [[str(pair) for pair in json.loads(text)] for text in frame["substitutions"]]
    for column in _BOOLEAN_COLUMNS:
        frame[column] = frame[column].astype(bool)
    frame["run_seed"] = frame["run_seed"].astype(np.int64).astype(np.uint64)
    for column in ("fault_onset_s", "jam_time_s", "isolation_time_s", "first_emergency_action_s"):
        frame[column] = frame[column].astype(float)
    # "" in the database when no emergency action was decided: missing here, as its time is.
    frame["first_emergency_action"] = frame["first_emergency_action"].where(frame["first_emergency_action"] != "", None)
    if "first_action_state" in frame.columns:
        frame["first_action_state"] = frame["first_action_state"].where(frame["first_action_state"] != "", None)
    frame.attrs["campaign"] = {
        "name": campaign[0],
        "seed": int(np.int64(campaign[1]).astype(np.uint64)),
        "config_hash": campaign[2],
        "campaign_hash": campaign[3],
        "runs_requested": campaign[4],
        "code_version": campaign[5],
        "created_utc": campaign[6],
        "config_yaml": campaign[7],
    }
    return frame


def _telemetry_frame(text_or_file, source):
    from ._uascma import InputError

    try:
        frame = pd.read_csv(text_or_file, keep_default_na=False, na_values=[""])
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as error:
        raise InputError(f"{source}: telemetry: a telemetry CSV written by uascma ({error})") from None
    for column in ("t_s", "cma_state", "action", "imm_mode"):
        if column not in frame.columns:
            raise InputError(f"{source}: {column}: a telemetry column, but it is missing")
    # Files written before the CSV carried names: integer codes and sentinels (-1: no RUL, -1e9: MM = -inf).
    if pd.api.types.is_integer_dtype(frame["cma_state"]):
        from ._uascma import cma_state_label

        frame["cma_state"] = [cma_state_label(int(i)) for i in frame["cma_state"]]
        frame["action"] = [ACTION_NAMES[int(i)] for i in frame["action"]]
        frame["imm_mode"] = [IMM_MODE_NAMES[int(i)] for i in frame["imm_mode"]]
        frame["rul_s"] = frame["rul_s"].where(frame["rul_s"] >= 0.0)
        frame["motor_margin"] = frame["motor_margin"].where(frame["motor_margin"] > -1e8, -np.inf)
    return frame


def read_telemetry(folder):
    """Reads a flight record folder's telemetry.csv into a DataFrame, one row per telemetry sample.

    Columns are those of the CSV (SI units, frame and unit in each name: ``t_s``, ``p_W_x_m`` …), with
    ``cma_state`` the CMA state label ('N,NF,MM1,G,RM1'), ``action`` the last executed action's name
    ('NoOp' before any), ``imm_mode`` 'nominal' or 'rotorK_out', and ``rul_s`` NaN while no motor is spalled.
    ``df.attrs["summary"]`` holds summary.json when the folder has one.
    Raises uascma.InputError when the file is missing or is not a uascma telemetry CSV.
    """
    from ._uascma import InputError

    folder = os.fspath(folder)
    path = os.path.join(folder, "telemetry.csv")
    if not os.path.isfile(path):
        raise InputError(f"{folder}: telemetry.csv: a flight record folder (uascma simulate --out), but it is missing")
    frame = _telemetry_frame(path, path)
    summary = os.path.join(folder, "summary.json")
    if os.path.isfile(summary):
        with open(summary) as f:
            frame.attrs["summary"] = json.load(f)
    return frame


def telemetry_frame(flight):
    """The telemetry of a uascma.Flight (flown with telemetry=True) as read_telemetry would read it."""
    frame = _telemetry_frame(io.StringIO(flight.telemetry_csv()), "flight")
    frame.attrs["summary"] = flight.summary()
    return frame

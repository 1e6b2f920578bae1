"""The MDP engine and the CMA model from Python: arrays, closed forms, policy files equal to the CLI's."""
import json
import os

import numpy as np
import pytest

import uascma
from conftest import example, run_cli

# Value iteration stops at a Bellman residual of 1e-10 (docs/modelling-choices.md#discount): values agree to ~γ/(1−γ) ·
# 1e-10.
VALUE_TOLERANCE = 1e-8


def two_state_chain():
    """State 0 earns 1 per step and stays with 0.9 (action 'stay') or moves to 1 ('go'); 1 is absorbing, 0."""
    p = np.zeros((2, 2, 2))
    p[0, 0] = [0.9, 0.1]  # stay
    p[0, 1] = [0.0, 1.0]
    p[1, 0] = [0.0, 1.0]  # go
    p[1, 1] = [0.0, 1.0]
    r = np.array([[1.0, 0.5], [0.0, np.nan]])  # 'go' unavailable in state 1
    return uascma.build_mdp(p, r, ["s0", "s1"], ["stay", "go"])


def test_build_mdp_arrays_and_dense_round_trip():
    mdp = two_state_chain()
    assert (mdp.num_states, mdp.num_actions, mdp.num_choices) == (2, 2, 3)
    assert mdp.state_choice_begin.shape == (3,)
    assert mdp.next_state.shape == mdp.probability.shape == (mdp.num_transitions,)
    p, r = mdp.dense()
    assert p.shape == (2, 2, 2) and r.shape == (2, 2)
    assert np.isnan(r[1, 1])
    np.testing.assert_allclose(p.sum(axis=2)[~np.isnan(r.T)], 1.0)


def test_value_iteration_matches_the_closed_form():
    mdp = two_state_chain()
    gamma = 0.9
    policy, summary = uascma.solve(mdp, gamma)
    assert summary.status == uascma.SolverStatus.converged
    # stay: V = 1 + γ (0.9 V) → V = 1 / (1 − 0.81); go: 0.5. Staying wins.
    expected = 1.0 / (1.0 - gamma * 0.9)
    assert policy.action.shape == (2,) and policy.value.shape == (2,)
    assert policy.action[0] == mdp.find_action("stay")
    assert policy.value[0] == pytest.approx(expected, abs=VALUE_TOLERANCE)
    np.testing.assert_allclose(uascma.evaluate_policy(mdp, policy.action, gamma), [expected, 0.0], atol=VALUE_TOLERANCE)
    pi_policy, _ = uascma.solve(mdp, gamma, method="pi")
    np.testing.assert_array_equal(pi_policy.action, policy.action)


def test_a_row_that_does_not_sum_to_one_names_the_state_and_action():
    p = np.zeros((1, 2, 2))
    p[0, 0] = [0.5, 0.4]
    p[0, 1] = [0.0, 1.0]
    with pytest.raises(uascma.InputError, match="s0.*a|a.*s0"):
        uascma.build_mdp(p, np.zeros((2, 1)), ["s0", "s1"], ["a"])
    with pytest.raises(uascma.InputError, match="reward"):
        uascma.build_mdp(p, np.zeros((3, 1)))


def test_default_policy_file_equals_the_cli_byte_for_byte(tmp_path):
    mine = tmp_path / "python.json"
    theirs = tmp_path / "cli.json"
    solution = uascma.solve_cma()
    solution.save(str(mine))
    run_cli("policy", "solve", "--out", theirs)
    assert mine.read_bytes() == theirs.read_bytes()
    assert solution.mdp.num_states == uascma.CMA_NUM_STATES
    assert solution.policy.action.shape == (uascma.CMA_NUM_STATES,)
    assert len(solution.quadrants()) == 27 * 4


def test_changed_weights_equal_the_cli_with_a_weights_file(tmp_path):
    weights = uascma.CmaWeights().renormalised("RM", 0.4)
    assert weights.sum() == pytest.approx(1.0, abs=1e-12)
    solution = uascma.solve_cma(weights, gamma=0.9)
    yaml = tmp_path / "weights.yaml"
    groups = {"end_states": ["C", "FL", "T", "E"], "actions": ["NoOp", "Terminate", "LandASAP", "LandPract"],
              "state_features": ["FS", "MH", "MM", "BH", "RM"]}
    lines = ["gamma: 0.9", "weights:"]
    for group, names in groups.items():
        lines.append(f"  {group}: {{" + ", ".join(f"{n}: {weights.get(n)!r}" for n in names) + "}")
    yaml.write_text("\n".join(lines) + "\n")
    loaded, gamma = uascma.load_cma_config(str(yaml))
    assert gamma == 0.9 and loaded.as_dict() == weights.as_dict()
    mine, theirs = tmp_path / "python.json", tmp_path / "cli.json"
    solution.save(str(mine))
    run_cli("policy", "solve", "--weights", yaml, "--out", theirs)
    assert mine.read_bytes() == theirs.read_bytes()
    assert solution.model_hash != uascma.solve_cma().model_hash


def test_load_policy_checks_the_model_hash(tmp_path):
    path = tmp_path / "policy.json"
    solution = uascma.solve_cma(uascma.CmaWeights(NoOp=0.2))
    solution.save(str(path))
    loaded = uascma.load_policy(str(path))
    np.testing.assert_array_equal(loaded.action, solution.policy.action)
    document = json.loads(path.read_text())
    document["model_hash"] = "0" * 16
    path.write_text(json.dumps(document))
    with pytest.raises(uascma.InputError, match="model_hash"):
        uascma.load_policy(str(path))


def test_weights_errors_name_the_field():
    with pytest.raises(uascma.InputError, match="Bogus"):
        uascma.CmaWeights(Bogus=1.0)
    with pytest.raises(uascma.InputError, match="gamma"):
        uascma.solve_cma(gamma=1.5)
    assert os.path.isfile(example("cma-weights.yaml"))
    weights, gamma = uascma.load_cma_config(example("cma-weights.yaml"))
    assert 0.0 <= gamma < 1.0 and weights.sum() > 0.0

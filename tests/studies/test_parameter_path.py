"""The quantities a study on the paper's model may vary (`studies.parameter_path`)."""

from __future__ import annotations

from dataclasses import fields

import pytest

from rotorcontact import ParameterError
from rotorcontact.model.params import OPTIONAL_MACHINE_KEYS, PAPER_MACHINE_KEYS, Machine, reference_machine
from rotorcontact.studies.batch import PARAMETER_ORDER
from rotorcontact.studies.parameter_path import check_path_param, parameter_path

M = reference_machine()
REF = M.parameters()


def test_the_machine_keys_split_into_the_paper_models_and_the_general_models():
    names = [f.name for f in fields(Machine)]
    assert sorted(PAPER_MACHINE_KEYS + OPTIONAL_MACHINE_KEYS) == sorted(names)
    assert not set(PAPER_MACHINE_KEYS) & set(OPTIONAL_MACHINE_KEYS)


@pytest.mark.parametrize("key", PAPER_MACHINE_KEYS)
def test_every_paper_key_moves_the_dimensionless_parameters(key):
    value = getattr(M, key)
    path = parameter_path(REF, key, [0.9 * value, value], M)
    assert path[0] != REF and path[1] == REF


@pytest.mark.parametrize("extra", [dict(gravity=9.81), dict(polar_inertia=0.04), dict(static_force=100.0),
                                   dict(stiffness_x=2e5, stiffness_y=3e6)])
def test_general_keys_leave_the_dimensionless_parameters_alone(extra):
    assert Machine(**{**M.as_dict(), **extra}).parameters() == REF


@pytest.mark.parametrize("key", OPTIONAL_MACHINE_KEYS)
def test_general_keys_are_refused_as_the_varied_quantity(key):
    with pytest.raises(ParameterError, match=rf"^param = '{key}' is a key of the general model \(MODEL.md §7-8\), "
                                             r"which this study leaves out .* allowed: gamma, .*, or with a machine "
                                             r"mass, .*restitution$"):
        parameter_path(REF, key, [1.0, 2.0], M)
    with pytest.raises(ParameterError, match=rf"^--param = '{key}' is a key of the general model"):
        check_path_param(key, M, "--param")


def test_check_path_param_takes_model_parameters_and_paper_keys():
    for name in PARAMETER_ORDER:
        assert check_path_param(name, None) == name
    for key in PAPER_MACHINE_KEYS:
        assert check_path_param(key, M) == key
        with pytest.raises(ParameterError, match=rf"^param = '{key}' is a machine quantity; allowed with a machine"):
            check_path_param(key, None)
    for bad in ("nonsense", None, 3):
        with pytest.raises(ParameterError, match=r"^param = .* is invalid; allowed: gamma"):
            check_path_param(bad, M)


@pytest.mark.parametrize("values", [[0.1, 0.05], [0.1, 0.1], [0.05, 0.1, 0.08]])
def test_values_out_of_order_or_repeated_are_refused(values):
    """A path is taken in order (the attractors' appearing and disappearing are read along it)."""
    with pytest.raises(ParameterError, match=r"^values of 'gamma' = .* must increase strictly"):
        parameter_path(REF, "gamma", values)
    assert [q.gamma for q in parameter_path(REF, "gamma", [0.05, 0.1])] == [0.05, 0.1]

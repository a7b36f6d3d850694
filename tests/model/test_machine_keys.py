"""The general machine's keys (MODEL.md §7): units, defaults that keep the paper's machine, validation."""

from __future__ import annotations

import pytest

from rotorcontact import Machine, ParameterError, load_machine, reference_machine

TOML_GENERAL = """
mass = 50.0
damping = "1.4 kN*s/m"
stiffness = 9.8e5
eccentricity = "0.3 mm"
clearance = "0.7 mm"
rotor_radius = 0.04
unbalance_phase = 0.21
speed = "12000 rpm"
friction = 0.15
restitution = 0.95
stiffness_x = "1.2 MN/m"
damping_y = "2 kN*s/m"
gravity = "9.81 m/s^2"
polar_inertia = "0.04 kg*m^2"
race_inertia = "2e-4 kg m^2"
race_drag_torque = "0.1 N*m"
race_drag_coefficient = "1e-4 N*m*s"
"""


def test_absent_keys_keep_the_paper_machine():
    m = reference_machine()
    assert (m.kx, m.ky, m.cx, m.cy) == (m.stiffness, m.stiffness, m.damping, m.damping)
    assert m.g == 0.0 and m.fs == 0.0
    assert not m.free_speed and not m.has_race and not m.needs_general_model
    # the dict of an existing machine is what it was: the ten fields of MODEL.md §1
    assert set(m.as_dict()) == set(Machine.units()) - {
        "stiffness_x", "stiffness_y", "damping_x", "damping_y", "gravity", "static_force", "polar_inertia",
        "race_inertia", "race_drag_torque", "race_drag_coefficient", "contact", "contact_stiffness",
        "contact_exponent", "stator_mass", "stator_stiffness", "stator_stiffness_x", "stator_stiffness_y",
        "stator_damping", "stator_damping_x", "stator_damping_y"}


def test_general_keys_in_si_with_units(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(TOML_GENERAL)
    m = load_machine(path)
    assert m.kx == pytest.approx(1.2e6, rel=1e-15) and m.ky == 9.8e5
    assert m.cx == pytest.approx(1400.0, rel=1e-15) and m.cy == pytest.approx(2000.0, rel=1e-15)
    assert m.g == pytest.approx(9.81, rel=1e-15)
    assert m.fs == pytest.approx(50.0 * 9.81, rel=1e-15)  # default: balances gravity
    assert m.polar_inertia == pytest.approx(0.04, rel=1e-15)
    assert m.race_inertia == pytest.approx(2e-4, rel=1e-15)
    assert m.race_radius == pytest.approx(0.0407, rel=1e-15)
    assert m.needs_general_model and m.free_speed and m.has_race
    assert Machine(**m.as_dict()) == m


@pytest.mark.parametrize("key, value, allowed", [
    ("stiffness_x", 0.0, "(0, inf)"), ("damping_y", -1.0, "[0, inf)"), ("gravity", -9.81, "[0, 1e+06]"),
    ("polar_inertia", 0.0, "(0, inf)"), ("race_drag_torque", -1.0, "[0, inf)"),
])
def test_general_keys_out_of_range(key, value, allowed):
    base = reference_machine().as_dict()
    extra = {"polar_inertia": 0.04, "race_inertia": 1e-4, "race_drag_torque": 0.0, "race_drag_coefficient": 0.0}
    with pytest.raises(ParameterError) as info:
        Machine(**{**base, **extra, key: value})
    assert key in str(info.value) and repr(value) in str(info.value) and allowed in str(info.value)


def test_race_needs_all_keys_and_a_free_speed():
    base = reference_machine().as_dict()
    with pytest.raises(ParameterError, match="race_drag_torque"):
        Machine(**base, polar_inertia=0.04, race_inertia=1e-4, race_drag_coefficient=0.0)
    with pytest.raises(ParameterError, match="polar_inertia"):
        Machine(**base, race_inertia=1e-4, race_drag_torque=0.0, race_drag_coefficient=0.0)


def test_static_force_given_is_used_and_wrong_units_refused(tmp_path):
    m = Machine(**reference_machine().as_dict(), gravity=9.81, static_force="0.2 kN")
    assert m.fs == pytest.approx(200.0, rel=1e-15)
    path = tmp_path / "bad.toml"
    path.write_text(TOML_GENERAL.replace('gravity = "9.81 m/s^2"', 'gravity = "9.81 m"'))
    with pytest.raises(ParameterError, match="gravity"):
        load_machine(path)


@pytest.mark.parametrize("changes, word", [
    ({"gravity": 1e300}, "gravity = 1e+300 is out of range; allowed: [0, 1e+06]"),
    ({"speed": 1e29}, "speed = 1e+29 is out of range; allowed: (0, 1e+06]"),
    ({"contact": "compliant", "contact_stiffness": 1e300}, "contact_stiffness = 1e+300 N/m^1.5 is out of range"),
])
def test_absurd_machine_values_are_refused_by_name(changes, word):
    from rotorcontact import Machine, ParameterError, reference_machine

    with pytest.raises(ParameterError) as err:
        Machine(**{**reference_machine().as_dict(), **changes})
    assert word in str(err.value) and "allowed" in str(err.value)


def test_contact_stiffness_bound_is_the_force_at_one_clearance():
    from rotorcontact import Machine, ParameterError, reference_machine
    from rotorcontact.model.params import MAX_CONTACT_FORCE

    base = {**reference_machine().as_dict(), "contact": "compliant"}
    limit = MAX_CONTACT_FORCE / base["clearance"] ** 1.5
    assert Machine(**base, contact_stiffness=0.99 * limit).contact_stiffness == 0.99 * limit
    with pytest.raises(ParameterError, match="K_c c_r\\^n <= 1e\\+15 N"):
        Machine(**base, contact_stiffness=1.01 * limit)

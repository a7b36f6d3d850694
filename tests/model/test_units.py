"""Quantities with units in machine files are converted to SI exactly as by hand."""

from __future__ import annotations

import math
import re

import pytest

from rotorcontact import Machine, ParameterError, load_machine
from rotorcontact.model.units import option_quantity, quantity_in
from reference_parameters import REF_MACHINE


@pytest.mark.parametrize(
    "text, unit, expected",
    [
        ("0.7 mm", "m", 0.7e-3),
        ("700 um", "m", 0.7e-3),
        ("12000 rpm", "rad/s", 12000 * 2 * math.pi / 60),
        ("3000 rpm", "rad/s", 100 * math.pi),
        ("1.4 kN*s/m", "N s/m", 1400.0),
        ("980 kN/m", "N/m", 9.8e5),
        ("0.98 MN/m", "N/m", 9.8e5),
        ("50000 g", "kg", 50.0),
        ("180 deg", "rad", math.pi),
        ("5 mm/s", "m/s", 5e-3),
        ("0.15", "1", 0.15),
        ("42", "kg", 42.0),
    ],
)
def test_conversions_match_hand_computation(text, unit, expected):
    assert quantity_in("x", text, unit) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize(
    "text, unit, fragment",
    [
        ("0.7 furlongz", "m", "unknown unit"),
        ("0.7 kg", "m", "units of [mass]"),
        ("fast", "rad/s", "has no number"),
        ("rpm", "rad/s", "has no number"),                 # pint alone reads it as 1 rpm
        ("m", "m", "has no number"),
        ("1 rpm rpm +", "rad/s", "not a quantity"),
        ("inf m", "m", "not finite"),
        ("1 rpm**1000", "rad/s", "not finite"),  # the conversion factor overflows
        (None, "m", "is not text"),
        (0.7, "m", "is not text"),
    ],
)
def test_bad_quantities_are_rejected_clearly(text, unit, fragment):
    with pytest.raises(ParameterError) as err:
        quantity_in("clearance", text, unit)
    assert "clearance" in str(err.value) and repr(text) in str(err.value) and fragment in str(err.value)


def _write(tmp_path, body: str):
    path = tmp_path / "m.toml"
    path.write_text(body, encoding="utf-8")
    return path


GOOD = """
mass = "50 kg"
damping = "1.4 kN*s/m"
stiffness = "980 kN/m"
eccentricity = "0.3 mm"
clearance = "0.7 mm"
rotor_radius = "40 mm"
unbalance_phase = 0.21
speed = "1759 rpm"
friction = 0.15
restitution = "0.95"
"""


def test_machine_file_with_units_equals_the_si_machine(tmp_path):
    m = load_machine(_write(tmp_path, GOOD))
    assert m == Machine(**dict(REF_MACHINE, speed=1759 * 2 * math.pi / 60))


@pytest.mark.parametrize(
    "old, new, fragment",
    [
        ('clearance = "0.7 mm"', 'clearance = "0 mm"', "clearance"),
        ('mass = "50 kg"', 'mass = "-50 kg"', "mass"),
        ('clearance = "0.7 mm"', 'clearance = "0.7 parsecz"', "unknown unit"),
        ('speed = "1759 rpm"', 'speed = "1759 kg"', "speed"),
        ('mass = "50 kg"\n', "", "missing key 'mass'"),
    ],
)
def test_bad_machine_files_are_rejected(tmp_path, old, new, fragment):
    with pytest.raises(ParameterError) as err:
        load_machine(_write(tmp_path, GOOD.replace(old, new)))
    assert fragment in str(err.value)


@pytest.mark.parametrize(
    "text, unit, expected",
    [
        ("50 Hz", "rad/s", 100 * math.pi),          # a frequency of rotation counts revolutions
        ("50 Hz", "rpm", 3000.0),
        ("3000 rev/min", "rad/s", 100 * math.pi),
        ("50 rev/s", "rpm", 3000.0),
        ("360 deg/s", "rad/s", 2 * math.pi),        # an angular speed stays one
        ("3 krpm", "rpm", 3000.0),                  # prefixed angular speeds stay ones too
        ("3 krpm", "rad/s", 100 * math.pi),
        ("0.003 Mrpm", "rad/s", 100 * math.pi),
        ("0.05 kHz", "rpm", 3000.0),                # and prefixed frequencies count revolutions
        ("400 grad/s", "rad/s", 2 * math.pi),
    ],
)
def test_rotation_frequencies_count_revolutions(text, unit, expected):
    assert quantity_in("speed", text, unit) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("text", ["184.2 1/s", "184.2 / s", "184.2 s**-1", "3000 / minute", "3000/min"])
@pytest.mark.parametrize("unit", ["rad/s", "rpm"])
def test_a_rate_without_an_angle_or_hertz_is_refused_as_ambiguous(text, unit):
    # 1/s is rad/s in SI, but as often meant as revolutions per second: a 2 pi error either way
    with pytest.raises(ParameterError, match=rf"^speed = '{re.escape(text)}' is a rate without an angle: rad/s or "
                                             r"revolutions per second\? allowed: "):
        quantity_in("speed", text, unit)


@pytest.mark.parametrize("unit", ["rad/s", "rpm"])
def test_an_options_angular_speed_must_carry_its_unit(unit):
    """A bare --speed 30000 could mean rpm or rad/s: it is refused; with a unit it is converted."""
    with pytest.raises(ParameterError) as err:
        option_quantity("--speed", "30000", unit)
    assert str(err.value).startswith("--speed = '30000' has no unit; allowed: an angular speed with its unit")
    assert option_quantity("--speed", "3000rpm", unit) == quantity_in("--speed", "3000rpm", unit)
    # other quantities of an option may be bare, in their unit
    assert option_quantity("--t-end", "2", "s") == 2.0


@pytest.mark.parametrize("key, text, fragment", [
    ("speed", "12000", "has no unit"),             # rpm or rad/s? a string must say
    ("unbalance_phase", "30", "has no unit"),      # degrees or radians?
    ("clearance", "0.0007", "has no unit"),
])
def test_a_machine_value_written_as_a_string_carries_its_unit(tmp_path, key, text, fragment):
    """A number is in SI units; a string is a quantity, and one without its unit is refused, not guessed."""
    with pytest.raises(ParameterError) as err:
        Machine(**{**REF_MACHINE, key: text})
    assert f"{key} = {text!r} {fragment}" in str(err.value)
    m = Machine(**{**REF_MACHINE, "speed": "12000 rpm", "unbalance_phase": "90 deg", "friction": "0.2"})
    assert m.speed == pytest.approx(12000 * math.pi / 30, rel=1e-15)
    assert m.unbalance_phase == pytest.approx(math.pi / 2, rel=1e-15) and m.friction == 0.2


def test_a_machine_values_range_error_shows_the_text_given_and_its_si_value():
    from rotorcontact.model.params import check_machine_value

    with pytest.raises(ParameterError) as err:
        check_machine_value("speed", "-12000rpm", label="--speed")
    assert str(err.value) == "--speed = '-12000rpm' (-1256.64 rad/s) is out of range; allowed: (0, 1e+06] rad/s"
    assert check_machine_value("speed", "12000 rpm") == quantity_in("speed", "12000 rpm", "rad/s")


def test_a_machine_takes_numpy_numbers_as_python_numbers():
    import numpy as np

    from rotorcontact import Machine, reference_machine

    data = reference_machine().as_dict()
    plain = Machine.from_mapping(data)
    data.update(mass=np.int64(round(data["mass"])), speed=np.array(data["speed"]), clearance=np.float32(0.5e-3))
    numpy = Machine.from_mapping(data)
    assert numpy.mass == round(plain.mass) and numpy.speed == plain.speed
    assert numpy.clearance == float(np.float32(0.5e-3))
    data.update(speed=np.bool_(True))
    with pytest.raises(ParameterError, match=r"speed = .* is not a number"):
        Machine.from_mapping(data)



def test_a_machine_value_that_is_not_a_quantity_is_named_first():
    from rotorcontact import Machine, reference_machine

    with pytest.raises(ParameterError, match=r"^speed = 'abc' has no number"):
        Machine(**{**reference_machine().as_dict(), "speed": "abc"})


@pytest.mark.parametrize("text", ["0.15 deg", "0.95 rad", "1 rev"])
def test_an_angle_is_no_plain_number(text):
    # pint counts angles as dimensionless: a friction coefficient of "0.15 deg" would silently be 0.0026
    with pytest.raises(ParameterError, match=rf"^friction = '{re.escape(text)}' is an angle; allowed: a plain number"):
        quantity_in("friction", text, "1")
    assert quantity_in("friction", "15 %", "1") == pytest.approx(0.15, rel=1e-15)


def test_a_contact_stiffness_with_units_is_converted_with_the_machines_exponent():
    # the exponent, given as text too, is read before K_c, whose unit N/m^n depends on it
    from rotorcontact import Machine, reference_machine

    base = {**reference_machine().as_dict(), "contact": "compliant"}
    assert Machine(**base, contact_stiffness="1 kN/mm", contact_exponent="1").contact_stiffness == \
        pytest.approx(1e6, rel=1e-15)
    assert Machine(**base, contact_stiffness="1 kN/mm**2", contact_exponent="2").contact_stiffness == \
        pytest.approx(1e9, rel=1e-15)
    with pytest.raises(ParameterError, match=r"^contact_stiffness = '1 kN/mm\*\*1.5' has units of .* expected units "
                                             r"convertible to N/m\*\*1.0"):
        Machine(**base, contact_stiffness="1 kN/mm**1.5", contact_exponent="1")


@pytest.mark.parametrize("text, spelt", [("12000 RPM", "rpm"), ("50 hz", "Hz"), ("3 KRPM", "krpm"),
                                          ("0.05 KHZ", "kHz"), ("0.001 MHZ", "MHz"), ("0.003 MRPM", "Mrpm")])
def test_a_unit_in_the_wrong_case_is_refused_with_its_spelling(text, spelt):
    unit = text.split()[1]
    with pytest.raises(ParameterError, match=rf"^speed = '{text}': unknown unit '{unit}' \('{unit}' is written "
                                             rf"'{spelt}'\); expected a quantity in rad/s$"):
        quantity_in("speed", text, "rad/s")
    assert quantity_in("speed", text.replace(unit, spelt), "rad/s") > 0.0


def test_a_temperature_is_refused_as_a_unit_with_an_offset():
    with pytest.raises(ParameterError, match=r"^speed = '20 degC' has a unit with an offset \(a temperature\)"):
        quantity_in("speed", "20 degC", "rad/s")


@pytest.mark.parametrize("text, unit, expected", [
    ("27.6 mil", "m", 27.6 * 0.0254 / 1000),  # an inch is 25.4 mm exactly
    ("3 mils", "um", 3 * 25.4),
    ("1e9 N/mil", "N/m", 1e9 / (0.0254 / 1000)),
    ("2 mil", "mm", 2 * 0.0254),
])
def test_a_mil_is_the_thousandth_of_an_inch_where_no_angle_is_meant(text, unit, expected):
    assert quantity_in("x", text, unit) == pytest.approx(expected, rel=1e-15)


def test_a_machine_takes_its_clearance_in_mils():
    m = Machine(**{**REF_MACHINE, "clearance": "27.6 mil"})
    assert m.clearance == pytest.approx(27.6 * 0.0254 / 1000, rel=1e-15)
    with pytest.raises(ParameterError, match=r"friction = '0.1 mil' has units of \[length\]"):
        quantity_in("friction", "0.1 mil", "1")

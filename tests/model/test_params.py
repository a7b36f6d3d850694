"""Parameters, the SI Machine, its conversion (MODEL.md §1-§2) and the input rules:
every bad value gets a ParameterError naming the parameter, the value and what is allowed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import Machine, ParameterError, Parameters, load_machine, reference_machine
from reference_parameters import REF, REF_MACHINE, REF_MACHINE_TOML, REF_VALUES, replace_line
from rotorcontact.model.params import OPTIONAL_MACHINE_KEYS

PARAMS = dict(gamma=0.1, omega=0.76, rho=0.4, mu=0.15, d=0.95, phi=0.21, r_ratio=57.0)


def write(tmp_path, text, name="machine.toml", mode="w"):
    path = tmp_path / name
    if mode == "wb":
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


# ---------------------------------------------------------------------------
# conversion
# ---------------------------------------------------------------------------


def test_reference_machine_is_the_rig_of_the_model():
    m = reference_machine()
    assert m.as_dict() == REF_MACHINE


def test_machine_to_parameters_by_hand():
    p = Machine(**REF_MACHINE).parameters()
    m, c, k, e, cr, R, ph, Om, mu, d = (REF_MACHINE[n] for n in REF_MACHINE)
    assert p.gamma == pytest.approx(c / (m * Om), rel=1e-15)
    assert p.omega == pytest.approx(math.sqrt(k / (m * Om**2)), rel=1e-15)
    assert p.rho == pytest.approx(e / cr, rel=1e-15)
    assert p.r_ratio == pytest.approx(R / cr, rel=1e-15)
    assert (p.mu, p.d, p.phi) == (mu, d, ph)
    # the values quoted in MODEL.md §2
    assert p.gamma == pytest.approx(0.152, abs=5e-4)
    assert p.omega == pytest.approx(0.76, abs=5e-3)
    assert p.rho == pytest.approx(3 / 7, rel=1e-15)
    assert p.r_ratio == pytest.approx(57.142857, rel=1e-6)
    assert Parameters.reference() == p
    # the numbers the tests use for the reference set
    assert p == REF and p.as_dict() == REF_VALUES


def test_another_machine_by_hand():
    data = dict(REF_MACHINE, mass=12.0, damping=300.0, stiffness=2.0e5, eccentricity=1e-4, clearance=5e-4,
                rotor_radius=0.02, unbalance_phase=-1.0, speed=100.0, friction=0.3, restitution=0.5)
    p = Machine(**data).parameters()
    assert p.gamma == pytest.approx(300.0 / (12.0 * 100.0), rel=1e-15)
    assert p.omega == pytest.approx(math.sqrt(2.0e5 / (12.0 * 100.0**2)), rel=1e-15)
    assert p.rho == pytest.approx(0.2, rel=1e-15)
    assert p.r_ratio == pytest.approx(40.0, rel=1e-15)
    assert (p.mu, p.d, p.phi) == (0.3, 0.5, -1.0)
    m2 = Machine(**data).with_speed(200.0)
    assert m2.speed == 200.0
    assert m2.parameters().gamma == pytest.approx(300.0 / (12.0 * 200.0), rel=1e-15)


def test_scales_si():
    m = Machine(**REF_MACHINE)
    mass, clearance, speed = REF_MACHINE["mass"], REF_MACHINE["clearance"], REF_MACHINE["speed"]
    assert m.length_scale == clearance
    assert m.time_scale == pytest.approx(1 / speed, rel=1e-15)
    assert m.force_scale == pytest.approx(mass * clearance * speed ** 2, rel=1e-15)
    assert m.impulse_scale == pytest.approx(mass * clearance * speed, rel=1e-15)
    assert set(Machine.units()) == set(REF_MACHINE) | set(OPTIONAL_MACHINE_KEYS)


def test_parameters_k_and_replace():
    p = Parameters(**PARAMS)
    k = 0.4 * complex(math.cos(0.21), math.sin(0.21)) / complex(0.76**2 - 1, 0.1)
    assert abs(p.k - k) < 1e-15
    q = p.replace(gamma=0.2)
    assert q.gamma == 0.2 and q.omega == p.omega and p.gamma == 0.1
    assert p.as_dict() == PARAMS
    with pytest.raises(ParameterError, match="'nope'"):
        p.replace(nope=1.0)
    with pytest.raises(ParameterError, match=r"d = 2\.0"):
        p.replace(d=2.0)


def test_boundary_values_are_accepted():
    Parameters(**dict(PARAMS, d=0.0, mu=0.0, rho=0.0, r_ratio=0.0, gamma=0.0))
    Parameters(**dict(PARAMS, d=1.0))
    Parameters(**dict(PARAMS, gamma=-0.1))  # negative damping is allowed for orbit analysis
    Machine(**dict(REF_MACHINE, damping=0.0, eccentricity=0.0, rotor_radius=0.0, friction=0.0, restitution=0.0))
    Machine(**dict(REF_MACHINE, restitution=1.0, unbalance_phase=-7.0))


# ---------------------------------------------------------------------------
# bad values
# ---------------------------------------------------------------------------


def check_message(exc, name, value_text, allowed=None):
    msg = str(exc.value)
    assert name in msg, msg
    assert value_text in msg, msg
    if allowed is not None:
        assert allowed in msg, msg


@pytest.mark.parametrize("name", list(PARAMS))
@pytest.mark.parametrize("value,text", [(math.nan, "nan"), (math.inf, "inf"), (-math.inf, "-inf")])
def test_parameters_non_finite(name, value, text):
    with pytest.raises(ParameterError) as exc:
        Parameters(**dict(PARAMS, **{name: value}))
    check_message(exc, f"{name} =", text, "finite")


@pytest.mark.parametrize("name", list(PARAMS))
def test_parameters_not_a_number(name):
    with pytest.raises(ParameterError) as exc:
        Parameters(**dict(PARAMS, **{name: "abc"}))
    check_message(exc, f"{name} =", "'abc'")
    with pytest.raises(ParameterError):
        Parameters(**dict(PARAMS, **{name: None}))
    with pytest.raises(ParameterError):
        Parameters(**dict(PARAMS, **{name: 1 + 2j}))


@pytest.mark.parametrize(
    "name,value,allowed",
    [
        ("omega", 0.0, "(0, 1e+06]"),
        ("omega", -0.5, "(0, 1e+06]"),
        ("rho", -0.1, "[0, 1e+06]"),
        ("mu", -0.01, "[0, 1e+06]"),
        ("d", -0.01, "[0, 1]"),
        ("d", 1.01, "[0, 1]"),
        ("r_ratio", -1.0, "[0, 1e+06]"),
        # magnitudes: the dimensionless groups of a rotor are of order one
        ("gamma", 1e308, "[-1e+06, 1e+06]"),
        ("gamma", -2e6, "[-1e+06, 1e+06]"),
        ("omega", 1e200, "(0, 1e+06]"),
        ("rho", 1e7, "[0, 1e+06]"),
        ("mu", 1e300, "[0, 1e+06]"),
        ("phi", 1e300, "[-1e+06, 1e+06]"),
        ("r_ratio", 1e10, "[0, 1e+06]"),
    ],
)
def test_parameters_out_of_range(name, value, allowed):
    with pytest.raises(ParameterError) as exc:
        Parameters(**dict(PARAMS, **{name: value}))
    check_message(exc, f"{name} = {value!r}", repr(value), allowed)


@pytest.mark.parametrize("name", list(REF_MACHINE))
@pytest.mark.parametrize("value,text", [(math.nan, "nan"), (math.inf, "inf")])
def test_machine_non_finite(name, value, text):
    with pytest.raises(ParameterError) as exc:
        Machine(**dict(REF_MACHINE, **{name: value}))
    check_message(exc, f"{name} =", text, "finite")


@pytest.mark.parametrize(
    "name,value,allowed",
    [
        ("mass", 0.0, "(0, inf)"),
        ("mass", -50.0, "(0, inf)"),
        ("stiffness", 0.0, "(0, inf)"),
        ("stiffness", -1.0, "(0, inf)"),
        ("clearance", 0.0, "[1e-09, 1]"),
        ("clearance", -1e-3, "[1e-09, 1]"),
        ("speed", 0.0, "(0, 1e+06]"),
        ("speed", -184.2, "(0, 1e+06]"),
        ("restitution", -0.1, "[0, 1]"),
        ("restitution", 1.5, "[0, 1]"),
        ("friction", -0.15, "[0, inf)"),
        ("eccentricity", -1e-5, "[0, inf)"),
        ("damping", -1.0, "[0, inf)"),
        ("rotor_radius", -0.04, "[0, inf)"),
    ],
)
def test_machine_out_of_range(name, value, allowed):
    with pytest.raises(ParameterError) as exc:
        Machine(**dict(REF_MACHINE, **{name: value}))
    check_message(exc, f"{name} = {value!r}", repr(value), allowed)


def test_machine_whose_dimensionless_groups_overflow():
    m = Machine(**dict(REF_MACHINE, speed=1e-170))
    with pytest.raises(ParameterError):
        m.parameters()


# ---------------------------------------------------------------------------
# TOML files
# ---------------------------------------------------------------------------


def test_load_machine_file_and_table_form(tmp_path):
    assert load_machine(write(tmp_path, REF_MACHINE_TOML)) == Machine(**REF_MACHINE)
    assert load_machine(write(tmp_path, "[machine]\n" + REF_MACHINE_TOML, "t.toml")) == Machine(**REF_MACHINE)
    assert load_machine("reference") == Machine(**REF_MACHINE)
    # integers are numbers too
    assert load_machine(write(tmp_path, replace_line(REF_MACHINE_TOML, "mass", "mass = 50"), "i.toml")).mass == 50.0


def test_toml_unknown_key(tmp_path):
    path = write(tmp_path, REF_MACHINE_TOML + "colour = 3.0\n")
    with pytest.raises(ParameterError) as exc:
        load_machine(path)
    check_message(exc, "colour", "unknown")
    assert "mass" in str(exc.value)  # lists what is allowed


def test_toml_unknown_key_in_table(tmp_path):
    path = write(tmp_path, "[machine]\n" + REF_MACHINE_TOML + "spin = 1.0\n")
    with pytest.raises(ParameterError) as exc:
        load_machine(path)
    check_message(exc, "spin", "unknown")


@pytest.mark.parametrize("key", list(REF_MACHINE))
def test_toml_missing_key(tmp_path, key):
    text = "\n".join(line for line in REF_MACHINE_TOML.splitlines() if line.split("=")[0].strip() != key) + "\n"
    with pytest.raises(ParameterError) as exc:
        load_machine(write(tmp_path, text))
    check_message(exc, repr(key), "missing")


@pytest.mark.parametrize(
    "text",
    [
        "mass = \n",
        "mass == 50\n",
        "[machine\nmass = 50\n",
        "mass = 50.0\nmass = 51.0\n",
        'mass = "50\n',
    ],
)
def test_toml_malformed(tmp_path, text):
    path = write(tmp_path, text)
    with pytest.raises(ParameterError) as exc:
        load_machine(path)
    assert "malformed" in str(exc.value) or "TOML" in str(exc.value)
    assert str(path) in str(exc.value)


def test_toml_not_utf8(tmp_path):
    path = write(tmp_path, b"mass = 50.0\n\xff\xfe = 1\n", mode="wb")
    with pytest.raises(ParameterError) as exc:
        load_machine(path)
    assert str(path) in str(exc.value)


@pytest.mark.parametrize(
    "key,line,text",
    [
        ("mass", 'mass = "heavy"', "'heavy'"),
        ("mass", "mass = true", "True"),
        ("stiffness", "stiffness = [1.0, 2.0]", "[1.0, 2.0]"),
        ("speed", "speed = { value = 3.0 }", "value"),
        ("mass", "mass = nan", "nan"),
        ("clearance", "clearance = inf", "inf"),
        ("mass", "mass = 0.0", "0.0"),
        ("stiffness", "stiffness = -9.8e5", "-980000.0"),
        ("clearance", "clearance = 0", "0"),
        ("speed", "speed = -1", "-1"),
        ("restitution", "restitution = 1.2", "1.2"),
        ("restitution", "restitution = -0.5", "-0.5"),
        ("friction", "friction = -0.1", "-0.1"),
        ("eccentricity", "eccentricity = -3e-4", "-0.0003"),
    ],
)
def test_toml_bad_values(tmp_path, key, line, text):
    path = write(tmp_path, replace_line(REF_MACHINE_TOML, key, line))
    with pytest.raises(ParameterError) as exc:
        load_machine(path)
    check_message(exc, key, text)


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(ParameterError) as exc:
        load_machine(tmp_path / "nope.toml")
    check_message(exc, "machine", "nope.toml")
    with pytest.raises(ParameterError):
        load_machine(tmp_path)


def test_from_mapping_rejects_non_tables():
    with pytest.raises(ParameterError):
        Machine.from_mapping([1, 2, 3])


def test_a_folder_given_as_machine_file_is_called_a_folder(tmp_path):
    with pytest.raises(ParameterError, match="is a folder, not a file") as exc:
        load_machine(tmp_path)
    assert "no such file" not in str(exc.value)


def test_a_machine_file_that_is_not_a_regular_file_is_called_so():
    with pytest.raises(ParameterError, match=r"^machine = '/dev/null': not a regular file; give a TOML file"):
        load_machine("/dev/null")


@pytest.mark.parametrize("name", sorted(PARAMS))
@pytest.mark.parametrize("flag", [True, False])
def test_bools_are_refused_for_float_parameters(name, flag):
    with pytest.raises(ParameterError, match=rf"{name} = {flag} is a bool, not a number"):
        Parameters(**{**PARAMS, name: flag})


@pytest.mark.parametrize("text", ["0.1", b"0.1", "nan", np.array("0.1")])
def test_text_is_refused_where_a_number_is_required(text):
    # float() would read it; a Python caller gives numbers, and only the command line and Machine parse text
    with pytest.raises(ParameterError, match=r"gamma = .* is text, not a number"):
        Parameters(**{**PARAMS, "gamma": text})
    with pytest.raises(ParameterError, match=r"gamma = .* is text, not a number"):
        REF.replace(gamma=text)


def test_bools_are_refused_for_machine_values():
    with pytest.raises(ParameterError, match="mass = True is a bool"):
        Machine(**{**REF_MACHINE, "mass": True})


def test_machine_takes_strings_with_units_as_machine_files_do(tmp_path):
    m = Machine(**{**REF_MACHINE, "speed": "12000 rpm", "clearance": "0.7 mm", "damping": "1.4 kN*s/m"})
    assert m.speed == pytest.approx(12000 * 2 * math.pi / 60, rel=1e-14)
    assert m.clearance == pytest.approx(0.7e-3, rel=1e-14) and m.damping == pytest.approx(1400.0, rel=1e-14)
    path = write(tmp_path, REF_MACHINE_TOML.replace("speed = 184.2", 'speed = "12000 rpm"'))
    assert load_machine(path) == Machine(**{**REF_MACHINE, "speed": "12000 rpm"})
    with pytest.raises(ParameterError, match="speed = '12000 bananas'.*unknown unit"):
        Machine(**{**REF_MACHINE, "speed": "12000 bananas"})
    with pytest.raises(ParameterError, match="speed = '3 m'.*rad/s"):
        Machine(**{**REF_MACHINE, "speed": "3 m"})


# ---------------------------------------------------------------------------
# bounds of magnitude reach every entry point
# ---------------------------------------------------------------------------


def test_the_largest_allowed_magnitudes_are_accepted():
    from rotorcontact.model.params import MAX_MAGNITUDE

    p = Parameters(**dict(PARAMS, gamma=-MAX_MAGNITUDE, omega=MAX_MAGNITUDE, rho=MAX_MAGNITUDE, mu=MAX_MAGNITUDE,
                          phi=-MAX_MAGNITUDE, r_ratio=MAX_MAGNITUDE))
    assert p.omega == MAX_MAGNITUDE


def test_simulate_refuses_absurd_parameters_and_initial_states():
    from rotorcontact import simulate
    from rotorcontact.model.params import MAX_VELOCITY

    ref = Parameters(**PARAMS)
    with pytest.raises(ParameterError, match=r"omega = 1e\+200 is out of range"):
        simulate(ref.replace(omega=1e200), 0j, 0j, 10.0)
    with pytest.raises(ParameterError, match=r"du0 = 1e\+308,0.0 is too fast.*allowed: \|du0\| <= 1e\+06"):
        simulate(ref, 0j, 1e308 + 0j, 10.0)
    with pytest.raises(ParameterError, match="du0"):
        simulate(ref, 0j, (0.0, 2 * MAX_VELOCITY), 10.0)
    traj = simulate(ref, 0j, complex(MAX_VELOCITY, 0.0), 1.0)  # the largest allowed shock still runs
    assert traj.status in ("completed", "max-events")


def test_a_machine_whose_groups_are_out_of_range_names_them():
    with pytest.raises(ParameterError, match=r"gamma = .* is out of range; allowed: \[-1e\+06, 1e\+06\]"):
        Machine(**dict(REF_MACHINE, speed=1e-6)).parameters()


def test_replace_is_the_constructor_with_the_changes():
    """replace validates only what changes, as the constructor does, and computes its own k."""
    from dataclasses import asdict

    base = Parameters.reference()
    _ = base.k  # cached on the base
    for changes in ({"gamma": 0.3}, {"omega": 2, "phi": -1.0}, {"d": 1.0, "mu": 0}):
        new = base.replace(**changes)
        ref = Parameters(**{**asdict(base), **changes})
        assert new == ref and asdict(new) == asdict(ref) and all(type(v) is float for v in asdict(new).values())
        assert new.k == ref.k
    assert base.replace(gamma=0.3).k != base.k  # not the base's cached value
    for changes in ({"d": 1.5}, {"omega": 0.0}, {"gamma": float("nan")}, {"mu": "x"}, {"rho": True}):
        name, value = next(iter(changes.items()))
        with pytest.raises(ParameterError) as by_replace:
            base.replace(**changes)
        with pytest.raises(ParameterError) as by_constructor:
            Parameters(**{**asdict(base), name: value})
        assert str(by_replace.value) == str(by_constructor.value)
    with pytest.raises(ParameterError, match=r"^k = .* is not a parameter \(unknown parameter 'k'\)"):
        base.replace(k=1.0)


@pytest.mark.parametrize("value", [np.complex128(0.1 + 1j), np.complex64(0.1), 0.1 + 0j, np.array(0.1 + 0j)])
def test_a_complex_number_is_refused_not_cut_to_its_real_part(value):
    from rotorcontact.model.params import check_finite

    with pytest.raises(ParameterError, match=r"^gamma = .* is complex; a finite real number is required$"):
        Parameters(gamma=value, omega=0.76, rho=0.4, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match=r"^mass = .* is complex"):
        check_finite("mass", value)


def test_a_velocity_is_a_number():
    import numpy as np

    from rotorcontact.model.params import MAX_VELOCITY, check_velocity

    assert check_velocity("du0", np.complex64(1 + 2j)) == 1 + 2j and check_velocity("du0", 3) == 3 + 0j
    for bad in (True, None, "1", [1.0, 2.0]):
        with pytest.raises(ParameterError, match=r"^du0 = .* (is not a number|is a bool|is text)"):
            check_velocity("du0", bad)
    with pytest.raises(ParameterError, match=r"^du0 = .* is too fast"):
        check_velocity("du0", 2 * MAX_VELOCITY)


@pytest.mark.parametrize("changes, match", [
    (dict(clearance=1e-200), r"^clearance = 1e-200 is out of range; allowed: \[1e-09, 1\]$"),
    # a slip of units: 700 km
    (dict(clearance="0.7 Mm"), r"^clearance = 700000.0 is out of range; allowed: \[1e-09, 1\] \(m: touchdown "
                               r"clearances are tenths of a millimetre; is the unit right\?\)"),
    (dict(clearance=1e-9, rotor_radius=0.04), r"^rotor_radius = 0.04 m is 4e\+07 clearances \(clearance = 1e-09 m\); "
                                              r"allowed: at most 1e\+06 clearances"),
    (dict(eccentricity=1e3), r"^eccentricity = 1000.0 m is 1.43e\+06 clearances"),
])
def test_lengths_beyond_what_the_model_resolves_are_refused(changes, match):
    # a drop with a clearance of 1e-200 m ran without end (its squared positions underflow)
    from rotorcontact import Machine, reference_machine

    with pytest.raises(ParameterError, match=match):
        Machine(**{**reference_machine().as_dict(), **changes})
    Machine(**{**reference_machine().as_dict(), "clearance": 1e-9, "rotor_radius": 1e-3, "eccentricity": 0.0})
    Machine(**{**reference_machine().as_dict(), "clearance": 1.0})  # the largest


def test_rows_checked_as_arrays_are_refused_exactly_where_the_constructor_refuses_and_with_its_message():
    from dataclasses import fields

    from rotorcontact.model.params import _PARAMETER_RULES, check_parameter_rows

    names = [f.name for f in fields(Parameters)]
    assert names == list(_PARAMETER_RULES)  # the rows' column order
    base = [getattr(REF, n) for n in names]
    for j, name in enumerate(names):
        rule = _PARAMETER_RULES[name]
        for bound in (rule.get("low"), rule.get("high")):
            if bound is None:
                continue
            # each bound, its neighbouring doubles and a value well beyond it on either side
            for value in (bound, np.nextafter(bound, -np.inf), np.nextafter(bound, np.inf), bound - 1.0, bound + 1.0):
                row = list(base)
                row[j] = float(value)
                rows = np.array([base, row, base])
                try:
                    Parameters(*row)
                except ParameterError as exc:
                    with pytest.raises(ParameterError) as got:
                        check_parameter_rows(rows)
                    assert str(got.value) == str(exc)
                else:
                    check_parameter_rows(rows)

"""The paper's reference parameter set (MODEL.md §1-§2), written out as numbers.

The values are those of the reference machine of MODEL.md §1 made dimensionless (γ = c / (m Ω),
ω = √(k / m) / Ω, ρ = e / c_r = 3/7, R / c_r = 400/7); tests/model/test_params.py checks that
`Parameters.reference()` gives exactly these. Tests import `REF` (or the dictionary `REF_VALUES`, for
parameter sets written as keyword arguments) where a module-level value is needed, e.g. in
``pytest.mark.parametrize``; others use the ``reference_params`` fixture of tests/conftest.py.
"""

from __future__ import annotations

from rotorcontact import Parameters

#: keyword arguments of `Parameters` for the reference set
REF_VALUES = dict(gamma=0.15200868621064062, omega=0.760043431053203, rho=3.0 / 7.0, mu=0.15, d=0.95, phi=0.21,
                  r_ratio=400.0 / 7.0)

#: the reference set
REF = Parameters(**REF_VALUES)


#: the reference machine of MODEL.md §1 in SI units: keyword arguments of `Machine`
REF_MACHINE = dict(
    mass=50.0,
    damping=1400.0,
    stiffness=9.8e5,
    eccentricity=0.3e-3,
    clearance=0.7e-3,
    rotor_radius=0.04,
    unbalance_phase=0.21,
    speed=184.2,
    friction=0.15,
    restitution=0.95,
)

#: the same machine as a machine file (TOML)
REF_MACHINE_TOML = """\
mass = 50.0
damping = 1400.0
stiffness = 9.8e5
eccentricity = 0.3e-3
clearance = 0.7e-3
rotor_radius = 0.04
unbalance_phase = 0.21
speed = 184.2
friction = 0.15
restitution = 0.95
"""


def replace_line(text: str, key: str, new_line: str) -> str:
    """``text`` (a machine file) with the line of ``key`` replaced by ``new_line``."""
    lines = [new_line if line.split("=")[0].strip() == key else line for line in text.splitlines()]
    return "\n".join(lines) + "\n"

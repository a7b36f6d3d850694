"""rotorcontact: exact simulation and analysis of rotor-stator contact.

The model is a Jeffcott rotor in magnetic bearings spinning inside a touchdown
bearing, with impacts (Newton restitution, Coulomb friction), after Mora, Budd,
Glendinning & Keogh, Proc. R. Soc. A (2015).
"""

from importlib.metadata import PackageNotFoundError, version

from .errors import ParameterError
from .flow import free_flight, to_inertial
from .params import Machine, Parameters, load_machine, reference_machine
from .simulate import simulate
from .trajectory import Trajectory

try:
    __version__ = version("rotorcontact")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "ParameterError",
    "Parameters",
    "Machine",
    "load_machine",
    "reference_machine",
    "free_flight",
    "to_inertial",
    "simulate",
    "Trajectory",
    "__version__",
]

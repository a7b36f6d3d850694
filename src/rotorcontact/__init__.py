"""rotorcontact: exact simulation and analysis of rotor-stator contact.

The model is a Jeffcott rotor in magnetic bearings spinning inside a touchdown
bearing, with impacts (Newton restitution, Coulomb friction), after Mora, Budd,
Glendinning & Keogh, Proc. R. Soc. A (2015).
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING

from .errors import ParameterError

try:
    __version__ = version("rotorcontact")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

# the public names and their modules, imported when first used so that the command line and
# ``import rotorcontact`` start without numba, scipy or matplotlib
_LAZY = {
    "free_flight": "model.flow",
    "to_inertial": "model.flow",
    "Machine": "model.params",
    "Parameters": "model.params",
    "load_machine": "model.params",
    "reference_machine": "model.params",
    "simulate": "simulation.simulator",
    "Trajectory": "simulation.trajectory",
}

if TYPE_CHECKING:  # pragma: no cover
    from .model.flow import free_flight, to_inertial
    from .model.params import Machine, Parameters, load_machine, reference_machine
    from .simulation.simulator import simulate
    from .simulation.trajectory import Trajectory


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'rotorcontact' has no attribute {name!r}")
    value = getattr(import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


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

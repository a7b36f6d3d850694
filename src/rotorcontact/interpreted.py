"""Run a kernel compiled when it is at hand, and interpreted while it is not.

numba compiles a kernel on its first call and caches it on disk (``cache=True``). Compiling the simulator
takes about 15 s, once per machine; interpreting the same source runs a short trajectory in well under a
second. `call_kernel` therefore runs a kernel

- compiled, when it is compiled in this process or cached on disk for these argument types;
- otherwise interpreted: its Python source, with every kernel it calls replaced by that kernel's own
  interpreted twin. All interpreted runs of a process share a budget of ``ROTORCONTACT_INTERPRET_S``
  seconds (default `DEFAULT_BUDGET_S`): a run that outlasts what is left of it is abandoned and its kernel
  compiled and run instead, and from then on every kernel runs compiled. So a command wastes at most the
  budget, however many kernels it uses. A run that raises anything is abandoned too, and its kernel runs
  compiled from then on.

Both tiers run the same floating-point operations in the same order. The kernels use ``math`` functions
(C's libm in both tiers), ``abs`` of a complex number for a modulus (libm's ``hypot`` in both; Python's
``math.hypot`` has its own algorithm), products or `int_power` rather than integer powers (numba
multiplies, Python calls ``pow``) and `complex_quotient` for every complex division (numba divides as
Python's complex type does; numpy's complex scalars, which the interpreted tier meets, multiply by a
reciprocal); functions that numba and Python compute differently (``math.gamma``) are evaluated in Python
and passed in. The tests hold the tiers bit-identical over chaotic, chattering and rolling trajectories,
drops and the impact map's orbits and continuation, on CPython 3.11. Known exceptions: CPython 3.14's mixed
real-complex arithmetic may differ in the sign of a zero, and numba with Intel's SVML installed may
vectorise a loop of sines.

Overflow and underflow pass silently in both tiers. A division by zero or an invalid operation on numpy
scalars, which compiled code would raise or turn into nan, abandons the interpreted run for the compiled one.
A kernel run through `call_kernel` must not modify its arguments (an abandoned run would leave them changed).

`int_power` and `complex_quotient` are compiled helpers of the kernels and take their arguments
unchecked, as the kernels do.
"""

from __future__ import annotations

import os
import threading
import time
import types
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from numba import njit
from numba.core.dispatcher import Dispatcher

from .errors import ParameterError

__all__ = ["DEFAULT_BUDGET_S", "BUDGET_VARIABLE", "INTERPRETED_ERRSTATE", "call_kernel", "compiled_only",
           "complex_quotient", "int_power", "interpreted", "interpret_budget"]

#: Seconds the interpreted runs of a process may take in all before every kernel runs compiled.
DEFAULT_BUDGET_S = 2.0
#: The environment variable that sets that budget (0: always compile; ``inf``: compile only a kernel whose
#: interpreted run Python refuses).
BUDGET_VARIABLE = "ROTORCONTACT_INTERPRET_S"
#: numpy's floating-point handling in the interpreted tier (see the module docstring).
INTERPRETED_ERRSTATE = dict(divide="raise", invalid="raise", over="ignore", under="ignore")

_state = threading.local()
# keyed by the kernel (or module namespace) itself, so that an id is never taken for another object's
_twins: dict[Any, Callable] = {}
_namespaces: dict[int, tuple[dict[str, Any], dict[str, Any]]] = {}
_lock = threading.RLock()
_on_disk: dict[tuple, bool] = {}
_compiled: set[Any] = set()  # kernels that run compiled from now on
_interpreted_s = [0.0]  # seconds of interpreted runs in this process


@njit(cache=True)
def complex_quotient(a: complex, b: complex) -> complex:
    """a / b as numba and Python's complex type compute it, in both tiers (a or b may be real)."""
    return complex(a) / complex(b)


@njit(cache=True)
def _positive_power(x: float, n: int) -> float:
    """x**n for an integer n >= 0 by binary powering (`int_power`)."""
    r = 1.0
    while n != 0:
        if n & 1:
            r *= x
        n >>= 1
        x *= x
    return r


@njit(cache=True)
def int_power(x: float, n: int) -> float:
    """x**n for an integer n by binary powering, as numba computes ``x ** n`` (Python calls pow); 1 / x**-n
    for n < 0."""
    if n >= 0:
        return _positive_power(x, n)
    if -n < 0:  # -2**63, whose 64-bit negation is itself: its first step (a zero bit) here, not by recursion
        return 1.0 / _positive_power(x * x, 1 << 62)
    return 1.0 / _positive_power(x, -n)


class _OutOfTime(BaseException):
    """The interpreted run passed its deadline (not an Exception: no ``except Exception`` in a kernel stops it)."""


def interpret_budget() -> float:
    """The interpretation budget in seconds, from ``ROTORCONTACT_INTERPRET_S`` (default `DEFAULT_BUDGET_S`).

    Raises
    ------
    ParameterError
        If the variable is set to something other than a number >= 0 (``inf`` included).
    """
    text = os.environ.get(BUDGET_VARIABLE)
    if text is None or text.strip() == "":
        return DEFAULT_BUDGET_S
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value >= 0.0:
        raise ParameterError(f"{BUDGET_VARIABLE} = {text!r} is invalid; allowed: a number of seconds >= 0, "
                             "or inf (never out of time)")
    return value


@contextmanager
def compiled_only() -> Iterator[None]:
    """Within this block `call_kernel` compiles (or loads) every kernel it runs, in this thread."""
    outer = getattr(_state, "compiled_only", False)
    _state.compiled_only = True
    try:
        yield
    finally:
        _state.compiled_only = outer


def _is_kernel(value: Any) -> bool:
    return isinstance(value, Dispatcher)


def _check_deadline() -> None:
    deadline = getattr(_state, "deadline", None)
    if deadline is not None and time.perf_counter() > deadline:
        raise _OutOfTime


def _namespace(module_globals: dict[str, Any]) -> dict[str, Any]:
    """The globals of a kernel module with every kernel in it replaced by its twin (built once)."""
    entry = _namespaces.get(id(module_globals))
    if entry is not None and entry[0] is module_globals:
        return entry[1]
    names: dict[str, Any] = {}
    _namespaces[id(module_globals)] = (module_globals, names)
    for name, value in list(module_globals.items()):
        names[name] = _twin(value) if _is_kernel(value) else value
    return names


def _twin(kernel) -> Callable:
    twin = _twins.get(kernel)
    if twin is not None:
        return twin
    source = kernel.py_func
    # the module's twin namespace, shared by its kernels; building it may build this kernel's twin
    names = _namespace(source.__globals__)
    twin = _twins.get(kernel)
    if twin is not None:
        return twin
    closure = source.__closure__
    if closure is not None:
        closure = tuple(
            types.CellType(_twin(c.cell_contents) if _is_kernel(c.cell_contents) else c.cell_contents)
            for c in closure
        )
    plain = types.FunctionType(source.__code__, names, source.__name__, source.__defaults__, closure)
    plain.__kwdefaults__ = source.__kwdefaults__

    def twin(*args, **kwargs):
        _check_deadline()
        return plain(*args, **kwargs)

    twin.__name__ = source.__name__
    twin.__qualname__ = source.__qualname__
    twin.__doc__ = source.__doc__
    twin.__wrapped__ = source
    _twins[kernel] = twin
    return twin


def interpreted(kernel) -> Callable:
    """The interpreted twin of ``kernel``: its Python source, calling the twins of the kernels it calls.

    Parameters
    ----------
    kernel : numba.core.dispatcher.Dispatcher
        A kernel (``@njit``).

    Returns
    -------
    callable
        A plain Python function with the kernel's signature and results. It compiles nothing.

    Raises
    ------
    ParameterError
        If ``kernel`` is not a numba kernel.
    """
    if not _is_kernel(kernel):
        raise ParameterError(f"kernel = {kernel!r} is not a numba kernel; allowed: a function decorated with @njit")
    with _lock:
        return _twin(kernel)


def _argument_types(kernel, args: tuple) -> tuple:
    return tuple(kernel.typeof_pyval(a) for a in args)


def _ready(kernel, args: tuple) -> bool:
    """Compiled in this process, or in numba's disk cache, for the types of ``args``."""
    try:
        sig = _argument_types(kernel, args)
    except Exception:
        return True  # numba cannot type these arguments: the compiled kernel raises as it always has
    if sig in kernel.overloads:
        return True
    key = (kernel, sig)
    found = _on_disk.get(key)
    if found is None:
        found = _on_disk[key] = _cached_on_disk(kernel, sig)
    return found


def _cached_on_disk(kernel, sig: tuple) -> bool:
    # numba's cache keeps an index per function, keyed by signature, CPU and bytecode; reading it loads
    # nothing. Where numba's internals differ from these, this answers False and the budget decides.
    try:
        cache = kernel._cache
        if not getattr(cache, "_enabled", False):
            return False
        index = cache._cache_file._load_index()
        return cache._index_key(sig, kernel.targetctx.codegen()) in index
    except Exception:
        return False


def call_kernel(kernel, *args, budget_s: float | None = None):
    """Call ``kernel(*args)``: compiled when at hand, else interpreted within a budget (module docstring).

    The budget is shared by all the interpreted runs of the process: once they have taken ``budget_s`` in
    all, every kernel is compiled, so that many short calls do not stay interpreted.

    Parameters
    ----------
    kernel : numba.core.dispatcher.Dispatcher
        The kernel.
    *args
        Its arguments, positional.
    budget_s : float, optional
        Seconds the interpreted runs of this process may take in all; default `interpret_budget`
        (``ROTORCONTACT_INTERPRET_S``). 0 compiles at once; ``math.inf`` interprets until a run is refused.

    Returns
    -------
    Any
        The kernel's result, the same in both tiers. The kernel must not modify its arguments.

    Raises
    ------
    ParameterError
        For a ``budget_s`` that is not a number of seconds >= 0, or an invalid ``ROTORCONTACT_INTERPRET_S``
        (read until the kernel runs compiled for good).
    """
    if not _is_kernel(kernel) or getattr(_state, "compiled_only", False):
        return kernel(*args)  # (not a kernel: numba's JIT is disabled, NUMBA_DISABLE_JIT)
    if budget_s is None and kernel in _compiled:
        return kernel(*args)  # compiled from now on: the budget no longer matters
    if budget_s is None:
        budget = interpret_budget()
    elif isinstance(budget_s, (int, float)) and not isinstance(budget_s, bool) and budget_s >= 0.0:
        budget = float(budget_s)
    else:
        raise ParameterError(f"budget_s = {budget_s!r} is invalid; allowed: a number of seconds >= 0, or inf")
    left = budget - _interpreted_s[0]
    if left <= 0.0 or kernel in _compiled:
        return kernel(*args)
    if _ready(kernel, args):
        with _lock:
            _compiled.add(kernel)  # at hand: compiled from now on, without asking again
        return kernel(*args)
    with _lock:
        twin = _twin(kernel)
    start = time.perf_counter()
    outer = getattr(_state, "deadline", None)
    _state.deadline = start + left if outer is None else min(outer, start + left)
    try:
        with np.errstate(**INTERPRETED_ERRSTATE):
            return twin(*args)
    except (_OutOfTime, Exception):
        with _lock:
            _compiled.add(kernel)  # abandoned (out of time, or refused by Python): compiled from now on
    finally:
        _state.deadline = outer
        with _lock:
            _interpreted_s[0] += time.perf_counter() - start
    return kernel(*args)

"""The interpreted tier against the compiled one, and when each runs.

The tiers must agree bit for bit: chaotic runs amplify a difference in the last bit of any operation into
a different sequence of impacts, so identical records over a chaotic run check every operation the kernels
use. A static check keeps out of the kernels the few constructs whose results differ between numba and
the Python interpreter.
"""

from __future__ import annotations

import ast
import inspect
import json
import math
import os
import subprocess
import sys
import textwrap
import types

import numpy as np
import pytest
from numba import njit
from numba.core.dispatcher import Dispatcher

import rotorcontact.interpreted as tiers
from rotorcontact import ParameterError, Parameters, free_flight, simulate
from rotorcontact.maps import impact_map
from rotorcontact.interpreted import (
    BUDGET_VARIABLE,
    INTERPRETED_ERRSTATE,
    call_kernel,
    interpret_budget,
    interpreted,
)
from rotorcontact.model.angles import _wrap_many, angle_difference
from rotorcontact.model.contact_law import forces_along
from rotorcontact.model.flow import _flow_many, equilibrium_point, has_regular_equilibrium
from rotorcontact.model.machine_model import constant_response, harmonic_response, unbalance_amplitudes
from rotorcontact.model.params import Machine, reference_machine
from rotorcontact.model.units import RPM
from rotorcontact.simulation import drop_run, simulator
from rotorcontact.simulation.drop import drop_kernel
from rotorcontact.simulation.trajectory import _evaluate_flights
from reference_parameters import REF_VALUES

# the kernels the package calls through call_kernel
ENTRY_KERNELS = [simulator.simulate_kernel, equilibrium_point, has_regular_equilibrium, _wrap_many,
                 forces_along, _flow_many, _evaluate_flights,
                 drop_kernel, unbalance_amplitudes, harmonic_response, constant_response,
                 *[v for v in vars(impact_map).values() if isinstance(v, Dispatcher)]]

RUNS = [
    # label, parameters, u0, du0, t_end, on_chatter
    ("chaotic-from-rest", dict(REF_VALUES, gamma=0.08), 0j, 0j, 1500.0, "contact"),
    ("chaotic-offset", dict(REF_VALUES, gamma=0.08), 0.5 + 0.1j, 0j, 1500.0, "contact"),
    ("periodic-impacting", dict(REF_VALUES, gamma=0.1), 0j, 0j, 800.0, "contact"),
    ("chatter-to-forward-rub", REF_VALUES, 0j, 0j, 500.0, "contact"),
    ("chatter-stop", REF_VALUES, 0j, 0j, 500.0, "stop"),
    ("backward-whirl", dict(REF_VALUES, gamma=0.02, omega=0.5), 0j, 0j, 400.0, "contact"),
    ("elastic", dict(REF_VALUES, gamma=0.08, d=1.0), 0.3j, 0j, 600.0, "contact"),
    ("overdamped", dict(gamma=1.6, omega=0.7, rho=2.0, mu=0.3, d=0.8, phi=-1.0, r_ratio=20.0), 0.2j,
     1.5 - 0.5j, 200.0, "contact"),
    ("stiff", dict(gamma=0.3, omega=1.2, rho=0.8, mu=0.3, d=0.7, phi=-2.5, r_ratio=5.0), 0.2 + 0.1j,
     -0.5 + 1j, 300.0, "contact"),
]


def _kernel_arguments(monkeypatch, module, kernel, run) -> tuple:
    """The arguments ``run()`` passes to ``kernel`` through ``module.call_kernel`` (run compiled here)."""
    seen = []

    def spy(called, *args, **kwargs):
        if called is kernel:
            seen.append(args)
        return called(*args)

    with monkeypatch.context() as m:
        m.setattr(module, "call_kernel", spy)
        run()
    return seen[0]


def _assert_identical(a, b) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b):
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape
            assert x.tobytes() == y.tobytes()
        else:  # a scalar: the same bits (nan included) in the compiled result's type
            kind = np.asarray(x).dtype
            assert np.asarray(x).tobytes() == np.asarray(y, dtype=kind).tobytes()


@pytest.mark.parametrize("label,kw,u0,du0,t_end,on_chatter", RUNS, ids=[r[0] for r in RUNS])
def test_simulator_tiers_are_bit_identical(monkeypatch, label, kw, u0, du0, t_end, on_chatter):
    args = _kernel_arguments(monkeypatch, simulator, simulator.simulate_kernel,
                             lambda: simulate(Parameters(**kw), u0, du0, t_end, on_chatter=on_chatter))
    compiled = simulator.simulate_kernel(*args)
    with np.errstate(**INTERPRETED_ERRSTATE):
        plain = interpreted(simulator.simulate_kernel)(*args)
    _assert_identical(compiled, plain)
    impacts = compiled[0]
    if label.startswith("chaotic"):
        assert len(impacts) > 300  # long enough for chaos to magnify any difference
    if label.startswith("chatter") or label == "backward-whirl":
        assert len(compiled[2]) >= 1  # a contact phase was run by both tiers


RACE = dict(race_inertia=2e-4, race_drag_torque=0.05, race_drag_coefficient=1e-4)
COMPLIANT = dict(contact="compliant", contact_stiffness=1e10)
DROPS = [
    # label, machine keys over the reference machine with gravity, speed (rpm), t_end (s)
    ("rigid", {}, 12000, 0.3),
    ("rigid-race", RACE, 12000, 0.2),
    ("rigid-low-restitution", dict(restitution=0.3), 3000, 0.3),
    ("compliant", COMPLIANT, 12000, 0.05),
    ("compliant-race", {**COMPLIANT, **RACE}, 3000, 0.05),
    ("compliant-stator-on-springs", {**COMPLIANT, "stator_mass": 20.0, "stator_stiffness": 4e6,
                                     "stator_damping": 400.0}, 12000, 0.05),
]


@pytest.mark.parametrize("label,keys,rpm,t_end", DROPS, ids=[d[0] for d in DROPS])
def test_drop_tiers_are_bit_identical(monkeypatch, label, keys, rpm, t_end):
    machine = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04, **keys})
    args = _kernel_arguments(monkeypatch, drop_run, drop_kernel,
                             lambda: drop_run.drop(machine, speed=rpm * RPM, t_end=t_end))
    compiled = drop_kernel(*args)
    with np.errstate(**INTERPRETED_ERRSTATE):
        plain = interpreted(drop_kernel)(*args)
    _assert_identical(compiled, plain)
    assert len(compiled[0]) >= 1  # it touched down


def test_impact_map_tiers_are_bit_identical(monkeypatch):
    """Every kernel call of the orbit search, the map and a continuation, run again in the other tier."""
    from rotorcontact.continuation.branches import orbit_branches

    calls = []

    def spy(kernel, *args):
        calls.append((kernel, tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)))
        return kernel(*args)

    monkeypatch.setattr(impact_map, "call_kernel", spy)
    for g in (0.1, 0.14, -0.2):
        orbits = impact_map.one_impact_orbits(Parameters(**dict(REF_VALUES, gamma=g)), 12.0)
        for o in orbits[:3]:
            impact_map.impact_map(o.params, (o.theta, o.rdot, o.thetadot))
            impact_map.impact_map_jacobian(o.params, (o.theta, o.rdot, o.thetadot), o.T)
    orbit_branches(Parameters(**dict(REF_VALUES, gamma=0.1)), "gamma", 0.05, 0.08, t_max=4.0, n_seeds=3)
    kernels = {kernel for kernel, _ in calls}
    assert len(kernels) >= 8 and len(calls) > 100
    rng = np.random.default_rng(11)
    for i in sorted(set(rng.choice(len(calls), size=min(len(calls), 400), replace=False)) | set(range(40))):
        kernel, args = calls[i]
        compiled = kernel(*args)
        with np.errstate(**INTERPRETED_ERRSTATE):
            plain = interpreted(kernel)(*args)
        if not isinstance(compiled, tuple):
            compiled, plain = (compiled,), (plain,)
        _assert_identical(compiled, plain)


def test_helper_kernels_tiers_are_bit_identical():
    rng = np.random.default_rng(5)
    theta, thetadot = rng.uniform(-7, 7, 500), rng.uniform(-3, 3, 500)
    cases = [
        (equilibrium_point, (0.1, 0.76, 0.43, 0.21)),
        (has_regular_equilibrium, (0.0, 1.0)),
        (_wrap_many, (rng.uniform(-40, 40, 1000),)),
        (forces_along, (theta, thetadot, 0.15, 0.76, 0.43, 0.21)),
        (_flow_many, (0.2 + 0.1j, -0.3j, rng.uniform(-5, 30, 400), 0.15, 0.76, 0.3 - 0.2j)),
    ]
    for kernel, args in cases:
        a, b = kernel(*args), interpreted(kernel)(*args)
        if isinstance(a, tuple):
            _assert_identical(a, b)
        else:
            assert np.asarray(a).tobytes() == np.asarray(b).tobytes(), kernel.py_func.__name__


def test_trajectory_evaluation_agrees_across_tiers():
    """state and contact_forces go through call_kernel; their kernels' twins give the same numbers."""
    traj = simulate(Parameters(**REF_VALUES), 0j, 0j, 300.0)
    t = np.linspace(0.0, traj.t_stop, 3001)
    starts, u_start, du_start = traj._flight_table
    p = traj.params
    args = (t, starts, u_start, du_start, p.k, p.gamma, p.omega)
    _assert_identical(_evaluate_flights(*args), interpreted(_evaluate_flights)(*args))
    u, _ = free_flight(p, 0.1, 0.2j, t)
    assert np.all(np.isfinite(u))
    np.testing.assert_array_equal(angle_difference(t, 0.5), _wrap_many(t - 0.5))


# ----------------------------------------------------------------------------------------------------------
# which tier runs


@njit
def _step(i):
    return math.sin(i * 0.001) * 1e-3


@njit
def _long_sum(n):
    s = 0.0
    for i in range(n):
        s += _step(i)
    return s


@njit
def _log(x):
    return math.log(x)


def _fresh(kernel) -> Dispatcher:
    """A new, uncompiled dispatcher for the same source (the tests above may have compiled the originals)."""
    return njit(kernel.py_func)


def test_short_call_stays_interpreted_and_long_one_is_compiled():
    small = _fresh(_long_sum)
    assert call_kernel(small, 100, budget_s=10.0) == interpreted(small)(100)
    assert small.signatures == []  # interpreted: nothing compiled
    big = _fresh(_long_sum)
    expected = interpreted(big)(200_000)
    assert call_kernel(big, 200_000, budget_s=1e-3) == expected  # over budget: compiled, same result
    assert len(big.signatures) == 1


def test_budget_is_spent_over_calls():
    kernel = _fresh(_long_sum)
    for _ in range(200):
        call_kernel(kernel, 20_000, budget_s=0.05)
        if kernel.signatures:
            break
    assert len(kernel.signatures) == 1  # many short calls end compiled


def test_budget_is_shared_by_all_kernels():
    first, second = _fresh(_long_sum), _fresh(_long_sum)
    budget = tiers._interpreted_s[0] + 0.01  # what this process has interpreted so far, and 10 ms more
    call_kernel(first, 200_000, budget_s=budget)  # outlasts the 10 ms
    assert len(first.signatures) == 1
    call_kernel(second, 10, budget_s=budget)  # short, but the budget is spent: compiled
    assert len(second.signatures) == 1


def test_zero_budget_compiles_at_once(monkeypatch):
    kernel = _fresh(_long_sum)
    monkeypatch.setenv(BUDGET_VARIABLE, "0")
    call_kernel(kernel, 10)
    assert len(kernel.signatures) == 1


def test_infinite_budget_never_runs_out(monkeypatch):
    """inf: a run however long, after any amount already interpreted, stays interpreted."""
    monkeypatch.setenv(BUDGET_VARIABLE, "inf")
    kernel = _fresh(_long_sum)
    tiers._interpreted_s[0] += 1e6  # as if this process had interpreted for days
    try:
        assert call_kernel(kernel, 200_000) == interpreted(kernel)(200_000)
    finally:
        tiers._interpreted_s[0] -= 1e6
    assert kernel.signatures == []
    errors = _fresh(_log)  # a run Python refuses is still compiled and run instead
    assert call_kernel(errors, 0.0, budget_s=math.inf) == -math.inf
    assert len(errors.signatures) == 1


def test_python_error_in_the_interpreted_tier_falls_back_to_the_compiled_kernel():
    kernel = _fresh(_log)  # Python's math.log(0) raises; compiled, it is -inf
    assert call_kernel(kernel, 0.0, budget_s=10.0) == -math.inf
    assert len(kernel.signatures) == 1
    assert call_kernel(kernel, 2.0, budget_s=10.0) == math.log(2.0)


def test_budget_variable(monkeypatch):
    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    assert interpret_budget() == tiers.DEFAULT_BUDGET_S
    monkeypatch.setenv(BUDGET_VARIABLE, "0.5")
    assert interpret_budget() == 0.5
    monkeypatch.setenv(BUDGET_VARIABLE, " inf ")
    assert interpret_budget() == math.inf
    for bad in ("abc", "-1", "-inf", "nan"):
        monkeypatch.setenv(BUDGET_VARIABLE, bad)
        with pytest.raises(ParameterError, match=BUDGET_VARIABLE):
            interpret_budget()


def test_call_kernel_refuses_a_bad_budget():
    for bad in (-1.0, -math.inf, math.nan, "1", True):
        with pytest.raises(ParameterError, match="budget_s"):
            call_kernel(_fresh(_log), 2.0, budget_s=bad)


def test_with_the_jit_disabled_kernels_are_plain_functions(tmp_path):
    script = ("from rotorcontact import Parameters, simulate; "
              "t = simulate(Parameters.reference(), 0j, 0j, 50.0); print(len(t.impacts))")
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1", "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert int(out.stdout) > 0


def test_interpreted_refuses_a_plain_function():
    with pytest.raises(ParameterError, match="not a numba kernel"):
        interpreted(math.sin)


def test_disk_cache_decides_between_tiers(tmp_path):
    """A cold cache interprets a short call; once the kernel is in the cache, the next process loads it."""
    script = textwrap.dedent("""
        import sys
        from rotorcontact.interpreted import call_kernel
        from rotorcontact.model.angles import wrap_angle
        if sys.argv[1] == "compile":
            wrap_angle(0.3)
        else:
            call_kernel(wrap_angle, 0.3, budget_s=10.0)
        print(len(wrap_angle.signatures))
    """)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}

    def run(mode: str) -> str:
        out = subprocess.run([sys.executable, "-c", script, mode], env=env, capture_output=True, text=True,
                             check=True, timeout=300)
        return out.stdout.strip()

    assert run("call") == "0"  # cold cache: interpreted
    assert run("compile") == "1"
    assert run("call") == "1"  # in the cache: loaded and run compiled


def test_cold_simulate_command_compiles_nothing(tmp_path, monkeypatch):
    """The first `rotorcontact simulate` on a machine runs interpreted, with the compiled run's numbers."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env.pop(BUDGET_VARIABLE, None)
    cmd = [sys.executable, "-m", "rotorcontact.cli.main", "simulate", "--t-end", "300", "--json", "--all-impacts"]
    cold = json.loads(subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, timeout=300).stdout)
    assert not any((tmp_path / "cache").rglob("*.nbi"))  # nothing was compiled
    monkeypatch.setenv(BUDGET_VARIABLE, "0")
    compiled = simulate(Parameters.reference(), 0j, 0j, 300.0).to_dict(None)
    assert len(cold["impacts"]) > 100
    assert cold["impacts"] == json.loads(json.dumps(compiled["impacts"]))
    assert cold["contact_intervals"] == json.loads(json.dumps(compiled["contact_intervals"]))


def test_cold_drop_command_compiles_nothing(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env.pop(BUDGET_VARIABLE, None)
    cmd = [sys.executable, "-m", "rotorcontact.cli.main", "drop", "reference", "--speed", "12000rpm", "--t-end",
           "0.2s", "--json"]
    out = json.loads(subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, timeout=300).stdout)
    assert not any((tmp_path / "cache").rglob("*.nbi"))
    assert len(out["impacts"]) > 0 and out["summary"]["regime"] == "backward-whirl"


# ----------------------------------------------------------------------------------------------------------
# constructs that numba and Python evaluate differently


def _reachable_kernels() -> list[Dispatcher]:
    seen: dict[int, Dispatcher] = {}
    todo = list(ENTRY_KERNELS)
    while todo:
        kernel = todo.pop()
        if id(kernel) in seen:
            continue
        seen[id(kernel)] = kernel
        codes = [kernel.py_func.__code__]
        names: set[str] = set()
        while codes:
            code = codes.pop()
            names.update(code.co_names)
            codes.extend(c for c in code.co_consts if isinstance(c, types.CodeType))
        for name in names:
            value = kernel.py_func.__globals__.get(name)
            if isinstance(value, Dispatcher):
                todo.append(value)
    return list(seen.values())


# numpy's own implementations (SIMD on some CPUs, pairwise summation) differ from numba's (libm, loops)
NUMPY_DIFFERENT = {"sin", "cos", "tan", "exp", "log", "log1p", "expm1", "sinh", "cosh", "tanh", "arctan2",
                   "arcsin", "arccos", "arctan", "hypot", "power", "sum", "mean", "dot", "prod", "linalg"}
# Python's own algorithms, where numba calls libm
MATH_DIFFERENT = {"hypot", "gamma", "lgamma", "erf", "erfc", "fsum", "prod", "dist"}


def _hazards(kernel: Dispatcher) -> list[str]:
    tree = ast.parse(textwrap.dedent(inspect.getsource(kernel.py_func)))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            exponent = node.right
            if isinstance(exponent, ast.UnaryOp):
                exponent = exponent.operand
            value = exponent.value if isinstance(exponent, ast.Constant) else None
            if isinstance(value, (int, float)) and (float(value).is_integer() or abs(value) == 0.5):
                # numba multiplies for an integer, LLVM turns pow(x, 2.0), pow(x, -1.0), pow(x, 0.5) into
                # products, quotients and sqrt; Python calls pow
                found.append(f"line {node.lineno}: power {value!r} (numba multiplies, Python calls pow)")
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            if node.value.id == "math" and node.attr in MATH_DIFFERENT:
                found.append(f"line {node.lineno}: math.{node.attr} (Python's own algorithm, not libm's)")
            if node.value.id in ("np", "numpy") and node.attr in NUMPY_DIFFERENT:
                found.append(f"line {node.lineno}: np.{node.attr} (numpy's implementation, not numba's)")
    return found


def test_tiered_kernels_avoid_constructs_that_differ_between_tiers():
    kernels = _reachable_kernels()
    assert len(kernels) > 30  # the simulator's whole call tree
    problems = {k.py_func.__qualname__: h for k in kernels if (h := _hazards(k))}
    assert problems == {}


def test_hazard_check_finds_each_construct():
    @njit
    def bad(x):
        return x**2 + math.hypot(x, 1.0) + np.cos(x) + x ** -3 + x**0.5 + math.gamma(x) + x**2.0

    @njit
    def good(x):
        return x * x + abs(complex(x, 1.0)) + math.cos(x) + x**-0.2 + x**1.5

    assert len(_hazards(bad)) == 7
    assert _hazards(good) == []


@pytest.mark.parametrize("x, n", [(2.0, -1), (1.5, -7), (-3.0, -2), (0.5, 0), (2.0, 10)])
def test_int_power_of_any_integer_is_the_power(x, n):
    from rotorcontact.interpreted import int_power

    assert int_power(x, n) == pytest.approx(x ** n, rel=4e-16)


def test_int_power_ends_at_the_most_negative_64_bit_exponent():
    """-2**63 is its own negation in 64 bits: compiled, the powering still ends, with x**-2**63."""
    from rotorcontact.interpreted import int_power, interpreted

    n = -(2**63)
    assert int_power(2.0, n) == 0.0 and int_power(-1.0, n) == 1.0 and int_power(1.0, n) == 1.0
    twin = interpreted(int_power)  # the Python tier: its callees are their Python twins too
    assert twin(2.0, n) == 0.0 and twin(-1.0, n) == 1.0
    # one exponent short, through the ordinary path: the same values
    assert int_power(2.0, n + 1) == 0.0 and int_power(-1.0, n + 2) == 1.0

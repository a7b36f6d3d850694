"""Design maps for a real machine: where levitation is safe, bistable or contact-certain.

A point of a map is a `Machine` (its speed, bearing stiffness and damping set
gamma = c/(m Omega) and omega^2 = k/(m Omega^2)). At each point the motions
that can persist are collected from the analysis (no simulation):

- contact-free whirl: the regular equilibrium x_R, admissible when |k| < 1
  (MODEL.md §4);
- impacting motions: one-impact periodic orbits B_n,a..d that are admissible,
  physically plausible and stable (MODEL.md §5, `rotorcontact.maps.impact_map`);
- forward rubs: pseudo-equilibria P1, P2 that are admissible and stable (MODEL.md §4).

The point's *outcome* (`OUTCOMES`; reported under the key ``"regime"``) is
``"safe"`` (whirl admissible, no stable contact motion), ``"bistable"`` (whirl
admissible and a stable contact motion coexists, so a touchdown can persist
after a disturbance) or ``"contact-certain"`` (no admissible contact-free
whirl). It is not a contact regime of a motion
(`rotorcontact.simulation.motion.REGIMES`) but a verdict on a machine setting.
Orbits with several impacts per period, rolling and chaotic motions are not
found by this analysis; `recovery_probability` samples disturbances with the
simulator, which sees all of them (`recovery_probabilities` does so for a whole
map as one chunked study).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from collections.abc import Mapping
from typing import Any, Sequence

import numpy as np

from ..analysis.equilibria import equilibria
from ..errors import ParameterError
from ..maps.impact_map import one_impact_orbits, period_limit
from ..model.params import MAX_SPEED, MAX_VELOCITY, Machine, check_finite, check_range
from ..model.validation import check_int, check_length, check_machine, is_pair, quoted, real_array
from ..model.si import MICROMETRE, orbit_si, pseudo_si, regular_si
from ..model.units import RPM
from .driver import run_study

__all__ = [
    "OUTCOMES",
    "MAP_AXES",
    "Motion",
    "MapPoint",
    "DesignMap",
    "classify_machine",
    "speed_map",
    "plane_map",
    "design_map",
    "recovery_probability",
    "recovery_probabilities",
    "rpm_to_rad_s",
    "rad_s_to_rpm",
]

#: The outcomes of a machine setting (see the module docstring), stored under the name ``regime``.
OUTCOMES = ("safe", "bistable", "contact-certain")
#: Former name of `OUTCOMES`.
REGIMES = OUTCOMES
#: The maps `design_map` draws: the axes of the map for the settings given ranges.
MAP_AXES = {
    frozenset({"speed"}): ("speed_rpm",),
    frozenset({"speed", "stiffness"}): ("speed_rpm", "stiffness"),
    frozenset({"speed", "damping"}): ("speed_rpm", "damping"),
    frozenset({"stiffness", "damping"}): ("stiffness", "damping"),
}
#: Largest number of points along each side of a plane map.
MAX_PLANE_SIDE = 60


def _speeds(name: str, value: Any) -> np.ndarray:
    arr = real_array(value)
    if arr is None or not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: finite real numbers")
    return arr


def rpm_to_rad_s(rpm):
    """Revolutions per minute to rad/s (a float for a number, else an array); a `ParameterError` for what
    is not finite real numbers."""
    arr = _speeds("rpm", rpm)
    return arr * RPM if np.ndim(rpm) else float(arr) * RPM


def rad_s_to_rpm(rad_s):
    """rad/s to revolutions per minute (a float for a number, else an array); a `ParameterError` for what
    is not finite real numbers."""
    arr = _speeds("rad_s", rad_s)
    return arr / RPM if np.ndim(rad_s) else float(arr) / RPM


@dataclass(frozen=True)
class Motion:
    """A motion that can persist at a map point, with its physical outputs in SI units.

    Attributes
    ----------
    name : str
        ``"x_R"``, an orbit label such as ``"B1,d"``, or ``"P1"`` / ``"P2"``.
    kind : str
        ``"contact-free"``, ``"impacting"`` or ``"forward-rub"`` (the regime names of
        `rotorcontact.simulation.motion.REGIMES`; ``"rub"`` is the former name of ``"forward-rub"``).
    stable : bool
        Linear stability.
    amplitude_um : float
        Whirl amplitude: the radius of the rotor centre's orbit in micrometres
        (|k| c_r for x_R; c_r for motions that touch the stator).
    impulse_Ns, impact_rate_hz : float or None
        Normal impulse per impact (N s) and impacts per second.
    friction_power_W : float or None
        Mean power dissipated by friction (W).
    contact_force_N : float or None
        Normal contact force of a rub (N).
    period_s : float or None
        Period of an impacting orbit (s).
    """

    name: str
    kind: str
    stable: bool
    amplitude_um: float
    impulse_Ns: float | None = None
    impact_rate_hz: float | None = None
    friction_power_W: float | None = None
    contact_force_N: float | None = None
    period_s: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class MapPoint:
    """One classified machine setting.

    Attributes
    ----------
    speed_rpm, stiffness, damping : float
        The setting (rpm, N/m, N s/m).
    gamma, omega : float
        Its dimensionless parameters.
    regime : str
        The outcome, one of `OUTCOMES`.
    whirl_admissible : bool
        Contact-free whirl x_R lies inside the clearance.
    coexisting : tuple of str
        Names of the stable contact motions that coexist (for example ("B1,d", "P2")).
    motions : tuple of Motion
        x_R (when admissible) and every stable contact motion, with SI outputs.
    recovery_probability : float or None
        For a bistable point, the fraction of sampled disturbances after which
        the rotor returns to contact-free whirl (None when not computed).
    """

    speed_rpm: float
    stiffness: float
    damping: float
    gamma: float
    omega: float
    regime: str
    whirl_admissible: bool
    coexisting: tuple[str, ...]
    motions: tuple[Motion, ...] = field(repr=False)
    recovery_probability: float | None = None

    def to_dict(self) -> dict[str, Any]:
        out = asdict(self)
        out["coexisting"] = list(self.coexisting)
        out["motions"] = [m.to_dict() for m in self.motions]
        return out


def _impact_motion(machine: Machine, orbit) -> Motion:
    """SI outputs of a one-impact orbit: impulse, rate, friction power (`rotorcontact.model.si.orbit_si`)."""
    si = orbit_si(machine, orbit)
    return Motion(
        name=orbit.label,
        kind="impacting",
        stable=bool(orbit.stable),
        amplitude_um=si["amplitude_um"],
        impulse_Ns=si["normal_impulse_Ns"],
        impact_rate_hz=si["impact_rate_hz"],
        friction_power_W=si["friction_power_W"],
        period_s=si["T_s"],
    )


def _rub_motion(machine: Machine, pseudo, stable: bool) -> Motion:
    """SI outputs of a forward rub: contact force and friction power (`rotorcontact.model.si.pseudo_si`)."""
    si = pseudo_si(machine, pseudo)
    return Motion(
        name=pseudo.name,
        kind="forward-rub",
        stable=stable,
        amplitude_um=machine.clearance * MICROMETRE,
        contact_force_N=si["normal_force_N"],
        friction_power_W=si["friction_power_W"],
    )


def classify_machine(machine: Machine, *, t_max: float = 12.0) -> MapPoint:
    """Classify one machine setting (see the module docstring).

    Parameters
    ----------
    machine : Machine
        The setting.
    t_max : float
        Longest period (dimensionless) of the impacting orbits searched.
    """
    check_machine(machine, optional=False)
    p = machine.parameters()
    eq = equilibria(p)
    motions: list[Motion] = []
    whirl = bool(eq.regular.exists and eq.regular.admissible and eq.regular.stable)
    if whirl:
        motions.append(Motion("x_R", "contact-free", True, regular_si(machine, eq.regular)["amplitude_um"]))
    coexisting = []
    for orbit in one_impact_orbits(p, t_max):
        if orbit.admissible and orbit.plausible and orbit.stable:
            motions.append(_impact_motion(machine, orbit))
            coexisting.append(orbit.label)
    for pseudo in eq.pseudo:
        if pseudo.exists and pseudo.admissible and pseudo.stable:
            motions.append(_rub_motion(machine, pseudo, True))
            coexisting.append(pseudo.name)
    if not whirl:
        regime = "contact-certain"
    elif coexisting:
        regime = "bistable"
    else:
        regime = "safe"
    return MapPoint(
        speed_rpm=rad_s_to_rpm(machine.speed),
        stiffness=machine.stiffness,
        damping=machine.damping,
        gamma=p.gamma,
        omega=p.omega,
        regime=regime,
        whirl_admissible=whirl,
        coexisting=tuple(coexisting),
        motions=tuple(motions),
    )


def _check_whirl(machine: Machine):
    p = machine.parameters()
    if abs(p.k) >= 1.0:
        raise ParameterError(
            f"recovery needs admissible contact-free whirl; at speed = {machine.speed:g} rad/s, "
            f"|k| = {abs(p.k):.4g} >= 1"
        )
    return p


def _check_shock(machines: Sequence[Machine], shock: Any) -> float:
    """``shock`` (m/s) checked for every machine: the kick shock / (c Omega) it gives is a dimensionless
    velocity, within the simulator's bound `MAX_VELOCITY`."""
    shock = check_range("shock", shock, low=0.0)
    if not isinstance(machines, (list, tuple)) or not machines:
        raise ParameterError(f"machines = {quoted(machines)} is invalid; allowed: a non-empty list of Machine")
    check_length("machines", machines, MAX_POINTS)
    for machine in machines:
        check_machine(machine, optional=False)
        kick = shock / (machine.clearance * machine.speed)
        if kick > MAX_VELOCITY:
            raise ParameterError(
                f"shock = {shock!r} m/s is too large at {machine.speed / RPM:.6g} rpm: the kick is "
                f"{kick:.3g} clearances per unit time; allowed: shock <= "
                f"{MAX_VELOCITY * machine.clearance * machine.speed:.6g} m/s (far beyond any touchdown shock)"
            )
    return shock


def recovery_probabilities(
    machines: Sequence[Machine],
    shock: float,
    *,
    directions: int = 24,
    chunk_size: int = 8,
    n_jobs: int | None = None,
    scheduler: Any = None,
    processes: bool = True,
    progress: bool = False,
) -> np.ndarray:
    """`recovery_probability` of each machine, as one chunked study (`rotorcontact.studies.driver.run_study`).

    Each machine contributes ``directions`` simulations of the batch kernel, in
    chunks of ``chunk_size`` machines, run in this process, through joblib
    (``n_jobs``) or on Dask (``scheduler``); the results do not depend on the
    executor or the chunk size.

    Returns
    -------
    numpy.ndarray
        The fraction of shocks that recover, per machine.

    Raises
    ------
    ParameterError
        If contact-free whirl is not admissible for a machine, or on invalid arguments.
    """
    from .basins import basin_settings, shock_grid
    from .batch import NO_CONTACT, BatchResult, parameter_array
    from .execution import ChunkTask, check_chunk_size, study_digest

    shock = _check_shock(machines, shock)
    directions = check_int("directions", directions, 1)
    chunk_size = check_chunk_size(chunk_size)
    settings = basin_settings()
    step = 2.0 * math.pi / directions
    lanes = []
    for machine in machines:
        p = _check_whirl(machine)
        kick = shock / (machine.clearance * machine.speed)
        u0, du0, _ = shock_grid((kick, kick, 1), (-math.pi, math.pi - step, directions)).initial_states(p)
        lanes.append((parameter_array(p), u0.ravel(), du0.ravel()))
    n = len(lanes)
    manifest = {"study": "recovery", "machines": [m.as_dict() for m in machines], "shock": shock,
                "directions": directions, "settings": settings.as_dict()}

    def keys(size: int) -> list[str]:
        return [f"recovery-{c:06d}" for c in range(math.ceil(n / size))]

    def waves(size: int, sink):
        tasks = []
        for c, key in enumerate(keys(size)):
            part = lanes[c * size : (c + 1) * size]
            tasks.append(ChunkTask(
                key=key,
                params=np.concatenate([np.broadcast_to(row, (directions, 1, row.size)) for row, _, _ in part]),
                u0=np.concatenate([u for _, u, _ in part]).reshape(-1, 1),
                du0=np.concatenate([du for _, _, du in part]).reshape(-1, 1),
                carry=False,
                settings=settings,
            ))
        yield tasks

    def assemble(size: int, load):
        import xarray as xr

        chunks = [BatchResult.from_arrays(res["sections"], res["summary"], settings) for res in map(load, keys(size))]
        recovered = np.concatenate([chunk.regime[:, 0] == NO_CONTACT for chunk in chunks]).reshape(n, directions)
        fraction = recovered.sum(axis=1) / directions
        impacts = sum(chunk.impacts_simulated for chunk in chunks)
        return xr.Dataset({"recovery_probability": (("machine",), fraction)}), impacts

    if n == 0:
        return np.zeros(0)
    run = run_study(manifest, study_digest(manifest), keys=keys, waves=waves, assemble=assemble,
                    n_items=n * directions, desc="recovery", chunk_size=chunk_size, n_jobs=n_jobs,
                    scheduler=scheduler, processes=processes, progress=progress)
    return run.dataset["recovery_probability"].values


def recovery_probability(
    machine: Machine,
    shock: float,
    *,
    directions: int = 24,
) -> float:
    """Fraction of velocity shocks of size ``shock`` (m/s) from contact-free whirl that recover.

    This is a one-amplitude slice of the basin computation
    (`rotorcontact.studies.basins.basins` on a `shock_grid`, with its batch
    settings): the rotor starts at the regular equilibrium with its velocity
    kicked by ``shock`` in each of ``directions`` equally spaced directions,
    runs through the batch kernel (impacts, chatter and contact included), and
    has recovered when its attractor is ``"no-contact"``.
    `recovery_probabilities` computes it for many machines at once.

    Raises
    ------
    ParameterError
        If contact-free whirl is not admissible, or on invalid arguments.
    """
    check_machine(machine, optional=False)
    return float(recovery_probabilities([machine], shock, directions=directions, n_jobs=1)[0])


@dataclass(frozen=True)
class DesignMap:
    """A classified map over speed, or over a plane of two settings.

    Attributes
    ----------
    machine : Machine
        The base machine.
    axes : tuple of str
        Names of the swept settings: ("speed_rpm",), ("speed_rpm", "stiffness")
        or ("stiffness", "damping").
    values : tuple of numpy.ndarray
        Their grids (rpm, N/m, N s/m).
    points : tuple of MapPoint
        Flattened in C order over the grids.
    shock : float or None
        The disturbance (m/s) of the recovery probabilities, when computed.
    """

    machine: Machine
    axes: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    points: tuple[MapPoint, ...] = field(repr=False)
    shock: float | None = None

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.values)

    def regime_codes(self) -> np.ndarray:
        """Outcomes as integer codes (index into `OUTCOMES`), shaped like the grid."""
        return np.array([OUTCOMES.index(pt.regime) for pt in self.points]).reshape(self.shape)

    def outcome_counts(self) -> dict[str, int]:
        """How many points have each outcome, in the order of `OUTCOMES`."""
        return {name: sum(pt.regime == name for pt in self.points) for name in OUTCOMES}

    def boundaries(self) -> list[tuple[float, str, str]]:
        """For a speed map: (speed_rpm, regime before, regime after) where the regime changes."""
        if len(self.axes) != 1:
            raise ParameterError("boundaries() applies to a map over one setting")
        out = []
        for a, b in zip(self.points[:-1], self.points[1:]):
            if a.regime != b.regime:
                out.append((0.5 * (a.speed_rpm + b.speed_rpm), a.regime, b.regime))
        return out

    def to_dict(self) -> dict[str, Any]:
        """The ``design-map --json`` contract."""
        return {
            "machine": self.machine.as_dict(),
            "axes": list(self.axes),
            "shock_m_per_s": self.shock,
            "points": [pt.to_dict() for pt in self.points],
        }

    def to_xarray(self):
        """The map as an xarray Dataset, settings as coordinates and units as attributes."""
        import xarray as xr

        from .. import __version__

        units = {"speed_rpm": "rpm", "stiffness": "N/m", "damping": "N s/m"}
        names = {"speed_rpm": "spin speed", "stiffness": "bearing stiffness", "damping": "bearing damping"}
        coords = {name: (name, vals, {"units": units[name], "long_name": names[name]})
                  for name, vals in zip(self.axes, self.values)}
        dims = self.axes
        shape = self.shape

        def grid(attr, dtype=float):
            return np.array([getattr(pt, attr) for pt in self.points], dtype=dtype).reshape(shape)

        recovery = np.array(
            [np.nan if pt.recovery_probability is None else pt.recovery_probability for pt in self.points]
        ).reshape(shape)
        ds = xr.Dataset(
            {
                "regime": (dims, self.regime_codes().astype(np.int8), {
                    "long_name": "outcome of the setting", "flag_values": np.arange(len(OUTCOMES), dtype=np.int8),
                    "flag_meanings": " ".join(OUTCOMES)}),
                "gamma": (dims, grid("gamma"), {"units": "1", "long_name": "damping group gamma"}),
                "omega": (dims, grid("omega"), {"units": "1", "long_name": "stiffness group omega"}),
                "whirl_admissible": (dims, grid("whirl_admissible", np.int8), {
                    "units": "1", "long_name": "contact-free whirl admissible and stable (1) or not (0)"}),
                # orbit labels hold commas ("B1,d"): the motions are joined by semicolons
                "coexisting": (dims, np.array([";".join(pt.coexisting) for pt in self.points]).reshape(shape), {
                    "long_name": "stable contact motions beside the whirl, separated by ';'"}),
                "recovery_probability": (dims, recovery, {
                    "units": "1",
                    "long_name": "fraction of shocks after which the whirl returns (nan: not simulated)"}),
            },
            coords=coords,
        )
        given = self.machine.as_dict()
        ds.attrs.update({"title": "rotorcontact design map", "source": f"rotorcontact {__version__}"})
        ds.attrs.update({f"machine_{k}": v for k, v in given.items()})
        ds.attrs.update({f"machine_{k}_units": u for k, u in Machine.units().items() if k in given})
        if self.shock is not None:
            ds.attrs["shock_m_per_s"] = self.shock
        return ds


def _check_grid(name: str, values: Sequence[float], positive: bool = True) -> np.ndarray:
    check_length(name, values, MAX_POINTS)
    arr = real_array(values)
    if arr is None or arr.size < 1 or not np.all(np.isfinite(arr)) or (positive and np.any(arr <= 0.0)):
        raise ParameterError(f"{name} = {values!r} is invalid; allowed: finite values{' > 0' if positive else ''}")
    return arr.ravel()


def _check_span(name: str, span: Any, points: int) -> tuple[float, float]:
    """A range of `design_map` of ``points`` points: two finite numbers, the first below the last (or equal
    to it, for one point)."""
    if not is_pair(span):
        raise ParameterError(f"range of {name} = {span!r} is invalid; allowed: (first, last), two numbers")
    first, last = (check_finite(f"range of {name}", v) for v in span)
    if not (first < last or (first == last and points == 1)):
        raise ParameterError(f"range of {name} = {span!r} is invalid; allowed: (first, last) with first < last "
                             "(first = last for a single point)")
    if points == 1 and first != last:
        raise ParameterError(f"range of {name} = {span!r} has two ends, but n = 1 is a single point; allowed: "
                             "n >= 2, or first = last")
    return first, last


def _check_search(machine: Machine, t_max: float) -> None:
    """Refuse a setting where the impacting orbits cannot be searched to the period ``t_max``.

    There the free flight grows or decays too fast for the guaranteed search (`period_limit`): at low
    speed, where the dimensionless damping c / (m Omega) is large. The message gives the lowest speed
    that can be mapped at the setting's stiffness and damping (the limit grows with the speed).
    """
    reach = period_limit(machine.parameters())
    if t_max <= reach:
        return
    lo, hi = math.log(machine.speed), math.log(MAX_SPEED)
    if t_max > period_limit(machine.with_speed(MAX_SPEED).parameters()):
        lowest = "none"
    else:
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if t_max > period_limit(machine.with_speed(math.exp(mid)).parameters()) else (lo, mid)
        rpm = math.exp(hi) / RPM
        step = 10.0 ** (math.floor(math.log10(rpm)) - 3)
        lowest = f"speeds from {math.ceil(rpm / step) * step:.4g} rpm"  # rounded up: that speed can be mapped
    raise ParameterError(
        f"at speed = {machine.speed / RPM:.6g} rpm (stiffness = {machine.stiffness:.6g} N/m, damping = "
        f"{machine.damping:.6g} N s/m) the free flight changes too fast to search impacting orbits to the period "
        f"{t_max:g} (up to {reach:.3g}); allowed at this stiffness and damping: {lowest}"
    )


def _classify_all(machines: list[Machine], shock: float | None, t_max: float, progress: bool,
                  **scale: Any) -> tuple[MapPoint, ...]:
    """Classify each setting, with a progress bar on stderr if asked; the recovery probabilities of the
    bistable points (with ``shock``) are one chunked study, run as ``scale`` says
    (`recovery_probabilities`)."""
    from .execution import progress_bar

    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    for m in machines:
        _check_search(m, t_max)
    if shock is not None:
        _check_shock(machines, shock)  # before the classification, which can take minutes
    pts = []
    with progress_bar(len(machines), "design map", progress, unit="point") as bar:
        for m in machines:
            pts.append(classify_machine(m, t_max=t_max))
            bar.update(1)
    if shock is None:
        return tuple(pts)
    bistable = [i for i, pt in enumerate(pts) if pt.regime == "bistable"]
    recovery = recovery_probabilities([machines[i] for i in bistable], shock, progress=progress, **scale)
    for i, value in zip(bistable, recovery):
        pts[i] = replace(pts[i], recovery_probability=float(value))
    return tuple(pts)


def speed_map(machine: Machine, speeds_rpm: Sequence[float], *, shock: float | None = None,
              t_max: float = 12.0, progress: bool = False, n_jobs: int | None = None, scheduler: Any = None,
              processes: bool = True) -> DesignMap:
    """Classify ``machine`` at each speed (rpm); see `classify_machine` and `recovery_probability`.

    ``progress`` shows a progress bar over the speeds on stderr (worth it with ``shock``, whose
    recovery probabilities are simulated, as one study run as ``n_jobs``, ``scheduler`` and
    ``processes`` say: `rotorcontact.studies.execution.make_executor`).
    """
    check_machine(machine, optional=False)
    speeds = _check_grid("speeds_rpm", speeds_rpm)
    fastest = rad_s_to_rpm(MAX_SPEED)
    if np.any(speeds > fastest):
        raise ParameterError(f"speeds_rpm = {quoted(speeds_rpm)} holds {float(np.max(speeds)):g} rpm; allowed: speeds "
                             f"up to {fastest:.6g} rpm (the Machine's bound, {MAX_SPEED:g} rad/s)")
    machines = [machine.with_speed(rpm_to_rad_s(s)) for s in speeds]
    points = _classify_all(machines, shock, t_max, progress, n_jobs=n_jobs, scheduler=scheduler, processes=processes)
    return DesignMap(machine, ("speed_rpm",), (speeds,), points, shock)


def plane_map(machine: Machine, axes: tuple[str, str], first: Sequence[float], second: Sequence[float], *,
              shock: float | None = None, t_max: float = 12.0, progress: bool = False, n_jobs: int | None = None,
              scheduler: Any = None, processes: bool = True) -> DesignMap:
    """Classify a plane of settings: ("speed_rpm", "stiffness") or ("stiffness", "damping").

    The other fields of ``machine`` stay fixed. ``progress`` shows a progress bar over the points on stderr;
    ``n_jobs``, ``scheduler`` and ``processes`` as for `speed_map`.
    """
    check_machine(machine, optional=False)
    allowed = (("speed_rpm", "stiffness"), ("stiffness", "damping"), ("speed_rpm", "damping"))
    if tuple(axes) not in allowed:
        raise ParameterError(f"axes = {axes!r} is invalid; allowed: {', '.join(map(str, allowed))}")
    a = _check_grid(axes[0], first)
    b = _check_grid(axes[1], second, positive=axes[1] != "damping")
    if axes[1] == "damping" and np.any(b < 0.0):
        raise ParameterError(f"damping = {second!r} is invalid; allowed: values >= 0")
    machines = []
    for x in a:
        for y in b:
            changes = {}
            for name, val in ((axes[0], x), (axes[1], y)):
                if name == "speed_rpm":
                    changes["speed"] = rpm_to_rad_s(val)
                else:
                    changes[name] = val
            machines.append(replace(machine, **changes))
    points = _classify_all(machines, shock, t_max, progress, n_jobs=n_jobs, scheduler=scheduler, processes=processes)
    return DesignMap(machine, tuple(axes), (a, b), points, shock)


#: Most points along each range of `design_map`; it bounds the run time.
MAX_POINTS = 100_000


def design_map(machine: Machine, ranges: dict[str, tuple[float, float]], n: int, *, shock: float | None = None,
               t_max: float = 12.0, progress: bool = False, n_jobs: int | None = None, scheduler: Any = None,
               processes: bool = True) -> DesignMap:
    """The map over the settings given ranges: a speed map, or a plane of two settings.

    Parameters
    ----------
    machine : Machine
        The base machine; the settings without a range keep its values.
    ranges : dict
        ``(first, last)`` for one or two of ``"speed"`` (rpm), ``"stiffness"`` (N/m) and
        ``"damping"`` (N s/m), in a combination of `MAP_AXES`.
    n : int
        Points along the range of a speed map; a plane has ``min(n, MAX_PLANE_SIDE)`` along each side.
    shock, t_max, progress, n_jobs, scheduler, processes
        As for `speed_map` and `plane_map`.

    Raises
    ------
    ParameterError
        For another combination of settings.
    """
    check_machine(machine, optional=False)
    allowed = "; ".join(" and ".join(sorted(k)) for k in MAP_AXES)
    if not isinstance(ranges, Mapping) or not all(isinstance(k, str) for k in ranges):
        raise ParameterError(f"ranges = {ranges!r} is invalid; allowed: a dict of (first, last) by setting: {allowed}")
    axes = MAP_AXES.get(frozenset(ranges))
    if axes is None:
        raise ParameterError(f"ranges of {', '.join(sorted(ranges)) or 'nothing'} give no map; allowed: {allowed}")
    n = check_int("n", n, 1, MAX_POINTS)
    side = n if len(ranges) == 1 else min(n, MAX_PLANE_SIDE)
    grids = {name: np.linspace(*_check_span(name, span, side), side) for name, span in ranges.items()}
    first, *second = [grids["speed" if axis == "speed_rpm" else axis] for axis in axes]
    scale = {"n_jobs": n_jobs, "scheduler": scheduler, "processes": processes}
    if not second:
        return speed_map(machine, first, shock=shock, t_max=t_max, progress=progress, **scale)
    return plane_map(machine, axes, first, second[0], shock=shock, t_max=t_max, progress=progress, **scale)

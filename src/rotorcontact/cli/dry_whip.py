"""``rotorcontact dry-whip``: the steady dry whip of a rotor on a touchdown bearing on springs (MODEL.md §8)."""

from __future__ import annotations

import argparse
import sys

from ..errors import ParameterError
from ..model.params import load_machine
from ..model.units import option_quantity
from .options import print_json

BEARINGS = ("failed", "acting")


def register(sub) -> None:
    p = sub.add_parser(
        "dry-whip",
        description="The steady dry whip of the machine (MODEL.md §8): rotor and stator on springs whirling "
                    "backward together in sliding contact, near the coupled natural frequency. Needs "
                    "contact = 'compliant' and a stator on springs (stator_mass, stator_stiffness).",
    )
    p.add_argument("machine", metavar="M.toml", help="machine file")
    p.add_argument("--speed", default=None, metavar="SPEED",
                   help="spin speed held, with units (12000rpm, 1250 rad/s; default: the machine's)")
    p.add_argument("--bearing", default="failed", metavar="STATE",
                   help="the magnetic bearing: failed (k = c = 0, default) or acting")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..analysis.dry_whip import steady_dry_whip

    machine = load_machine(args.machine)
    if args.bearing not in BEARINGS:
        raise ParameterError(f"--bearing = {args.bearing!r}; allowed: {', '.join(BEARINGS)}")
    try:
        if args.speed is not None:
            machine = machine.with_speed(option_quantity("--speed", args.speed, "rad/s"))
        whip = steady_dry_whip(machine, bearing_failed=args.bearing == "failed")
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("bearing_failed = False", "--bearing = acting")
                             .replace("speed =", "--speed =").replace("----speed", "--speed")) from None
    out = whip.to_dict()
    from ..simulation.drop_run import MAX_START_DEPTH

    depth = whip.penetration / machine.clearance
    if depth > MAX_START_DEPTH:
        print(f"rotorcontact dry-whip: warning: the whip presses {depth:.3g} clearances into the stator, beyond "
              f"the compliant law's range ({MAX_START_DEPTH:g}), and the simulator cannot start on it",
              file=sys.stderr)
    if args.json:
        print_json(out)
        return 0
    print(f"dry whip at {out['speed_rpm']:.6g} rpm (bearing {out['bearing']}): "
          f"whirl {out['whirl_frequency_hz']:.6g} Hz "
          f"(coupled natural frequency {out['coupled_frequency_hz']:.6g} Hz)")
    print(f"rotor orbit {out['rotor_orbit_m'] * 1e6:.6g} um, stator orbit {out['stator_orbit_m'] * 1e6:.6g} um, "
          f"contact force {out['normal_force_N']:.6g} N, penetration {out['penetration_m'] * 1e6:.6g} um, "
          f"slip {out['slip_velocity_m_per_s']:.6g} m/s")
    return 0

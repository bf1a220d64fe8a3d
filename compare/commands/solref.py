"""solref and solimp to paste into MJCF for a spring-damper contact, for each mapping, each with
its error measured on a drop test run now.

For a body of mass M (kg) on a contact of stiffness K (N/m) and damping C (N s/m): the seed's,
the physical and the penalty mapping, and the calibrated one when DIR/calibration.json of a
`calibrate` run exists (--calibration, default reports/calibration/calibration.json). The
drop test drops the body (--shape point | box | circle) from 0.3 m with gravity and normal
contact only, under the linear damping law (MuJoCo's), and compares MuJoCo with custom_sim.
Exit status 0, or 2 for bad input (a non-positive mass or stiffness, ...).
"""
from __future__ import annotations

from ..table import text

DEFAULT_CALIBRATION = "reports/calibration/calibration.json"


def add_arguments(parser) -> None:
    parser.add_argument("--mass", type=float, required=True, metavar="M", help="body mass, kg")
    parser.add_argument("--k", type=float, required=True, metavar="K", help="contact stiffness, N/m")
    parser.add_argument("--c", type=float, required=True, metavar="C", help="contact damping, N s/m")
    parser.add_argument("--shape", default="point", help="point | box | circle (default point)")
    parser.add_argument("--size", type=float, nargs=2, default=(0.2, 0.1), metavar=("W", "H"),
                        help="box width and height, m (default 0.2 0.1)")
    parser.add_argument("--radius", type=float, default=0.1, help="circle radius, m (default 0.1)")
    parser.add_argument("--calibration", default=DEFAULT_CALIBRATION, metavar="FILE",
                        help=f"a stored calibration.json (default {DEFAULT_CALIBRATION}, used if present)")


def main(args) -> int:
    from ..tools.calibration.conversion import conversion_table, drop_scene

    drop_scene(args.mass, args.k, args.c, args.shape, args.size, args.radius)  # bad input first
    rows = conversion_table(args.mass, args.k, args.c, args.shape, args.size, args.radius, args.calibration)
    print(f"{args.shape} of {args.mass:g} kg, k = {args.k:g} N/m, c = {args.c:g} N s/m; error: MuJoCo against "
          f"custom_sim on a drop from 0.3 m (gravity and normal contact, linear damping law, dt 1e-4 s)")
    print(text(["mapping", "position error max (m)", "MJCF <pair> (or <geom>) attributes"],
               [[r.mapping, "diverged" if r.position_error_max is None else f"{r.position_error_max:.3e}",
                 r.mjcf() + (f"  ({r.note})" if r.note else "")] for r in rows], align=["left", "right", "left"]))
    return 0

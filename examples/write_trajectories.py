"""Run examples/seed_sim.py on scene files exported as JSON and write one CSV per scene:
what a simulator in any language does for `python -m compare run --trajectories DIR`.

    python -m compare scene box_drop --json > box_drop.json
    python examples/write_trajectories.py box_drop.json --out my_runs
    python -m compare run box_drop --trajectories my_runs

Each CSV has the header t,x,y,theta,vx,vy,omega, then the t = 0 row (the scene's state0) and
one row per step. Numbers are written with 17 significant digits, which keep a double exactly;
fewer digits are accepted, and the harness allows for their rounding.
"""
import argparse
import json
from pathlib import Path

import numpy as np

from seed_sim import step


def run(scene: dict) -> np.ndarray:
    """(steps + 1, 7) rows t, x, y, theta, vx, vy, omega."""
    n, dt = scene["steps"], scene["dt"]
    out = np.empty((n + 1, 7))
    z = np.array(scene["state0"], dtype=float)
    out[0] = [0.0, *z]
    for i in range(1, n + 1):
        z = step(z, scene, dt)
        out[i] = [i * dt, *z]
    return out


def write(scene: dict, folder: Path, digits: int = 17) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{scene['name']}.csv"
    np.savetxt(path, run(scene), delimiter=",", header="t,x,y,theta,vx,vy,omega", comments="",
               fmt=f"%.{digits}g")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+", metavar="SCENE.json", help="from `python -m compare scene NAME --json`")
    parser.add_argument("--out", default="trajectories", help="folder for <scene name>.csv")
    parser.add_argument("--digits", type=int, default=17, help="significant digits written")
    args = parser.parse_args()
    for spec in args.scenes:
        print(write(json.loads(Path(spec).read_text()), Path(args.out), args.digits))


if __name__ == "__main__":
    main()

"""An outsider's simulator, written apart from the examples: RK4, a smooth Coulomb friction
with its own eps and an unclamped spring-damper with its own c, the state a dict, tuples back."""
import math

INTEGRATOR = "rk4"
EPS_V = 0.02        # m/s: friction regularisation velocity (alpha = 50 s/m)
C_DAMP = 15.0


def forces(s, sc):
    mp = sc["mass_properties"]
    m, I = mp["mass"], mp["inertia"]
    fx, fy, tq = 0.0, -m * sc["g"], 0.0
    ct = sc["contact"]
    for (px, py) in mp["contact_points"]:
        if mp["points_rotate"]:
            c, sn = math.cos(s["th"]), math.sin(s["th"])
            rx, ry = c * px - sn * py, sn * px + c * py
        else:
            rx, ry = px, py
        d = -(s["y"] + ry)
        if d <= 0:
            continue
        vn = s["vy"] + s["w"] * rx
        vt = s["vx"] - s["w"] * ry
        fn = ct["k"] * d - C_DAMP * vn
        ft = -ct["mu"] * fn * vt / math.sqrt(vt * vt + EPS_V * EPS_V)
        fx += ft; fy += fn; tq += rx * fn - ry * ft
    return fx / m, fy / m, (tq / I if mp["rotates"] else 0.0)


def deriv(z, sc):
    s = dict(zip(("x", "y", "th", "vx", "vy", "w"), z))
    ax, ay, aw = forces(s, sc)
    return (z[3], z[4], z[5], ax, ay, aw)


def step(state, scene, dt):
    z = tuple(float(v) for v in state)
    k1 = deriv(z, scene)
    k2 = deriv(tuple(a + dt / 2 * b for a, b in zip(z, k1)), scene)
    k3 = deriv(tuple(a + dt / 2 * b for a, b in zip(z, k2)), scene)
    k4 = deriv(tuple(a + dt * b for a, b in zip(z, k3)), scene)
    return tuple(a + dt / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(z, k1, k2, k3, k4))


def simulate(scene):
    import numpy as np
    z = scene["state0"]
    out = [list(z)]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        out.append(list(z))
    return np.array(out)

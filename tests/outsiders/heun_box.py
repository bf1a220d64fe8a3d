"""An outsider's box simulator in array style: the four corners as one (4, 2) array, the forces on
all of them at once, its own geometry from the box's size. It says RK4 but takes Heun's step
(explicit trapezoid, second order): a label copied from a template, the kind of slip only the
order of the error shows. Boxes only; anything else is refused."""
import numpy as np

INTEGRATOR = "rk4"
SHAPES = ("box",)

CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) / 2.0


def rates(q, sc):
    """dq/dt for q = [x, y, th, vx, vy, w]."""
    b, ct, on = sc["body"], sc["contact"], set(sc["effects"])
    m = b["mass"]
    w_, h_ = b["size"]
    inertia = m * (w_ * w_ + h_ * h_) / 12.0
    c, s = np.cos(q[2]), np.sin(q[2])
    r = (CORNERS * [w_, h_]) @ np.array([[c, s], [-s, c]])          # corners turned, (4, 2)
    depth = -(q[1] + r[:, 1])
    vt = q[3] - q[5] * r[:, 1]
    vn = q[4] + q[5] * r[:, 0]
    if "contact" in on:
        if ct["damping_law"] == "compression":
            fn = ct["k"] * depth + ct["c"] * np.maximum(0.0, -vn)
        else:
            fn = np.maximum(0.0, ct["k"] * depth - ct["c"] * vn)
        fn = np.where(depth > 0.0, fn, 0.0)
    else:
        fn = np.zeros(4)
    ft = -ct["mu"] * fn * np.tanh(ct["alpha"] * vt) if "friction" in on else np.zeros(4)
    fx, fy = ft.sum(), fn.sum() - (m * sc["g"] if "gravity" in on else 0.0)
    torque = np.sum(r[:, 0] * fn - r[:, 1] * ft)
    return np.array([q[3], q[4], q[5], fx / m, fy / m, torque / inertia])


def step(state, sc, dt):
    if sc["body"]["shape"] not in SHAPES:
        raise NotImplementedError(f"only boxes ({sc['body']['shape']} is not one)")
    q = np.asarray(state, dtype=float)
    k1 = rates(q, sc)
    k2 = rates(q + dt * k1, sc)
    return q + 0.5 * dt * (k1 + k2)

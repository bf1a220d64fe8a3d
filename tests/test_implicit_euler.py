"""Implicit Euler solves its implicit equations, with an analytic Jacobian that is right."""
import math

import numpy as np
import pytest

from custom_sim import simulate
from custom_sim.forces import acceleration_jacobian, accelerations
from custom_sim.model import build_model

# central differences with step 1e-7 on O(1) states: truncation ~1e-14 x f''', round-off
# ~1e-16 |f| / 1e-7 = 1e-9 |f|; accelerations are ~1e2..1e3, so 1e-5 relative is safe
FD_STEP = 1e-7
FD_REL = 1e-5


def test_one_step_matches_the_closed_form_on_a_spring(scene_factory):
    """Point in contact, linear law, no gravity: m d'' = -k d - c d' is linear, so implicit
    Euler's update is one 2x2 solve: [1 + h c/m, h k/m; -h, 1] [v1, y1]^T = [v0, y0]^T
    (with y = -d). Newton must land on it."""
    k, c, m, h = 1e4, 30.0, 0.7, 1e-3
    y0, v0 = -2e-3, 0.1
    scene = scene_factory({"shape": "point", "mass": m, "contact_height": 0.0},
                          {"position": [0.0, y0], "velocity": [0.0, v0]},
                          duration=h, dt=h, integrator="implicit_euler", effects=["contact"],
                          contact={"k": k, "c": c, "damping_law": "linear"})
    tr = simulate(scene)
    # v1 = v0 + h (-k y1 - c v1)/m with d = -y;  y1 = y0 + h v1
    a = np.array([[1 + h * c / m, h * k / m], [-h, 1.0]])
    v1, y1 = np.linalg.solve(a, [v0, y0])
    assert tr.vy[1] == pytest.approx(v1, rel=1e-10)
    assert tr.y[1] == pytest.approx(y1, rel=1e-10)
    # a linear system: Newton from the explicit predictor converges in two iterations
    # (one to land, one to see the update is zero)
    assert tr.newton_iterations <= 2


@pytest.mark.parametrize("law", ["compression", "linear"])
@pytest.mark.parametrize("shape", ["box", "circle", "t"])
def test_jacobian_against_finite_differences(scene_factory, law, shape):
    bodies = {
        "box": {"shape": "box", "mass": 1.2, "size": [0.2, 0.1]},
        "circle": {"shape": "circle", "mass": 0.8, "radius": 0.1},
        "t": {"shape": "compound", "parts": [{"size": [0.3, 0.06], "offset": [0.0, 0.12], "mass": 0.6},
                                             {"size": [0.06, 0.24], "offset": [0.0, 0.0], "mass": 0.4}]},
    }
    scene = scene_factory(bodies[shape], {"position": [0.0, 0.0]},
                          effects=["gravity", "contact", "friction"] + (["rolling_friction"] if shape == "circle" else []),
                          contact={"k": 1e4, "c": 25.0, "damping_law": law, "mu": 0.6, "alpha": 20.0,
                                   "mu_roll": 0.003 if shape == "circle" else 0.0})
    model, points = build_model(scene)
    rng = np.random.default_rng(7)
    jac = np.zeros((3, 6))
    checked = 0
    for _ in range(60):
        z = np.array([0.0, rng.uniform(-0.01, 0.12), rng.uniform(-0.6, 0.6),
                      rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-3, 3)])
        if near_a_kink(scene, model, points, z):
            continue  # a finite difference across a kink is not a derivative
        acceleration_jacobian(model, points, z, jac)
        fd = central_difference(model, points, z)
        assert np.allclose(jac, fd, rtol=FD_REL, atol=FD_REL * (np.max(np.abs(fd)) + 1)), z
        checked += 1
    assert checked >= 40, f"only {checked} of 60 states away from kinks"


# A state is near a kink when a perturbation of KINK_MARGIN >> FD_STEP could cross one:
# a contact switch (d = 0), the max() of either damping law, or sign(omega) of rolling.
KINK_MARGIN = 1e-4


def near_a_kink(scene, model, points, z):
    c, s = (math.cos(z[2]), math.sin(z[2])) if model.points_rotate else (1.0, 0.0)
    if model.rolling and abs(z[5]) < KINK_MARGIN:
        return True
    for lx, ly in points:
        rx, ry = c * lx - s * ly, s * lx + c * ly
        d, vcy = -(z[1] + ry), z[4] + z[5] * rx
        push = scene.contact.k * d - scene.contact.c * vcy
        if abs(d) < KINK_MARGIN or (d > 0 and (abs(vcy) < KINK_MARGIN or abs(push) < KINK_MARGIN * scene.contact.k)):
            return True
    return False


def central_difference(model, points, z):
    fd = np.zeros((3, 6))
    for j in range(6):
        dz = np.zeros(6)
        dz[j] = FD_STEP
        fd[:, j] = (np.array(accelerations(model, points, z + dz, 0.0, 0.0, 0.0))
                    - np.array(accelerations(model, points, z - dz, 0.0, 0.0, 0.0))) / (2 * FD_STEP)
    return fd


def test_jacobian_exact_at_smooth_states(scene_factory):
    """The same check without any skipping, at states chosen away from every kink."""
    scene = scene_factory({"shape": "box", "mass": 1.0, "size": [0.2, 0.1]}, {"position": [0.0, 0.0]},
                          contact={"k": 1e4, "c": 25.0, "damping_law": "linear", "mu": 0.6, "alpha": 20.0})
    model, points = build_model(scene)
    z = np.array([0.1, 0.045, 0.02, 0.3, -0.2, 1.5])  # lower corners 7 and 3 mm deep, pushing
    assert not near_a_kink(scene, model, points, z)
    jac = np.zeros((3, 6))
    acceleration_jacobian(model, points, z, jac)
    fd = central_difference(model, points, z)
    assert np.abs(fd).max() > 1e3, "the state must be in contact"
    assert np.allclose(jac, fd, rtol=FD_REL, atol=FD_REL * (np.max(np.abs(fd)) + 1))


def test_newton_converges_on_every_builtin_scene():
    from compare.scenarios import load_builtins
    import dataclasses
    for scene in load_builtins():
        tr = simulate(dataclasses.replace(scene, integrator="implicit_euler", duration=min(scene.duration, 1.0)))
        assert tr.meta["newton_unconverged_steps"] == 0, scene.name
        assert tr.meta["newton_max_iterations"] <= 10, (scene.name, tr.meta)


def test_the_implicit_step_allocates_nothing():
    """The Newton step and its Jacobian build no temporary array: their compiled code calls no
    allocator (an array expression such as `k * dd` would: 14 allocation sites in an earlier
    Jacobian). Fresh uncached copies are compiled, since numba shows no code loaded from cache."""
    import numba

    from custom_sim.integrators import implicit_euler_step
    from custom_sim.model import initial_state
    from compare.scenarios import load

    scene = load("box_drop")
    model, points = build_model(scene)
    z = initial_state(scene)
    work = np.zeros((18, 6))
    jac = numba.njit(acceleration_jacobian.py_func)
    jac(model, points, z, work[2:5])
    step = numba.njit(implicit_euler_step.py_func)
    step(model, points, z.copy(), scene.dt, 0.0, 0.0, 0.0, np.zeros(4, dtype=np.int64), work)
    for f in (jac, step):
        code = "".join(f.inspect_llvm().values())
        assert code, f"no code to inspect for {f.py_func.__name__}"
        calls = code.count("NRT_MemInfo_alloc") + code.count("NRT_Allocate")
        assert calls == 0, f"{f.py_func.__name__} calls an allocator {calls} times"

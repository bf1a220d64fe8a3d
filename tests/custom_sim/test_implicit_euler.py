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


@pytest.mark.slow   # compiles four fresh functions (4 s): a property of speed, not of the motion
def test_the_implicit_step_allocates_nothing():
    """The Newton step, its Jacobian and the step on a jump build no temporary array: their compiled code calls no
    allocator (an array expression such as `k * dd` would: 14 allocation sites in an earlier
    Jacobian). Fresh uncached copies are compiled, since numba shows no code loaded from cache."""
    import numba

    from custom_sim.filippov import jump_step
    from custom_sim.forces import loaded_acceleration_jacobian
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
    held_jac = numba.njit(loaded_acceleration_jacobian.py_func)
    held_jac(model, points, z, work[2:5], 0, 0.5)
    jump = numba.njit(jump_step.py_func)
    zi = z.copy()
    jump(model, points, z, zi, scene.dt, 0.0, 0.0, 0.0, np.zeros(4, dtype=np.int64), work, 1e-10, 1e-10)
    for f in (jac, step, held_jac, jump):
        code = "".join(f.inspect_llvm().values())
        assert code, f"no code to inspect for {f.py_func.__name__}"
        calls = code.count("NRT_MemInfo_alloc") + code.count("NRT_Allocate")
        assert calls == 0, f"{f.py_func.__name__} calls an allocator {calls} times"


# A point mass falling at V0 from Y0 above the ground, one step of H: the semi-implicit step
# would end H |V0| - Y0 = 50 um deep. With c / m = 1e5 1/s the damper alone, engaging at d = 0
# with c |v|, stops the fall in one step from any v < -0.02 m/s, so no v1 solves the implicit
# equation (derivation in the test).
V0, Y0, H = -1.0, 5e-5, 1e-4
JUMP_MASS, JUMP_C, JUMP_K, G = 0.1, 1e4, 1e5, 9.81


@pytest.mark.parametrize("law", ["compression", "linear"])
def test_no_root_step_lands_on_the_jump(scene_factory, law):
    """G(v) = v - v0 + h g - h [y0 + h v < 0] (k d + c max(0, -v)) / m. Out of contact
    (v > v* = -y0/h) G = v - v0 + h g > 0; in contact G is increasing in v and at v* equals
    v* - v0 + h g - h c |v*| / m = 0.5 + 0.00098 - 5 < 0: G jumps over zero at v*, no root.
    The jump's point is v1 = v*, y1 = 0, and G_out + lam (G_in - G_out) = 0 gives
    lam = (v* - v0 + h g) m / (h c |v*|) = 0.1002, inside [0, 1]. The harness's own Newton
    must find no root there, and its check must accept the step."""
    import dataclasses

    from compare.oracle.reference import Equations
    from compare.oracle.one_step import one_step
    from compare.checks.step_check import check_step

    scene = scene_factory({"shape": "point", "mass": JUMP_MASS, "contact_height": 0.0},
                          {"position": [0.0, Y0], "velocity": [0.0, V0]},
                          duration=H, dt=H, integrator="implicit_euler", effects=["gravity", "contact"],
                          g=G, contact={"k": JUMP_K, "c": JUMP_C, "damping_law": law})
    tr = simulate(scene)
    v_star = -Y0 / H
    assert tr.meta["newton_unconverged_steps"] == 0
    assert tr.vy[1] == pytest.approx(v_star, rel=1e-12)
    assert abs(tr.y[1]) <= 1e-17   # on the ground to round-off of y0 + h v1
    lam = (v_star - V0 + H * G) * JUMP_MASS / (H * JUMP_C * abs(v_star))
    assert 0.0 < lam < 1.0
    states = tr.states()
    _, _, solved = one_step(Equations.from_scene(scene), states[:1], H, "implicit_euler")
    assert not solved[0], "the harness finds a root: the state does not test the jump"
    row = check_step(scene, states, "implicit_euler", H)
    assert row.passed is True and row.details["no_root_steps"] == 1, row.reason
    # and a step off the jump by more than round-off fails the same check
    off = states.copy()
    off[1, 4] += 1e-8
    off[1, 1] += H * 1e-8
    assert check_step(dataclasses.replace(scene), off, "implicit_euler", H).passed is False


def test_a_jump_step_is_not_taken_where_a_root_exists(scene_factory):
    """With a weak damper (c / m = 1e3 1/s) G_in(v*) = 0.5 - 0.05 > 0: the point lands, a root
    exists in contact, and the step is plain Newton's root, with |G| to round-off."""
    from custom_sim.forces import no_point
    from custom_sim.implicit_residual import residual
    from custom_sim.integrators import RESIDUAL_TOL
    from custom_sim.model import build_model

    scene = scene_factory({"shape": "point", "mass": JUMP_MASS, "contact_height": 0.0},
                          {"position": [0.0, Y0], "velocity": [0.0, V0]},
                          duration=H, dt=H, integrator="implicit_euler", effects=["gravity", "contact"],
                          g=G, contact={"k": JUMP_K, "c": 100.0, "damping_law": "compression"})
    tr = simulate(scene)
    assert tr.meta["newton_unconverged_steps"] == 0
    assert tr.y[1] < 0.0   # in contact, not on the jump
    model, points = build_model(scene)
    states = tr.states()
    zi = states[1].copy()
    res = residual(model, points, states[0], zi, H, 0.0, 0.0, 0.0, no_point(), 1.0, np.zeros(3),
                   np.zeros(4, dtype=np.int64))
    assert res <= RESIDUAL_TOL


def test_fast_impact_at_its_former_step_lands_on_the_jump():
    """fast_impact at its former step of 1e-4 s: its corner's touchdown at step 80 has no root
    (the harness's Newton finds none); the plain damped Newton stopped 4.1e-5 m/s (vy) off the
    jump's point and failed the step check there. Now every step holds to round-off."""
    import dataclasses

    from compare.scenarios import load
    from compare.checks.step_check import check_step

    dt = 1e-4
    scene = dataclasses.replace(load("fast_impact"), integrator="implicit_euler", dt=dt, duration=100 * dt)
    tr = simulate(scene)
    row = check_step(scene, tr.states(), "implicit_euler", dt)
    assert row.details["no_root_steps"] >= 1, "the window no longer holds the jump it tests"
    assert row.passed is True and tr.meta["newton_unconverged_steps"] == 0, (row.details["first_step"], row.details["phase"])


def test_solve3_reports_a_singular_matrix_instead_of_dividing_by_zero():
    """Two proportional rows: elimination leaves an exact zero pivot. The compiled solve (Python's
    error model, where 1 / 0 raises) says so with False; a regular system it solves."""
    from custom_sim.linear3 import solve3

    singular = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [1.0, 0.0, 1.0]])
    assert solve3(singular.copy(), np.ones(3), np.zeros(3)) is False
    regular = np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]])
    b, x = np.array([1.0, 2.0, 3.0]), np.zeros(3)
    assert solve3(regular.copy(), b.copy(), x) is True
    assert np.allclose(regular @ x, b, rtol=0.0, atol=1e-15)


# box_slide under the sign friction at h = 1e-2 s, standing on a corner at theta = -1.65 rad
# and barely turning: implicit Euler's Newton stalls on the friction's jump, and the touchdown
# jump step tried there runs its lam off to 1e12, where its Newton matrix is singular to the bit.
SINGULAR_JUMP_STATE = [0.0, 0.0997051715381252, -1.6461623677238917, -0.0, 0.0, 0.00016270994544930405]


def test_a_step_whose_jump_newton_turns_singular_ends_as_an_unconverged_step():
    """That step raised ZeroDivisionError out of the compiled loop. A singular Newton matrix
    gives no direction: the jump step is not taken, and the step ends where the damped Newton
    left it, finite, counted as one unconverged solve (the sign law has no root there)."""
    import dataclasses

    from compare.scenarios import load
    from custom_sim import Stepper

    base = load("box_slide")
    scene = dataclasses.replace(base, integrator="implicit_euler", dt=1e-2,
                                contact=dataclasses.replace(base.contact, friction_law="sign", alpha=None))
    stepper = Stepper(scene, watch_chatter=False)
    stepper.reset(SINGULAR_JUMP_STATE)
    state = stepper.advance(1)
    assert np.all(np.isfinite(state))
    assert stepper.counters[3] == 1

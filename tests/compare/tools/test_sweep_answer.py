"""The sweep's answer to "the cheapest way to 1 mm" and the README table it writes: the same
answer whatever the timings, times compared only beyond their spread, the machine named."""
from __future__ import annotations


from markdown_table import rows

from compare.tools.accuracy.workprecision import Run, SceneSweep
from compare.tools.sweep.answer import answer
from compare.tools.sweep.cheapest import cheapest_table
from compare.scenarios import load


def runs(rk4_time, euler_time, spread=0.1e-3):
    """box_slide-like ladders (1 s): RK4 at 2 ms and semi-implicit Euler at 0.5 ms both reach
    1 mm with 2000 force evaluations; MuJoCo's RK4 at 2 ms within 1 mm of its own solution."""
    def r(sim, integ, dt, evals_per_step, t, err):
        steps = int(round(1.0 / dt))
        return Run(sim, integ, dt, steps, error_max=err, error_max_self=err, cpu_time=t,
                   cpu_time_spread=spread, force_evals=evals_per_step * steps)
    return [r("custom", "rk4", 2e-3, 4, rk4_time, 5e-4), r("custom", "rk4", 1e-3, 4, 2 * rk4_time, 1e-5),
            r("custom", "semi_implicit_euler", 2e-3, 1, 0.02e-3, 5e-3),
            r("custom", "semi_implicit_euler", 5e-4, 1, euler_time, 8e-4),
            r("custom", "semi_implicit_euler", 2.5e-4, 1, 2 * euler_time, 4e-4),
            r("mujoco", "RK4", 2e-3, 4, 8e-3, 2e-4), r("mujoco", "Euler", 5e-4, 1, 9e-3, 9e-4)]


def sweep(rk4_time, euler_time, spread=0.1e-3):
    return SceneSweep(load("box_slide"), {"amplification": 1.0}, runs(rk4_time, euler_time, spread),
                      {"change_at_double_step": 0.0, "error_max": 1e-4})


def test_the_answer_is_the_same_when_the_timings_swap():
    a = answer(sweep(0.11e-3, 0.12e-3))
    b = answer(sweep(0.12e-3, 0.11e-3))
    for text in (a, b):
        assert text.startswith("ours: RK4 at dt = 0.002 s, 2000 force evaluations (500 steps)"), text
        assert "cannot be told from it" in text or "within the timing spread" in text, text
        assert "MuJoCo: RK4 at dt = 0.002 s, 2000 force evaluations" in text, text


def test_a_time_difference_beyond_the_spread_is_reported():
    text = answer(sweep(0.5e-3, 0.1e-3, spread=0.01e-3))
    assert "semi-implicit Euler at dt = 0.0005 s is faster beyond the spread" in text, text


def test_the_table_names_the_machine_and_the_command():
    table = cheapest_table([sweep(0.11e-3, 0.12e-3)], "python -m compare sweep box_slide")
    first = table.splitlines()[0]
    assert first.startswith("Measured by `python -m compare sweep box_slide` on ") and "cores" in first
    scene, ours, our_time, theirs, their_time = next(r for r in rows(table) if r[0] == "box_slide")
    assert ours == "RK4, dt 0.002 s: 2000 force evaluations" and theirs.startswith("MuJoCo RK4, dt 0.002 s")
    assert "+-" in our_time and "+-" in their_time

"""index.md of the sweep: how it is measured (the constants the ladders and the search use, in s
and m), each scene's answer to "the cheapest way to 1 mm", the stability table, and a section
per scene with its figure and every run.
"""
from __future__ import annotations

from pathlib import Path

from ...oracle.reference import REFERENCE_RTOL
from ...table import DASH, markdown
from ..accuracy.stability_search import ENERGY_GROWTH_LIMIT, QUIET_CONTACT_SHARE
from ..accuracy.workprecision import GRID, LADDER, MUJOCO_CONVERGED_N, MUJOCO_LADDER, RUN_BUDGET
from .answer import answer
from .cheapest import cheapest_table
from .residual import residual_rows
from .stability import stability_section
from .wording import num
from .yours import yours_section


def write_index(results, path: Path, runtime: float, jobs: int) -> Path:
    """index.md of a sweep that took runtime (s) on jobs workers: the method, each scene's answer,
    the stability table and a section per scene."""
    lines = [
        "# What accuracy costs: work-precision and stability",
        "",
        f"Sweep of {len(results)} scene(s) in {runtime:.0f} s on {jobs} worker process(es) "
        f"(`python -m compare sweep`).",
        "",
        "How it is measured (docs/physics.md, \"Accuracy against cost\"):",
        "",
        f"- **Reference**: the same equations as custom_sim solved by scipy's DOP853 at rtol = atol = "
        f"{REFERENCE_RTOL:g}, each contact switch (a point touching or leaving, the kink of the damping law; "
        f"the sign of omega under a sign(omega) rolling law) located as an event and the integration "
        f"restarted there "
        f"(compare/oracle/reference.py). *Converged* = the change when the tolerance is tightened 100-fold.",
        f"- **Error**: distance between centres of mass, simulator against reference, every {GRID * 1e3:g} ms; "
        f"max and RMS (L2) over the run. MuJoCo's error is given twice: against its own converged solution "
        f"(RK4 at dt = {GRID / MUJOCO_CONVERGED_N:g} s: numerical error only) and against our reference "
        "(numerical error plus model difference).",
        "- **Cost**: time of the stepping alone (ours: one compiled call, MuJoCo: `mj_step` with nstep, "
        "both recording nothing), the minimum over repeats after a warm-up, as the CPU time of the stepping "
        "thread (the wall time on an idle core; on this shared 2-core machine it does not charge a run for "
        "time given to other processes; results.json has the wall times too), and force evaluations.",
        f"- **Ladders**: dt = {GRID:g} s / n, n in {list(LADDER)} for ours and {list(MUJOCO_LADDER)} for MuJoCo; "
        f"a rung predicted to take over {RUN_BUDGET:g} s is skipped; unstable rungs are left out of the diagrams.",
        f"- **Stable** = no divergence (for MuJoCo: no reset on a bad acceleration), for ours no chatter (a contact "
        f"point's slip or normal velocity flipping sign every step, custom_sim/chatter.py; docs/stability.md), "
        f"and the energy, read where "
        f"the contact energy is under {QUIET_CONTACT_SHARE:.0%} of the motion's energy, never more than "
        f"{ENERGY_GROWTH_LIMIT:.0%} of the motion's largest kinetic energy above its start. The exact motion "
        f"only loses energy (damping, friction and rolling resistance all dissipate), so growth is numerical.",
        "",
        "## What is the cheapest way to reach 1 mm here?",
        "",
        "The step size with the fewest force evaluations whose max COM position error over the whole run is "
        "within 1 mm, and stays within it at every finer step on the ladder (a fixed step's error jumps about "
        "as the contact switches fall at different places inside a step; one lucky step size is not an "
        "answer). Force evaluations are counted, so the answer does not move with the machine's load; the "
        "CPU time stands beside them with the spread of its repeats, and a time is called faster only when "
        "it differs by more than that spread.",
        "",
        cheapest_table(results),
        "",
    ]
    for sweep in results:
        lines.append(f"- **{sweep.scene.name}**: {answer(sweep)}")
    lines += stability_section(results)
    for sweep in results:
        lines += scene_section(sweep)
    path.write_text("\n".join(lines) + "\n")
    return path


def scene_section(sweep) -> list[str]:
    """A scene's section: its reference, MuJoCo's converged solution, R(end), its answer, every run."""
    ref = sweep.reference
    s = sweep.scene
    conv = sweep.mujoco_converged
    lines = [f"## {s.name}", "", f"{s.description}", "",
             f"![work-precision diagram of {s.name}]({s.name}_workprecision.png)", "",
             f"- Reference: {ref['method']} at rtol = atol = {ref['rtol']:g}, {ref['segments']} smooth pieces "
             f"({', '.join(f'{v} {k}' for k, v in ref['switches'].items() if v)} switches), "
             f"{ref['nfev']} evaluations, {ref['solve_time']:.2f} s. Converged: a 100-fold tighter tolerance "
             f"moves it by {ref['change_at_tighter_tolerance']:.2g} m at most.",
             f"- Error amplification: raising the start by 1e-7 m moves the motion by up to "
             f"{ref['amplification']:.3g} x 1e-7 m (largest at t = {ref['amplification_time']:.3g} s)."]
    if conv:
        lines.append(f"- MuJoCo's converged solution ({conv['integrator']} at dt = {conv['dt']:g} s) moves by "
                     f"{conv['change_at_double_step']:.2g} m when the step doubles, and lies "
                     f"{conv['error_max']:.3g} m (max; RMS {conv['error_l2']:.3g} m) from our reference: "
                     f"the model difference.")
    lines += ["", "**Energy the numerics made or lost** (R(end) = E(end) - E(0) + W, docs/energy-balance.md):", "",
              *residual_rows(sweep)]
    lines += ["", f"**Cheapest way to 1 mm:** {answer(sweep)}", ""]
    lines += yours_section(sweep)
    rows = [[r.simulator, r.integrator, f"{r.dt:g}", *map(num, (r.error_max, r.error_l2, r.angle_error_max,
                                                                  r.error_max_self, r.residual_end, r.cpu_time,
                                                                  r.wall_time)),
             DASH if r.force_evals is None else str(r.force_evals), "" if r.stable else "unstable: " + r.note]
            for r in sweep.runs]
    lines += markdown(["simulator", "integrator", "dt (s)", "max error (m)", "RMS error (m)", "max angle error (rad)",
                       "MuJoCo vs own converged, max (m)", "R(end) (J)", "CPU time (s)", "wall time (s)",
                       "force evaluations", "note"], rows).splitlines()
    lines.append("")
    return lines

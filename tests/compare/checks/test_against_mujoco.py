"""custom_sim against its MuJoCo twin on every built-in scenario, the way `run` judges it.

With every effect on, the two differ by named models (friction law, mid-penetration contact
point, damping law, the mapping): that comparison is shown with its attribution, each cause's
share measured, and judged by no upper bound. What is judged is check `contact`: MuJoCo's own
contact with friction off and the linear law, against the mapping's measured force error and
the motion's sensitivity to it, never more than a tenth of the motion.
"""
import math

import pytest

from compare.scenarios import builtin_paths, load
from compare.checks.result import metrics_json
from compare.run.scenario import run_scenario
from compare.checks.contact_check import MOTION_SHARE


SLOW = ("t_shape_drop", "spinning_box")   # the two longest: CI's step for slow checks


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.stem in SLOW else p
                                  for p in builtin_paths()], ids=lambda p: p.stem)
def test_builtin_scenario_agrees_with_mujoco(path):
    scene = load(str(path))
    assert scene.mujoco.solref == "penalty"
    result = run_scenario(scene)
    assert result.error is None, result.error
    assert result.passed
    contact = next(c for c in result.checks if c.name == "contact")
    assert contact.passed is True, contact.reason
    assert contact.position_error_max <= contact.tolerance_position <= MOTION_SHARE * contact.details["motion_position"]
    if contact.tolerance_angle is not None:
        assert contact.angle_error_max <= contact.tolerance_angle <= MOTION_SHARE * contact.details["motion_angle"]
    # the full comparison: shown, not judged, and fully attributed
    native = next(c for c in result.checks if c.name == "native")
    assert native.passed is None and native.position_error_max == result.metrics["position_error_max"]
    ladder = result.attribution
    assert all(r["measured"] for r in ladder), [r["note"] for r in ladder]
    assert ladder[0]["position_error_max"] == pytest.approx(result.metrics["position_error_max"], rel=1e-9, abs=1e-15)
    assert ladder[-1]["position_error_max"] == 0.0
    shares = sum(r["share_position"] for r in ladder[1:])
    assert shares == pytest.approx(ladder[0]["position_error_max"], rel=1e-9, abs=1e-15)
    data = metrics_json(result)
    assert {"step", "dynamics", "contact", "native"} <= {c["name"] for c in data["checks"]}
    assert all(math.isfinite(v) for r in data["attribution"] for v in r.values() if isinstance(v, float))

"""--sim-process: a simulator in any language over stdin/stdout (docs/process-protocol.md).

The worked examples (examples/process/step.c built with cc, step.js run by node) are held to
the harness's checks on short scenes; the buggy C copy is named by the diagnosis; each way a
process can fail (it dies, hangs, prints something else, answers the wrong count, cannot be
started) is one line naming the request and what came back, and leaves no process running.
The faulty processes are small Python scripts (the interpreter running these tests).
"""
import dataclasses
import json
import os
import pickle
import shlex
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from compare.cli import main
from compare.scenarios import load
from compare.usersim import UserCodeError, UserFault, load_simulator, preflight, run_user
from compare.usersim.process import ANSWER, Process
from compare.usersim.scene_dict import scene_dict

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples" / "process"
PY = shlex.quote(sys.executable)


def _build(tmp_path_factory, source: str) -> str:
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler: `cc` is not on PATH (the C examples are built with it)")
    out = tmp_path_factory.mktemp("c") / Path(source).stem
    subprocess.run([cc, "-O2", "-o", str(out), str(EXAMPLES / source), "-lm"], check=True)
    return str(out)


@pytest.fixture(scope="module")
def step_c(tmp_path_factory):
    return _build(tmp_path_factory, "step.c")


@pytest.fixture(scope="module")
def buggy_c(tmp_path_factory):
    return _build(tmp_path_factory, "buggy_step.c")


@pytest.fixture(scope="module")
def step_js():
    node = shutil.which("node")
    if node is None:
        pytest.skip("no JavaScript runtime: `node` is not on PATH (examples/process/step.js runs on it)")
    return f"{shlex.quote(node)} {shlex.quote(str(EXAMPLES / 'step.js'))}"


def short_file(tmp_path, builtin: str, duration: float) -> str:
    text = (ROOT / "scenarios" / f"{builtin}.toml").read_text()
    text = "\n".join(f"duration = {duration}" if line.startswith("duration") else line for line in text.splitlines())
    path = tmp_path / f"{builtin}.toml"
    path.write_text(text)
    return str(path)


def gone(pid: int) -> bool:
    """The process has exited and been reaped (no zombie left behind)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


# --- the worked examples ---------------------------------------------------------------------

def test_the_c_example_passes_validate_with_its_diagnosis_probes(step_c, tmp_path, capsys):
    scene = short_file(tmp_path, "box_drop", 0.4)
    assert main(["validate", "--sim-process", step_c, scene]) == 0
    out = capsys.readouterr().out
    assert "pass" in out and "FAIL" not in out
    assert "every step agrees with the reference step to round-off" in out


def test_the_js_example_passes_validate(step_js, tmp_path, capsys):
    scene = short_file(tmp_path, "spinning_box", 0.3)   # RK4
    assert main(["validate", "--sim-process", step_js, scene]) == 0
    out = capsys.readouterr().out
    assert "FAIL" not in out and "every step agrees with the reference step to round-off" in out


def test_the_buggy_c_copy_is_named_by_the_diagnosis(buggy_c, tmp_path, capsys):
    scene = short_file(tmp_path, "box_drop", 0.4)
    assert main(["validate", "--sim-process", buggy_c, scene]) == 1
    out = capsys.readouterr().out
    assert "explained by friction_on_com_velocity" in out and "box_inertia_about_corner" in out


def test_identify_probes_the_c_example_and_finds_the_scene_law(step_c, tmp_path, capsys):
    scene = short_file(tmp_path, "rolling_circle", 0.2)
    assert main(["identify", "--sim-process", step_c, scene, "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["normal"]["law"] == "compression" and result["normal"]["k"] == pytest.approx(1e4, rel=1e-9)
    assert result["friction"]["law"] == "tanh" and result["friction"]["mu"] == pytest.approx(0.3, rel=1e-9)
    assert result["rolling"]["law"] == "tanh"
    assert all(result["matches_scene"].values())


def test_the_c_example_is_identical_to_the_python_example_step_for_step(step_c):
    """The same algorithm in C and in Python (examples/seed_sim.py): the same doubles, every step
    (the states cross the pipe exactly)."""
    scene = dataclasses.replace(load("t_shape_drop"), duration=0.4)
    ours = load_simulator(str(ROOT / "examples" / "seed_sim.py") + ":step").run(scene).states
    theirs = Process(step_c).run(scene).states
    assert np.array_equal(ours, theirs)


@pytest.mark.slow
def test_run_takes_sim_process_and_judges_every_check(step_c, tmp_path, capsys):
    scene = short_file(tmp_path, "point_drop", 0.3)
    assert main(["run", scene, "--sim-process", step_c, "--out", str(tmp_path / "out"), "--jobs", "1"]) == 0
    metrics = json.loads((tmp_path / "out" / "point_drop" / "metrics.json").read_text())
    assert metrics["pass"] and all(c["pass"] is not False for c in metrics["checks"])


def test_sim_process_and_sim_are_one_or_the_other(step_c, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--sim", "examples/seed_sim.py:step", "--sim-process", step_c])
    assert exc.value.code == 2


# --- the protocol ------------------------------------------------------------------------------

RECORDER = """
import sys
log = open(sys.argv[1], "a")
for line in sys.stdin:
    log.write(line)
    log.flush()
    if line.startswith("scene "):
        print("ready scene", flush=True)
    else:
        print(*line.split()[2:], flush=True)     # the state back, as it came
"""


def script(tmp_path, text: str, name: str = "sim.py") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_states_cross_the_pipe_exactly_and_a_second_scene_is_a_second_scene_line(tmp_path):
    log = tmp_path / "log.txt"
    sim = Process(f"{PY} {script(tmp_path, RECORDER)} {log}")
    rng = np.random.default_rng(3)
    first, second = load("point_drop"), load("box_slide")
    states = [rng.normal(size=6) * 10.0 ** rng.integers(-300, 300, size=6), np.array([0.1 + 0.2, -0.0, 5e-324, 1.0, 2.0, 3.0])]
    sd1, sd2 = scene_dict(first), scene_dict(second)
    for z in states:
        out = sim.function(z, sd1, first.dt)
        assert np.array_equal(np.array(out), z) and np.signbit(out[1]) == np.signbit(z[1])
    sim.function(states[0], sd2, second.dt)
    pid = sim._holder[0].proc.pid
    sim.close()
    lines = log.read_text().splitlines()
    assert [w.split(" ", 1)[0] for w in lines] == ["scene", "step", "step", "scene", "step"]
    assert json.loads(lines[0][6:]) == json.loads(json.dumps(sd1)) and json.loads(lines[3][6:])["name"] == "box_slide"
    assert [float(w) for w in lines[2].split()[1:]] == [first.dt, *states[1].tolist()]
    assert gone(pid)


def test_a_process_can_be_sent_to_another_python_process():
    sim = Process(f"{PY} -c pass", timeout=3.0)
    copy = pickle.loads(pickle.dumps(sim))
    assert isinstance(copy, Process) and copy.command == sim.command and copy.timeout == 3.0


def test_ready_names_the_integrator_and_a_misspelled_one_is_bad_input(tmp_path):
    ready = script(tmp_path, """
        import sys
        for line in sys.stdin:
            print("ready rk4" if "point_drop" in line else "ready semi-implicit", flush=True)
    """)
    sim = Process(f"{PY} {ready}")
    assert sim.integrator_for(load("point_drop")) == "rk4"
    with pytest.raises(UserCodeError, match="'semi-implicit': not an integrator the harness knows .* the closest "
                                            "is 'semi_implicit_euler'"):
        sim.integrator_for(load("box_drop"))
    sim.close()


def test_a_skipped_scene_raises_not_implemented_with_the_reason(tmp_path):
    """`skip REASON`: the step raises NotImplementedError(REASON), the signal of a scene the code
    does not do (the scene's row names the reason)."""
    skip = script(tmp_path, """
        import sys
        for line in sys.stdin:
            print("skip boxes only", flush=True)
    """)
    sim = Process(f"{PY} {skip}")
    scene = load("point_drop")
    assert sim.integrator_for(scene) == scene.integrator
    with pytest.raises(NotImplementedError, match="^boxes only$"):
        sim.function(np.zeros(6), scene_dict(scene), scene.dt)
    with pytest.raises(UserFault, match="NotImplementedError: boxes only"):
        sim.run(dataclasses.replace(scene, duration=0.01))
    sim.close()


# --- each way a process fails: one line, the request named, no process left -------------------

FAULTY = """
import os, sys, time
open(sys.argv[1], "w").write(str(os.getpid()))
steps = 0
for line in sys.stdin:
    if line.startswith("scene "):
        print({ready!r}, flush=True)
        continue
    steps += 1
    if steps < 3:
        print(*line.split()[2:], flush=True)
        continue
    {fault}
"""


@pytest.fixture(scope="module")
def scene():
    return dataclasses.replace(load("point_drop"), duration=0.01)


def faulty(tmp_path, fault: str, ready: str = "ready scene", timeout: float = 10.0):
    pidfile = tmp_path / "pid"
    path = script(tmp_path, FAULTY.format(fault=fault, ready=ready))
    command = f"{PY} {path} {pidfile}"
    return Process(command, timeout=timeout, start_timeout=timeout), command, pidfile


def third_request(scene) -> str:
    """The third step request: the script answers the first two with the state it was given."""
    return "step " + " ".join(repr(float(v)) for v in [scene.dt, *scene_dict(scene)["state0"]])


@pytest.mark.parametrize("fault, problem", [
    ("sys.stderr.write('out of cheese\\n'); sys.exit(3)",
     "no answer, the process ended (it exited with status 3; its last line on stderr: 'out of cheese')"),
    ("os.kill(os.getpid(), 9)", "no answer, the process ended (it was killed by SIGKILL)"),
    ("time.sleep(60)", "no answer within 0.5 s (the process was killed)"),
    ("print('hello', flush=True)", f"answered 'hello' (expected {ANSWER})"),
    ("print('1 2 3 4 5', flush=True)", f"answered 5 numbers '1 2 3 4 5' (expected {ANSWER})"),
    ("print('1 2 3 4 5 6 7', flush=True)", f"answered 7 numbers '1 2 3 4 5 6 7' (expected {ANSWER})"),
    ("print('1 2 3 4 5 x', flush=True)", f"answered '1 2 3 4 5 x' (expected {ANSWER})"),
    ("print(flush=True)", f"answered an empty line (expected {ANSWER})"),
], ids=["dies", "killed", "hangs", "garbage", "five", "seven", "not_a_number", "empty"])
def test_a_failing_process_is_one_line_naming_the_request_and_is_ended(tmp_path, scene, fault, problem):
    sim, command, pidfile = faulty(tmp_path, fault, timeout=0.5)
    with pytest.raises(UserFault) as exc:
        run_user(sim, scene)
    assert str(exc.value) == (f"--sim-process {command!r}: request `{third_request(scene)}` "
                              f"(step 3 of scene point_drop): {problem}")
    assert gone(int(pidfile.read_text()))


def test_a_process_that_does_not_answer_the_scene_line_is_the_scene_error_row(tmp_path, scene, capsys):
    sim, command, pidfile = faulty(tmp_path, "pass", ready="hello there")
    preflight(sim, [scene])
    with pytest.raises(UserFault) as exc:
        run_user(sim, scene)
    assert str(exc.value) == (f"--sim-process {command!r}: request `scene {{...}}` (scene point_drop): "
                              "answered 'hello there' (expected `ready INTEGRATOR` or `skip REASON`)")
    assert gone(int(pidfile.read_text()))


def test_validate_prints_a_failing_process_as_that_scene_s_error_line(tmp_path, capsys):
    path = script(tmp_path, FAULTY.format(fault="print('oops', flush=True)", ready="ready scene").replace(
        "open(sys.argv[1], \"w\").write(str(os.getpid()))", ""))
    scene = short_file(tmp_path, "point_drop", 0.01)
    command = f"{PY} {path}"
    assert main(["validate", "--sim-process", command, scene]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[1] == (f"point_drop       error: --sim-process {command!r}: request `{third_request(load(scene))}` "
                      f"(step 3 of scene point_drop): answered 'oops' (expected {ANSWER})")


@pytest.mark.parametrize("command, message", [
    ("/no/such/folder/sim", "--sim-process '/no/such/folder/sim': cannot start /no/such/folder/sim: no such file "
                            "(expected a program to run)"),
    ("no_such_program_q7", "--sim-process 'no_such_program_q7': cannot start no_such_program_q7: no such program "
                           "on PATH (expected a program on PATH, or a path to one such as ./step)"),
    ("'unbalanced", "--sim-process \"'unbalanced\": cannot read the command (No closing quotation); expected a "
                    "command line, e.g. \"./step\" or \"node step.js\""),
])
def test_a_command_that_cannot_start_is_bad_input_in_one_line(command, message, capsys):
    assert main(["validate", "--sim-process", command, "point_drop"]) == 2
    assert capsys.readouterr().err.strip() == f"error: {message}"


def test_a_program_in_this_folder_named_without_its_path_is_pointed_to(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mystep").write_text("")
    assert main(["validate", "--sim-process", "mystep", "point_drop"]) == 2
    assert capsys.readouterr().err.strip() == ("error: --sim-process 'mystep': cannot start mystep: no such program "
                                               "on PATH (this folder's file is ./mystep)")


def test_a_file_that_is_not_executable_is_bad_input(tmp_path, capsys):
    path = script(tmp_path, "print('hi')")
    assert main(["identify", "--sim-process", str(path), "point_drop"]) == 2
    assert capsys.readouterr().err.strip() == (f"error: --sim-process {str(path)!r}: cannot start {path}: not "
                                               f"executable (chmod +x {path}?)")


def test_a_process_left_after_the_diagnosis_probes_is_ended_when_dropped(step_c, scene):
    sim = Process(step_c)
    sim.call(scene_dict(scene)["state0"], scene_dict(scene), scene.dt)
    pid = sim._holder[0].proc.pid
    assert not gone(pid)
    del sim
    assert gone(pid)


def test_a_fork_of_the_harness_starts_its_own_process_and_leaves_the_parent_s(step_c, scene):
    """run forks one copy of the harness per scene after the preflight has started a process: the
    copy must start its own, and the parent's must go on answering."""
    sim = Process(step_c)
    sd = scene_dict(scene)
    z = np.array(sd["state0"])
    first = sim.function(z, sd, scene.dt)
    parent = sim._holder[0].proc.pid
    child = os.fork()
    if child == 0:   # the copy: its own process, the same answer, then its process ended
        ok = sim.function(z, sd, scene.dt) == first and sim._holder[0].proc.pid != parent
        sim.close()
        os._exit(0 if ok else 1)
    _, status = os.waitpid(child, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    assert sim.function(z, sd, scene.dt) == first and sim._holder[0].proc.pid == parent
    sim.close()
    assert gone(parent)


def test_tools_overhead_shows_a_process_round_trip_beside_the_python_call(step_c, capsys):
    from compare.usersim.overhead import print_round_trip
    scene = dataclasses.replace(load("box_drop"), duration=0.05)   # 1000 steps
    trip = print_round_trip(scene)
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("no-op process (C) through --sim-process: ") and " us/step round trip (CPU: harness " in out[0]
    assert out[1].startswith("examples/process/step.c on box_drop (semi_implicit_euler), 1000 steps: ")
    assert 0.0 < trip < 1e-2


def test_identify_names_the_probe_and_the_process_s_line_in_one_line(tmp_path, capsys):
    garbled = script(tmp_path, """
        import sys
        for line in sys.stdin:
            print("ready scene" if line.startswith("scene ") else "hello", flush=True)
    """)
    command = f"{PY} {garbled}"
    assert main(["identify", "--sim-process", command, "point_drop"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert err.startswith(f"error: {command} called by identify (")
    assert err.endswith(f": --sim-process {command!r}: request `{err.split('request `')[1].split('`')[0]}` "
                        f"(step 1 of scene point_drop): answered 'hello' (expected {ANSWER})")


def test_the_first_answer_may_take_the_start_timeout_the_others_the_reply_timeout(tmp_path, scene):
    slow_start = script(tmp_path, """
        import sys, time
        time.sleep(0.6)   # an interpreter loading
        for line in sys.stdin:
            print("ready scene" if line.startswith("scene ") else " ".join(line.split()[2:]), flush=True)
    """)
    sim = Process(f"{PY} {slow_start}", timeout=0.3, start_timeout=5.0)
    assert run_user(sim, scene).states().shape == (scene.steps + 1, 6)

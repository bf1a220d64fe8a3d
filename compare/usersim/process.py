"""A simulator in any language as a step function: a process spoken to one line each way (protocol 1).

    --sim-process "COMMAND"      Process(COMMAND)      docs/process-protocol.md

    harness -> process:  scene {JSON of the scene, as `scene --json` prints it, on one line}
    process -> harness:  ready INTEGRATOR     (a name the harness knows, "other:NAME", or "scene")
                     or  skip REASON          (a scene this code does not do)
    harness -> process:  step DT X Y THETA VX VY OMEGA
    process -> harness:  X Y THETA VX VY OMEGA
    ... (another `scene` line may follow; at the end the harness closes stdin and the process exits)

Numbers travel as Python's repr of a float (the shortest text that reads back to the same
double, at most 17 significant digits), so a state crosses the pipe exactly.

Process is a StepFunction: the harness's run loop, its checks, identify's designed probes, the
diagnosis's probes and the purity test call `function(state, scene, dt)` as they call a Python
step. `fresh()` ends the process (the next call starts a new one, as a Python module is
imported again); a scene the process has not been told sends a `scene` line first. A process
that dies, hangs (REPLY_TIMEOUT), prints anything but the answer or answers the wrong count is
a ProcessFault (that scene's error row) naming the request and what came back; the process is
ended (its process group killed) whenever it fails and at the end of every run.
"""
from __future__ import annotations

import hashlib
import json
import os
import select
import shlex
import shutil
import signal
import subprocess
import tempfile
import time
import weakref
from dataclasses import dataclass

import numpy as np

from custom_sim import Scene

from .base import declared_integrator
from .errors import UserCodeError, UserFault
from .functions import StepFunction
from .scene_dict import scene_dict

PROTOCOL = 1
# A reply must come within this many seconds of its request (s); the first reply of a process,
# its `ready`, within START_TIMEOUT (an interpreter or a JIT loading before it reads a line).
REPLY_TIMEOUT = 10.0
START_TIMEOUT = 30.0
# After stdin is closed a process has this long to exit before it is killed (s).
EXIT_GRACE = 1.0
# What is quoted of a line that came back, at most (characters).
QUOTE = 120
ANSWER = "6 numbers X Y THETA VX VY OMEGA"
# A step request: %r of a float is its repr, the shortest text that reads back to the same double
# (bytes formatted directly: half the time of a str then encoded).
_REQUEST = b"step %r %r %r %r %r %r %r\n"


class ProcessFault(UserFault):
    """The process died, hung, printed something else or answered the wrong count: one line."""


def _quote(data: bytes) -> str:
    text = data.decode("utf-8", "replace").rstrip("\r")
    return repr(text if len(text) <= QUOTE else text[:QUOTE] + "...")


def _argv(command: str) -> list[str]:
    """The command's words, its program found (bad input, one line, where it cannot be)."""
    where = f"--sim-process {command!r}"
    try:
        argv = shlex.split(command)
    except ValueError as exc:
        raise UserCodeError(f"{where}: cannot read the command ({exc}); expected a command line, "
                            "e.g. \"./step\" or \"node step.js\"") from None
    if not argv:
        raise UserCodeError(f"{where}: empty command (expected the command that starts your simulator, "
                            "e.g. \"./step\" or \"node step.js\")")
    program = argv[0]
    if os.sep in program or (os.altsep and os.altsep in program):
        if not os.path.isfile(program):
            raise UserCodeError(f"{where}: cannot start {program}: no such file (expected a program to run)")
        if not os.access(program, os.X_OK):
            raise UserCodeError(f"{where}: cannot start {program}: not executable (chmod +x {program}?)")
    elif shutil.which(program) is None:
        hint = (f"this folder's file is ./{program}" if os.path.isfile(program)
                else "expected a program on PATH, or a path to one such as ./step")
        raise UserCodeError(f"{where}: cannot start {program}: no such program on PATH ({hint})")
    return argv


class _Pipe:
    """One running process: a request written, its reply line read, within a timeout."""

    def __init__(self, argv: list[str], where: str):
        self.stderr = tempfile.TemporaryFile()
        try:
            self.proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.stderr,
                                         bufsize=0, process_group=0)
        except OSError as exc:
            self.stderr.close()
            raise UserCodeError(f"{where}: cannot start {argv[0]}: {exc.strerror or exc}") from None
        assert self.proc.stdin is not None and self.proc.stdout is not None   # both piped above
        self.fd_in, self.fd_out = self.proc.stdin.fileno(), self.proc.stdout.fileno()
        self.poller = select.poll()
        self.poller.register(self.fd_out, select.POLLIN)
        self.buffer = bytearray()
        self.owner = os.getpid()             # a forked copy of the harness (run's scenes) must not use it
        self.first = True                    # no answer yet: the first may take START_TIMEOUT

    def ask(self, line: bytes, timeout: float) -> bytes:
        """The reply line (without its newline) to `line`; raises EOFError when the process has
        closed its output (it exited), TimeoutError when no whole line came in time."""
        try:
            os.write(self.fd_in, line)
        except (BrokenPipeError, ConnectionResetError):
            raise EOFError from None
        if not self.buffer:                  # the usual case: one whole line, read at once
            if not self.poller.poll(max(1, int(timeout * 1000))):
                raise TimeoutError
            chunk = os.read(self.fd_out, 65536)
            if chunk.find(b"\n") == len(chunk) - 1 and chunk:
                return chunk[:-1]
            if not chunk:
                raise EOFError
            self.buffer += chunk
        return self.reply(timeout)

    def reply(self, timeout: float) -> bytes:
        buffer = self.buffer
        deadline = None
        while True:
            end = buffer.find(b"\n")
            if end >= 0:
                line = bytes(buffer[:end])
                del buffer[:end + 1]
                return line
            if deadline is None:
                deadline = time.monotonic() + timeout
            left = deadline - time.monotonic()
            if left <= 0 or not self.poller.poll(max(1, int(left * 1000))):
                raise TimeoutError
            chunk = os.read(self.fd_out, 65536)
            if not chunk:
                raise EOFError
            buffer += chunk

    def exit_text(self) -> str:
        """How the process ended (it has, or is made to within EXIT_GRACE), and its last line on stderr."""
        try:
            code = self.proc.wait(EXIT_GRACE)
        except subprocess.TimeoutExpired:
            self.kill()
            return "it closed its output but did not exit (it was killed)"
        if code < 0:
            try:
                name = signal.Signals(-code).name
            except ValueError:
                name = f"signal {-code}"
            how = f"it was killed by {name}"
        else:
            how = f"it exited with status {code}"
        self.stderr.seek(0)
        lines = [line for line in self.stderr.read()[-4096:].splitlines() if line.strip()]
        return how + (f"; its last line on stderr: {_quote(lines[-1])}" if lines else "")

    def kill(self) -> None:
        """End the process and every process it started (its process group), and reap it."""
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        self.proc.wait()

    def close(self) -> None:
        """Close stdin (the end of the session), give the process EXIT_GRACE to exit, else kill it.
        In a forked copy of the harness only its copies of the pipes are closed: the process is
        the parent's."""
        for stream in (self.proc.stdin, self.proc.stdout):
            try:
                if stream is not None:
                    stream.close()
            except OSError:
                pass
        if self.owner != os.getpid():
            return
        try:
            self.proc.wait(EXIT_GRACE)
        except subprocess.TimeoutExpired:
            pass
        self.kill()
        self.stderr.close()


def _end(pipe_holder: list) -> None:
    """weakref.finalize's hook: a Process dropped (or the interpreter leaving) ends its process."""
    if pipe_holder and pipe_holder[0] is not None:
        pipe_holder[0].close()
        pipe_holder[0] = None


_LIVE: weakref.WeakSet = weakref.WeakSet()   # every Process of this interpreter


def _forked() -> None:
    """In a fork of the harness (run forks one per scene): each Process forgets the parent's
    process (its copies of the pipes closed), so the next call starts its own."""
    for sim in list(_LIVE):
        sim.close()


os.register_at_fork(after_in_child=_forked)


class Process(StepFunction):
    """COMMAND run as a step function speaking protocol 1 on stdin/stdout (see the module)."""

    kind = "step"
    signature = "a process answering `step DT X Y THETA VX VY OMEGA` with 6 numbers (docs/process-protocol.md)"

    def __init__(self, command: str, timeout: float = REPLY_TIMEOUT, start_timeout: float = START_TIMEOUT):
        self.command = self.spec = self.label = command
        self.timeout, self.start_timeout = float(timeout), float(start_timeout)
        self.where = f"--sim-process {command!r}"
        self.argv = _argv(command)
        self._holder: list[_Pipe | None] = [None]   # the running _Pipe (a list: the finalizer holds it, not self)
        self._finalizer = weakref.finalize(self, _end, self._holder)
        self._answers: dict[str, tuple] = {}  # scene JSON -> ("ready", integrator) | ("skip", reason)
        self._told: str | None = None         # the scene JSON the running process was told last
        self._told_dict: dict | None = None   # ... and the dict it came from (compared by identity first)
        self._steps = 0                       # step requests since that scene line
        self._skip: str | None = None         # the reason, when the process skips the scene it was told
        _LIVE.add(self)

    @property
    def function(self):
        """step(state, scene, dt) -> state, as the harness calls a Python step (a property, not an
        attribute: a bound method kept on self would keep self alive past its last use)."""
        return self._step

    def __reduce__(self):  # another process starts its own
        return (type(self), (self.command, self.timeout, self.start_timeout))

    def fresh(self) -> None:
        """End the running process: the next call starts a new one (a fresh state, as a Python
        module imported again)."""
        self.close()

    def close(self) -> None:
        """Close stdin, let the process exit (or kill it)."""
        _end(self._holder)
        self._told = self._told_dict = self._skip = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _run(self, scene: Scene):
        try:
            return super()._run(scene)
        except UserFault as exc:   # no frame of a process is Python: the traceback would be the harness's
            exc.details = ""
            raise
        finally:
            self.close()

    # -- the protocol --------------------------------------------------------------------------

    def _pipe(self):
        pipe = self._holder[0]
        if pipe is not None and pipe.owner != os.getpid():   # inherited by a fork: the parent's to end
            self.close()
            pipe = None
        if pipe is None:
            pipe = self._holder[0] = _Pipe(self.argv, self.where)
            self._told = self._told_dict = None
        return pipe

    def _fault(self, request: str, context: str, problem: str) -> ProcessFault:
        """The process is ended; the one line naming the request and what came back."""
        self.close()
        return ProcessFault(f"{self.where}: request `{request}`{context}: {problem}")

    def _exchange(self, request: str, context: str, timeout: float) -> bytes:
        pipe = self._pipe()
        try:
            return pipe.ask(request.encode() + b"\n", timeout)
        except (EOFError, TimeoutError) as exc:
            raise self._lost(pipe, exc, request, context, timeout) from None

    def _lost(self, pipe, exc, request: str, context: str, timeout: float) -> ProcessFault:
        """The fault for a request that got no answer (the process ended, or it timed out)."""
        if isinstance(exc, EOFError):
            return self._fault(_short(request), context, f"no answer, the process ended ({pipe.exit_text()})")
        pipe.kill()
        return self._fault(_short(request), context, f"no answer within {timeout:g} s (the process was killed)")

    def _tell(self, sd: dict, text: str) -> tuple:
        """Send the scene line; the answer ("ready", integrator) or ("skip", reason). A misnamed
        integrator is bad input (as a Python module's INTEGRATOR); a fault is a ProcessFault."""
        context = f" (scene {sd.get('name', '?')})"
        pipe = self._pipe()
        line = self._exchange(f"scene {text}", context, self.start_timeout if pipe.first else self.timeout)
        pipe.first = False
        word, _, rest = line.decode("utf-8", "replace").strip().partition(" ")
        rest = rest.strip()
        if word == "ready" and rest:
            answer = ("ready", rest)
        elif word == "skip":
            answer = ("skip", rest or "no reason given")
        else:
            raise self._fault("scene {...}", context,
                              f"answered {_quote(line)} (expected `ready INTEGRATOR` or `skip REASON`)")
        self._answers[text] = answer
        self._told, self._told_dict, self._steps = text, sd, 0
        self._skip = answer[1] if answer[0] == "skip" else None
        if answer[0] == "ready" and answer[1] != "scene":
            declared_integrator(answer[1], f"{self.where}: ready", sd.get("integrator", ""))
        return answer

    def _step(self, state, sd: dict, dt: float) -> list:
        """One step request; the 6 numbers answered (a list of floats). The hot path: one write,
        one poll, one read."""
        pipe = self._holder[0]
        if sd is not self._told_dict or pipe is None:
            pipe = self._pipe()
            text = json.dumps(sd, separators=(",", ":"))
            if text != self._told:
                self._tell(sd, text)
            self._told_dict, pipe = sd, self._holder[0]
        assert pipe is not None   # started by _pipe() above
        if self._skip is not None:
            raise NotImplementedError(self._skip)
        self._steps += 1
        z = state.tolist() if state.__class__ is np.ndarray else [float(v) for v in state]
        request = _REQUEST % (float(dt), *z)
        try:
            line = pipe.ask(request, self.timeout)
        except (EOFError, TimeoutError) as exc:
            raise self._lost(pipe, exc, request[:-1].decode(), self._context(sd), self.timeout) from None
        words = line.split()
        if len(words) == 6:
            try:
                return list(map(float, words))
            except ValueError:
                pass
            problem = f"answered {_quote(line)}"
        elif not words:
            problem = "answered an empty line"
        elif all(_number(w) for w in words):
            problem = f"answered {len(words)} number{'s' if len(words) != 1 else ''} {_quote(line)}"
        else:
            problem = f"answered {_quote(line)}"
        raise self._fault(request[:-1].decode(), self._context(sd), f"{problem} (expected {ANSWER})")

    def _context(self, sd: dict) -> str:
        return f" (step {self._steps} of scene {sd.get('name', '?')})"

    def skip_reason(self, scene: Scene) -> str | None:
        """The reason the process gave in `skip REASON` for this scene, or None: asked once per
        scene, before any step (the handshake integrator_for makes)."""
        self.integrator_for(scene)
        answer = self._answers.get(json.dumps(scene_dict(scene), separators=(",", ":")))
        return answer[1] if answer is not None and answer[0] == "skip" else None

    def integrator_for(self, scene: Scene) -> str:
        """The integrator the process names in its `ready` for this scene (the scene's for
        "scene", or for a scene it skips or fails on: its run then says so)."""
        sd = scene_dict(scene)
        text = json.dumps(sd, separators=(",", ":"))
        answer = self._answers.get(text)
        if answer is None:
            try:
                answer = self._tell(sd, text)
            except ProcessFault as exc:
                answer = ("fault", str(exc))
        if answer[0] == "ready" and answer[1] != "scene":
            return declared_integrator(answer[1], f"{self.where}: ready", scene.integrator)
        return scene.integrator


def _number(word: bytes) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _short(request: str) -> str:
    return request if not request.startswith("scene ") else "scene {...}"


@dataclass(frozen=True)
class Command:
    """What a study sends its workers for --sim-process: the command, started where each task
    runs (the program must be there: a local cluster's workers share this machine). It answers
    as compare.usersim.bundle.Bundle does: spec, whole, function, files, digest, simulator()."""

    command: str
    whole: bool = False
    function: str = ""
    files: tuple = ()

    @property
    def spec(self) -> str:
        return f"--sim-process {self.command!r}"

    @property
    def digest(self) -> str:
        return hashlib.sha256(self.command.encode()).hexdigest()[:16]

    def simulator(self) -> Process:
        return Process(self.command)

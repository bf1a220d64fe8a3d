"""`study --sim` on a real Dask cluster: a scheduler and two workers started as separate processes
on 127.0.0.1, in a folder of their own, so the user's files are not where they look; and the same
over TLS, with a certificate made for the test.
"""
from __future__ import annotations

import datetime
import ipaddress
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from compare.tools.study import table  # noqa: E402

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("dask_cluster")]

ROOT = Path(__file__).resolve().parents[3]
START_TIMEOUT = 90.0   # s for the scheduler and both workers to be up on a busy 2-core machine

SCENE = """
duration = 0.2
dt = 1e-3
[body]
shape = "box"
mass = 1.0
size = [0.2, 0.1]
[initial]
position = [0.0, 10.0]
velocity = [0.5, 0.0]
"""
# The user's code: a module that imports a sibling, both only in the user's folder.
HELPER = "def drop(y, vy, g, dt):\n    return y + (vy - g * dt) * dt, vy - g * dt\n"
STEP = '''
from helper import drop

def step(state, scene, dt):
    x, y, th, vx, vy, om = state
    y, vy = drop(y, vy, scene["g"], dt)
    return [x + vx * dt, y, th + om * dt, vx, vy, om]
'''
# m: semi-implicit Euler on a parabola is within g dt t / 2 of it (0.2 s at dt = 1 ms, g = 9.81)
SIE_ERROR_BOUND = 9.81 * 1e-3 * 0.2 / 2


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _user_folder(tmp_path: Path) -> Path:
    user = tmp_path / "user"
    user.mkdir()
    (user / "helper.py").write_text(HELPER)
    (user / "my_sim.py").write_text(STEP)
    (user / "free_fall.toml").write_text(SCENE)
    return user


class Cluster:
    """`dask scheduler` and two `dask worker`s, each started in its own empty folder with only this
    checkout on PYTHONPATH; stopped (by their ids) on leaving."""

    def __init__(self, base: Path, tls: list[str] | None = None):
        self.base, self.tls, self.procs = base, tls or [], []
        self.protocol = "tls" if tls else "tcp"
        self.address = f"{self.protocol}://127.0.0.1:{_free_port()}"

    def _start(self, name: str, argv: list[str]) -> None:
        folder = self.base / name
        folder.mkdir(parents=True)
        env = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}
        env["PYTHONPATH"] = str(ROOT)
        log = open(folder / "log.txt", "w")
        self.procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_" + argv[0], *argv[1:]],
                                           cwd=folder, env=env, stdout=log, stderr=subprocess.STDOUT))

    def __enter__(self):
        port = self.address.rsplit(":", 1)[1]
        self._start("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", port, "--no-dashboard",
                                  "--protocol", self.protocol, *self.tls])
        for i in (1, 2):
            self._start(f"worker-{i}", ["worker", self.address, "--nthreads", "1", "--no-dashboard",
                                        "--host", "127.0.0.1", "--name", f"test-worker-{i}", *self.tls])
        return self

    def wait(self, env: dict) -> None:
        """Until both workers have joined (a client in a child process, with env's TLS settings)."""
        probe = ("import sys; from distributed import Client; c = Client(sys.argv[1], timeout=60); "
                 "c.wait_for_workers(2, timeout=60); print(sorted(c.run(lambda: __import__('os').getcwd()).values()))")
        out = subprocess.run([sys.executable, "-c", probe, self.address], env=env, capture_output=True, text=True,
                             timeout=START_TIMEOUT)
        assert out.returncode == 0, out.stderr[-2000:] + self.logs()
        return out.stdout

    def logs(self) -> str:
        return "".join(f"\n--- {p}\n" + p.read_text()[-1500:] for p in sorted(self.base.glob("*/log.txt")))

    def __exit__(self, *exc):
        for proc in self.procs:
            proc.terminate()
        for proc in self.procs:
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


def _study(user: Path, out: Path, address: str, env: dict) -> subprocess.CompletedProcess:
    """The user's study, started from the user's folder with a relative --sim (as a user would)."""
    return subprocess.run([sys.executable, "-m", "compare", "study", "free_fall.toml", "--vary", "body.mass=1,2",
                           "--integrators", "semi_implicit_euler", "--no-twin", "--sim", "my_sim.py:step",
                           "--scheduler", address, "--out", str(out)],
                          cwd=user, env=env, capture_output=True, text=True, timeout=600)


def _check_rows(out: Path, run) -> None:
    assert run.returncode == 0, run.stdout + run.stderr
    rows = table.read_csv(out / "study.csv")
    mine = [r for r in rows if r["simulator"] == "yours"]
    assert len(mine) == 2 and len(rows) == 4
    for r in mine:
        assert r["status"] == "ok", r["note"]
        assert 0 < float(r["position_error_max"]) <= SIE_ERROR_BOUND, r["position_error_max"]


def _env(**extra) -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}
    env["PYTHONPATH"] = str(ROOT)
    env.update(extra)
    return env


def test_the_users_module_and_its_sibling_reach_workers_that_cannot_see_them(tmp_path):
    user = _user_folder(tmp_path)
    with Cluster(tmp_path / "cluster") as cluster:
        cwds = cluster.wait(_env())
        assert str(user) not in cwds
        out = tmp_path / "study"
        _check_rows(out, _study(user, out, cluster.address, _env()))


def _certificate(folder: Path) -> tuple[Path, Path, Path]:
    """(CA certificate, certificate for 127.0.0.1 signed by it, its key), made now."""
    x509 = pytest.importorskip("cryptography.x509")
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    now = datetime.datetime.now(datetime.UTC)

    def cert(subject, key, issuer, issuer_key, ca: bool):
        builder = (x509.CertificateBuilder().subject_name(subject).issuer_name(issuer).public_key(key.public_key())
                   .serial_number(x509.random_serial_number()).not_valid_before(now - datetime.timedelta(minutes=5))
                   .not_valid_after(now + datetime.timedelta(days=1))
                   .add_extension(x509.BasicConstraints(ca=ca, path_length=None), critical=True))
        if not ca:
            builder = builder.add_extension(x509.SubjectAlternativeName(
                [x509.IPAddress(ipaddress.ip_address("127.0.0.1")), x509.DNSName("localhost")]), critical=False)
        return builder.sign(issuer_key, hashes.SHA256())

    ca_key, key = ec.generate_private_key(ec.SECP256R1()), ec.generate_private_key(ec.SECP256R1())
    ca_name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "study test CA")])
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "127.0.0.1")])
    ca = cert(ca_name, ca_key, ca_name, ca_key, True)
    leaf = cert(name, key, ca_name, ca_key, False)
    paths = folder / "ca.pem", folder / "cert.pem", folder / "key.pem"
    paths[0].write_bytes(ca.public_bytes(serialization.Encoding.PEM))
    paths[1].write_bytes(leaf.public_bytes(serialization.Encoding.PEM))
    paths[2].write_bytes(key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                           serialization.NoEncryption()))
    return paths


def test_a_study_through_a_tls_scheduler_with_dasks_own_settings(tmp_path):
    user = _user_folder(tmp_path)
    ca, cert, key = _certificate(tmp_path)
    tls = ["--tls-ca-file", str(ca), "--tls-cert", str(cert), "--tls-key", str(key)]
    settings = _env(DASK_DISTRIBUTED__COMM__TLS__CA_FILE=str(ca), DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT=str(cert),
                    DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY=str(key))
    with Cluster(tmp_path / "cluster", tls) as cluster:
        cluster.wait(settings)
        out = tmp_path / "study"
        _check_rows(out, _study(user, out, cluster.address, settings))
        # without the settings: one line naming them, exit 2, nothing written
        bare = _study(user, tmp_path / "bare", cluster.address, _env())
        assert bare.returncode == 2 and bare.stderr.count("\n") == 1, bare.stderr
        assert "no TLS settings" in bare.stderr and not (tmp_path / "bare").exists()
        # a client whose certificate no CA of the scheduler signed is refused, in one line
        (tmp_path / "other").mkdir()
        other = _certificate(tmp_path / "other")
        wrong = _env(DASK_DISTRIBUTED__COMM__TLS__CA_FILE=str(other[0]),
                     DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT=str(other[1]),
                     DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY=str(other[2]),
                     DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="5s")
        refused = _study(user, tmp_path / "refused", cluster.address, wrong)
        assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
        assert "Traceback" not in refused.stderr

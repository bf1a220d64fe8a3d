#!/usr/bin/env bash
# A study on a real Dask cluster: a scheduler and two workers started as separate processes on
# 127.0.0.1, each in a folder of its own; a small study through --scheduler, study.csv checked;
# then a study of a user's simulator (a module and the sibling it imports, in a folder the workers
# cannot see) run from that folder; the processes are always stopped. The same over TLS:
# tests/compare/executor/test_dask_cluster.py (pytest -m slow).
#   usage: .ci/study_cluster.sh            (from anywhere; 100 s on 2 cores shared with other jobs)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
WORK="$(mktemp -d)"
PORT="${STUDY_CI_PORT:-$(python -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}"
PIDS=()
cleanup() {
    for pid in "${PIDS[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
    rm -rf "$WORK"
}
trap cleanup EXIT
# the workers import this checkout's packages (the functions a task names are imported there)
export PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}"
dask scheduler --host 127.0.0.1 --port "$PORT" --no-dashboard >"$WORK/scheduler.log" 2>&1 &
PIDS+=($!)
for i in 1 2; do
    mkdir -p "$WORK/worker-$i"
    (cd "$WORK/worker-$i" && exec dask worker "tcp://127.0.0.1:$PORT" --nthreads 1 --nworkers 1 --no-dashboard \
        --host 127.0.0.1 --name "ci-worker-$i" --local-directory "$WORK/worker-$i") >"$WORK/worker-$i.log" 2>&1 &
    PIDS+=($!)
done
python - "$PORT" <<'PY'
import sys, time
from distributed import Client
client = Client(f"tcp://127.0.0.1:{sys.argv[1]}", timeout=30)
client.wait_for_workers(2, timeout=60)
print("cluster up:", len(client.scheduler_info()["workers"]), "workers")
PY
python -m compare study box_drop --vary contact.k=1e4,1e5 --vary dt=1e-4,1e-3 \
    --integrators semi_implicit_euler rk4 --scheduler "tcp://127.0.0.1:$PORT" --out "$WORK/study"
python - "$WORK/study/study.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
head = ["contact.k", "dt", "integrator", "stable", "position_error_max", "twin_position_error_max",
        "wall_time", "force_evals", "status"]
assert list(rows[0])[:len(head)] == head, list(rows[0])
assert len(rows) == 8, len(rows)
combos = {(r["contact.k"], r["dt"], r["integrator"]) for r in rows}
assert len(combos) == 8, "a run is missing or duplicated"
assert all(r["status"] in ("ok", "unstable") for r in rows), [r["note"] for r in rows]
ok = [r for r in rows if r["status"] == "ok"]
assert ok and all(float(r["position_error_max"]) >= 0 and int(r["force_evals"]) > 0 for r in ok)
print(f"study.csv: {len(rows)} rows, {len(ok)} ok")
PY
grep -q "cluster at tcp://127.0.0.1:$PORT" "$WORK/study/index.md"
echo "study on the cluster: passed"

# the user's simulator, only in a folder of the user's: a step that imports a sibling file
USER_DIR="$WORK/user"
mkdir -p "$USER_DIR"
echo 'INTEGRATOR = "rk4"' > "$USER_DIR/helper.py"
{ echo "from helper import INTEGRATOR"; cat examples/seed_sim.py; } > "$USER_DIR/my_sim.py"
(cd "$USER_DIR" && python -m compare study box_drop --vary contact.k=1e4,1e5 --integrators rk4 --no-twin \
    --sim my_sim.py:step --scheduler "tcp://127.0.0.1:$PORT" --out "$WORK/yours")
python - "$WORK/yours/study.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
mine = {r["contact.k"]: r for r in rows if r["simulator"] == "yours"}
ours = {r["contact.k"]: r for r in rows if r["simulator"] == "custom_sim"}
assert len(rows) == 4 and len(mine) == 2, rows
for k, r in mine.items():
    assert r["status"] == "ok" and r["integrator"] == "rk4", r["note"]
    # the seed's algorithm, the same integrator: the same error as custom_sim's to round-off (m)
    assert abs(float(r["position_error_max"]) - float(ours[k]["position_error_max"])) < 1e-9, (r, ours[k])
print(f"study.csv of yours: {len(mine)} runs ok, as custom_sim's")
PY
echo "study of a simulator the workers cannot see: passed"

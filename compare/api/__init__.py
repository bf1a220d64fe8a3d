"""The public Python API (docs/python-api.md): `compare.judge` and `compare.identify`, and the
frozen objects they return. `run` prints from the same objects.

    judge.py            judge(sim, scenes, law=, whole=, out=) -> Judgement; collect, run's pipeline
    judgement.py        Judgement: every scene's, passed, lines, diagnosis, exit status
    scene.py            SceneJudgement: one scene's status, checks, diagnosis and lines
    check.py            Check: one check's row (difference, tolerance, unit, reason)
    diagnosis.py        Diagnosis, Mistake: what explains a user's run
    status.py           Status: pass, FAIL, not judged, error, unstable, timeout, skipped
    identify.py         identify(sim, scenes) -> one Identification per scene
    identification.py   Identification, Effect: `identify --json` as objects
    subject.py          the simulator under test from "MODULE:FUNCTION", a function, or an object
"""

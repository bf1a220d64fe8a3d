"""`python -m compare run` around the checks: every scenario judged in a process of its own, the
report written whole, and the lines the command prints.

    config.py      RunConfig: the report's folder, jobs, timeout (s), law and cache, passed down
    outcome.py     one scenario's process: run, judge, write its page; what it sends back
    processes.py   every scenario in a process forked for it, costliest first, with a timeout (s)
    warm_up.py     compiling and importing once, before the processes fork
    law.py         the scenes under --law (a law file, or the law `identify` finds)
    report.py      the report: every scenario into a hidden folder, then index.md, moved into place
    lines.py       the line printed per scenario (its verdict) and the cache's line
"""

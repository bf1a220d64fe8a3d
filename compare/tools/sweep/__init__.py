"""The sweep's report: what `python -m compare sweep` writes from the work-precision results.

The measuring (ladders of steps, the reference, the executor) is compare/tools/accuracy/
workprecision.py; this package turns its SceneSweeps into DIR/sweep/:

    wording.py        integrator names, times (s, ms), lengths (mm, um), numbers, as the sweep writes them
    answer.py         "the cheapest way to reach 1 mm here?" in a few sentences
    cheapest.py       cheapest.md: that answer as one table, with the machine it was measured on
    residual.py       the energy residual R(end) (J): its order against dt, and its table
    stability.py      the table of stability limits (s) beside the linear theory
    figure.py         <scene>_workprecision.png: error against CPU time, |R(end)| against dt
    page.py           index.md: the method, the answers, the stability table, a section per scene
    results_json.py   results.json: every run and limit, as numbers
    report.py         the whole folder, written beside the old one and moved into place
"""

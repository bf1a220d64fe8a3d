"""Parameter studies: a grid of scene fields x integrators, run in batches on Dask (`python -m compare study`).

    fields.py    --vary NAME=SPEC, the varied scene through the loader
    plan.py      points, runs, keys, batches
    measure.py   the pure task: a batch of runs -> rows (stable, errors, cost)
    runner.py    references and batches on the executor (compare/executor/), results kept
    table.py     study.csv / study.parquet
    maps.py      heatmaps with the theory's stability limit
    report.py    DIR/index.md
"""

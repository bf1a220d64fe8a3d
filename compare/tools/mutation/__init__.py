"""The harness's own mutation test: typical mistakes put into copies of custom_sim (catalogue.py),
each run by `python -m compare tools mutation` (mutants.py)."""

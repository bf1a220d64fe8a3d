"""Verdicts: run a scenario in every simulator, measure the differences, judge each check."""

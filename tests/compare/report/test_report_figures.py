"""The figures' line thinning keeps what a reader must see: every extreme of every run of
samples, the first and last sample, in time order."""
from __future__ import annotations

import numpy as np

from compare.report.plots import MAX_POINTS, _envelope


def test_short_lines_are_drawn_whole():
    y = np.arange(MAX_POINTS, dtype=float)
    assert _envelope(y) == slice(None)


def test_a_one_sample_spike_and_each_runs_extremes_survive():
    rng = np.random.default_rng(1)
    y = rng.normal(size=100_003)
    spike = 54_321
    y[spike] = 50.0                      # one sample, far above the rest
    k = _envelope(y)
    assert len(k) <= MAX_POINTS + 2
    assert np.all(np.diff(k) > 0), "indices in time order, none twice"
    assert k[0] == 0 and k[-1] == len(y) - 1
    assert spike in k
    assert y[k].max() == y.max() and y[k].min() == y.min()
    # every run of samples keeps its own lowest and highest point
    runs = MAX_POINTS // 2
    width = -(-len(y) // runs)
    for start in range(0, len(y), width * 97):   # a spread of runs
        run = y[start:start + width]
        assert start + int(np.argmax(run)) in k and start + int(np.argmin(run)) in k

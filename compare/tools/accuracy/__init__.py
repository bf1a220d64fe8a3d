"""Accuracy against cost: converged reference solutions, work-precision sweeps, stability search, benchmarks."""

"""The tools off the run path: accuracy and cost studies, calibration, Dask studies, the mutation
test, the game. The checks never import them."""

"""Calibration: fit the twin's contact settings to custom_sim (or k, c, mu, alpha to MuJoCo)."""

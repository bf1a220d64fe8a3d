"""Calibration: fit the MuJoCo twin's contact settings to custom_sim, or custom_sim's k, c, mu,
alpha to the twin, and a measured solref/solimp conversion (docs/calibration.md).

    parameters.py   PARAMETERS, DEFAULT_FIT, parse_fit: what may be fitted, bounds, gains/values
    settings.py     ContactSettings: a twin's pair settings, read from / written to MjModel, MjSpec
    targets.py      prepare(scene, mapping): a scene compiled once; Batch: rollouts of k twins at once
    fit.py          fit(targets, params): mujoco.minimize.least_squares, status, bounds, cost
    calibration.py  calibrate(fitted, held_out, params, base, max_iter): fit, measure, read back
    causes.py       what no contact setting can remove
    reverse.py      reverse_fit(targets): custom_sim's k, c, mu, alpha that follow MuJoCo
    conversion.py   conversion_table(mass, k, c, shape): solref/solimp per mapping, with its error
    report.py       write_calibration / write_reverse: index.md, calibration.json, MJCF, plots
"""

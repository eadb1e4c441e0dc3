#!/usr/bin/env python3
"""One-off (docs/speed.md "Exported C"): FilterPy's time per row for the filters kfw-cli export-c
was timed on, on the same data. Never run by tests or CI (FilterPy is not a Debian package).

  python3 bench/filterpy_step.py FILTERPY_DIR DATA_DIR
FILTERPY_DIR: a checkout of rlabbe/filterpy; DATA_DIR: rb.csv (kfw-cli simulate
presets/models/range_bearing.json --set sim.duration=600) and cv.csv (cv1d, the same).
Needs NumPy and SciPy (Debian: python3-numpy, python3-scipy)."""
import csv
import math
import sys
import time

sys.path.insert(0, sys.argv[1])
import numpy as np  # noqa: E402
from filterpy.kalman import (ExtendedKalmanFilter, KalmanFilter,  # noqa: E402
                             MerweScaledSigmaPoints, UnscentedKalmanFilter)


def rows(path, cols):
    with open(path) as f:
        return [[float(r["t"])] + [float(r[c]) for c in cols] for r in csv.DictReader(f)]


def best(run, data, repeats=3):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run(data)
        times.append((time.perf_counter() - t0) / len(data))
    return min(times)


def cv_q(dt, sa, dim):
    q = np.array([[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]]) * sa**2
    if dim == 1:
        return q
    Q = np.zeros((4, 4))
    for i, j in [(0, 0), (0, 2), (2, 0), (2, 2)]:
        Q[i, j] = Q[i + 1, j + 1] = q[i // 2, j // 2]
    return Q


def run_cv1d(data):
    kf = KalmanFilter(dim_x=2, dim_z=1)
    kf.x = np.array([data[0][1], 0.0])
    kf.P = np.diag([100.0, 10.0])
    kf.H = np.array([[1.0, 0.0]])
    kf.R = np.array([[4.0]])
    for k, (t, z) in enumerate(data):
        if k:
            dt = t - data[k - 1][0]
            kf.F = np.array([[1.0, dt], [0.0, 1.0]])
            kf.Q = cv_q(dt, 0.5, 1)
            kf.predict()
        kf.update(np.array([z]))


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def hx(x):
    return np.array([math.hypot(x[0], x[1]), math.atan2(x[1], x[0])])


def H_jac(x):
    r2 = x[0] ** 2 + x[1] ** 2
    r = math.sqrt(r2)
    return np.array([[x[0] / r, x[1] / r, 0, 0], [-x[1] / r2, x[0] / r2, 0, 0]])


def residual(a, b):
    y = a - b
    y[1] = wrap(y[1])
    return y


R_RB = np.diag([10.0**2, 0.02**2])
X0 = np.array([-1000.0, 900.0, 0.0, -30.0])
P0 = np.diag([400.0, 400.0, 4.0, 4.0])


def F_cv(dt):
    F = np.eye(4)
    F[0, 2] = F[1, 3] = dt
    return F


def run_ekf(data):
    f = ExtendedKalmanFilter(dim_x=4, dim_z=2)
    f.x, f.P, f.R = X0.copy(), P0.copy(), R_RB
    for k, (t, r, b) in enumerate(data):
        if k:
            dt = t - data[k - 1][0]
            f.F, f.Q = F_cv(dt), cv_q(dt, 0.5, 2)
            f.predict()
        f.update(np.array([r, b]), H_jac, hx, residual=residual)


def run_ukf(data):
    pts = MerweScaledSigmaPoints(4, alpha=1.0, beta=2.0, kappa=0.0)
    f = UnscentedKalmanFilter(dim_x=4, dim_z=2, dt=0.1, hx=hx, fx=lambda x, dt: F_cv(dt) @ x,
                              points=pts, residual_z=residual)
    f.x, f.P, f.R = X0.copy(), P0.copy(), R_RB
    for k, (t, r, b) in enumerate(data):
        if k:
            dt = t - data[k - 1][0]
            f.Q = cv_q(dt, 0.5, 2)
            f.predict(dt=dt)
        f.update(np.array([r, b]))


def main():
    d = sys.argv[2]
    cv = rows(d + "/cv.csv", ["z"])
    rb = rows(d + "/rb.csv", ["range", "bearing"])
    for name, run, data in [("cv1d KF", run_cv1d, cv), ("range_bearing EKF", run_ekf, rb),
                            ("range_bearing UKF", run_ukf, rb)]:
        print(f"{name}: {best(run, data) * 1e6:.1f} us per row ({len(data)} rows, best of 3)")


if __name__ == "__main__":
    main()

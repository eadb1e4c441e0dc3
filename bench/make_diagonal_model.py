#!/usr/bin/env python3
"""A diagonal model of N states for the model-load benchmark (issue 29): F and Q written as full
N x N matrices (the form that made loading quadratic), one scalar channel per state.

usage: bench/make_diagonal_model.py N > model.json"""
import json
import sys


def model(n):
    states = [f"x{i}" for i in range(n)]
    F = [["1" if i == j else 0 for j in range(n)] for i in range(n)]
    Q = [["q*dt" if i == j else 0 for j in range(n)] for i in range(n)]
    meas = {f"z{i}": {"roles": [f"z{i}"], "H": [[1 if j == i else 0 for j in range(n)]], "R": ["r"]}
            for i in range(n)}
    return {
        "format": "kfw-preset", "version": 2, "scenario": "model",
        "title": f"diagonal random walk, {n} states",
        "parameters": {
            "q": {"value": 0.1, "min": 1e-6, "max": 1e6, "scale": "log", "label": "q"},
            "r": {"value": 1.0, "min": 1e-6, "max": 1e6, "scale": "log", "label": "r"},
        },
        "model": {"version": 1, "states": states, "x0": [0] * n, "P0": [1] * n,
                  "process": {"F": F, "Q": Q}, "measurements": meas},
    }


if __name__ == "__main__":
    json.dump(model(int(sys.argv[1])), sys.stdout)

# ruff: noqa: SIM115, B905  (measurement scripts: patch before import, terse)
import pickle
import sys

import numpy as np

a, b = pickle.load(open(sys.argv[1], "rb")), pickle.load(open(sys.argv[2], "rb"))
def eq(x, y):
    if isinstance(x, np.ndarray):
        return x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y, equal_nan=True)
    if isinstance(x, (list, tuple)):
        return len(x) == len(y) and all(eq(p, q) for p, q in zip(x, y))
    return x == y
print("identical:", eq(a, b))

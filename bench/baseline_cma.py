"""A straightforward closest-match inverse (the baseline of benchmark 4; not used by the package).

For every sample it tries every level: copies the relay states, moves the
input there, sums the weighted relays and keeps the level whose output is
closest to the measurement. O(n_levels * n_hysterons) per sample.
"""
import numpy as np


class NaiveCMA:
    def __init__(self, model):
        self.model = model
        n = model.n_levels
        self.i, self.j = np.tril_indices(n)
        self.w = model.density[self.i, self.j]
        self.edges = model.edges
        self.h = -np.ones(self.i.size)

    def _apply(self, h, u):
        h = h.copy()
        h[self.edges[self.i + 1] <= u] = 1.0
        h[self.edges[self.j] >= u] = -1.0
        return h

    def inverse(self, y):
        best, best_err, best_h = None, np.inf, None
        for u in self.edges:
            h = self._apply(self.h, u)
            err = abs(self.model.offset + self.w @ h - y)
            if err < best_err:
                best, best_err, best_h = u, err, h
        self.h = best_h
        return best

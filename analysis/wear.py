"""The chalk's mark by Archard's wear law (docs/chalk.md): over each step every node k leaves
lambda_k (its normal force at x^{n+1}) times its slide along the board, binned per BIN of board."""
from itertools import pairwise

import numpy as np

from analysis import diagnostics

BIN = 1e-4                  # m of board per bin of the mark: 0.1 mm
UNIT = "N m per 0.1 mm"     # what a bin holds: lambda_k times the length slid in it, summed
RISE = 2.0                  # a dash begins at a bin holding more than this times the one before


def archard(s0, s1, lam):
    """One step's deposit: node k slides from s0_k to s1_k (m) under lam_k (N); bin j, [j BIN,
    (j + 1) BIN), gets sum_k lam_k |[s0_k, s1_k] within it|. Returns (j0, deposit), deposit[i]
    being bin j0 + i's (N m); it sums to sum_k lam_k |s1_k - s0_k|."""
    s0, s1, lam = (np.asarray(a, float) for a in (s0, s1, lam))
    lo, hi = np.minimum(s0, s1), np.maximum(s0, s1)
    on = (lam > 0) & (hi > lo)
    if not on.any():
        return 0, np.zeros(0)
    lo, hi, lam = lo[on], hi[on], lam[on]
    j0, j1 = int(np.floor(lo.min() / BIN)), int(np.floor(hi.max() / BIN)) + 1
    edges = np.arange(j0, j1 + 1) * BIN
    # sum_k lam_k times the length of node k's slide below each edge; differenced, per bin
    below = (lam[:, None] * np.clip(edges - lo[:, None], 0.0, (hi - lo)[:, None])).sum(axis=0)
    return j0, np.diff(below)


class Deposit:
    """The mark so far: the deposit (N m) of the bins first <= j < first + len(values) that it
    touched."""

    def __init__(self):
        self.values, self.first = np.zeros(0), 0

    def add(self, j0, deposit):
        """Add `deposit` to the bins from j0 on (archard's result)."""
        if not len(deposit):
            return
        if not len(self.values):
            self.first = j0
        lo, hi = min(self.first, j0), max(self.first + len(self.values), j0 + len(deposit))
        if (lo, hi) != (self.first, self.first + len(self.values)):     # grown: zeros each side
            self.values = np.pad(self.values, (self.first - lo, hi - self.first - len(self.values)))
            self.first = lo
        self.values[j0 - lo:j0 - lo + len(deposit)] += deposit

    def step(self, scene, x0, x1, lam1=None):
        """A step from x0 to x1 by `archard`, lam1 the lambda_k at x1 (diagnostics.lambdas, found
        here when None); returns sum_k lambda_k |delta s_k|."""
        tangent = diagnostics.tangent(scene)
        lam1 = diagnostics.lambdas(scene, x1) if lam1 is None else lam1
        j0, deposit = archard(x0 @ tangent, x1 @ tangent, lam1)
        self.add(j0, deposit)
        return float(deposit.sum())

    def centres(self):
        """The touched bins' middles along the board (m)."""
        return (self.first + np.arange(len(self.values)) + 0.5) * BIN

    def span(self):
        """The board the mark covers, (from, to) in m; None before any deposit."""
        if not len(self.values):
            return None
        return self.first * BIN, (self.first + len(self.values)) * BIN

    def darkest(self):
        """The largest bin's deposit (N m; 0 before any)."""
        return float(self.values.max(initial=0.0))

    def copy(self):
        """A Deposit of its own holding the same bins."""
        other = Deposit()
        other.values, other.first = self.values.copy(), self.first
        return other

    def shade(self, a, b):
        """How dark the mark is over each stretch [a_i, b_i] of board (m), 0 to 1: its deposit per
        metre there over the darkest bin's, the deposit taken as even within a bin."""
        darkest = self.darkest()
        a, b = np.asarray(a, float), np.asarray(b, float)
        if darkest <= 0:
            return np.zeros(np.broadcast(a, b).shape)
        edges = (self.first + np.arange(len(self.values) + 1)) * BIN
        below = np.concatenate([[0.0], np.cumsum(self.values)])        # the deposit below each edge
        held = np.interp(b, edges, below) - np.interp(a, edges, below)
        return np.clip(held / np.maximum(b - a, 1e-300) * BIN / darkest, 0.0, 1.0)


def dashes(values):
    """A mark's dashes: each begins at a bin holding more than RISE times the one before (not at
    one that only continues a rise). For each dash that a next one ends: (its first bin's index,
    its darkest bin's deposit, its faintest's)."""
    v = np.asarray(values, float)
    rises = np.r_[False, v[1:] > RISE * v[:-1]]
    starts = np.flatnonzero(rises & ~np.r_[False, rises[:-1]])
    return [(int(a), float(v[a:b].max()), float(v[a:b].min())) for a, b in pairwise(starts)]


def csv_text(deposit):
    """marks.csv: a header, then per bin its middle along the board (mm) and its deposit (N m)."""
    rows = [f"{1e3 * s:.2f},{d!r}" for s, d in zip(deposit.centres(), deposit.values.tolist())]
    return "\n".join([f"x_mm,deposit_N_m_per_{BIN * 1e3:g}_mm"] + rows) + "\n"

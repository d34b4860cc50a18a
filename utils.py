"""Shared helpers: input checks, IJV triplets, and (below its own banner) the SPD solve of the Newton system.

Every energy returns its Hessian as an IJV triplet (rows, cols, values) with DOF index 2*node + axis;
duplicate entries are summed when the matrix is built. The helpers here turn a batch of dense
per-element blocks into such a triplet, so no energy repeats that bookkeeping.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.linalg import lapack


# ----------------------------------------------------------------------------------------------
# Input checks: one line each in the energies, a ValueError that names the argument.
# ----------------------------------------------------------------------------------------------

def check_points(name, x, shape=None):
    """Return `x` as a float64 (N, 2) array, of `shape` if given; ValueError if the shape is wrong or a value
    is not finite."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 2 or x.shape[1] != 2 or shape not in (None, x.shape):
        raise ValueError(f"{name} must have shape {shape or '(N, 2)'}, got shape {x.shape}")
    if not np.isfinite(x).all():
        bad = np.argwhere(~np.isfinite(x))[0]
        raise ValueError(f"{name} has a non-finite value {x[tuple(bad)]} at node {bad[0]}")
    return x


def check_per_item(name, a, count, what="node"):
    """Return `a` as a float64 (count,) array (a scalar is broadcast); ValueError on length or non-finite."""
    a = np.asarray(a, dtype=np.float64)
    if a.ndim == 0:
        a = np.full(count, float(a))
    if a.shape != (count,):
        raise ValueError(f"{name} must have one value per {what} ({count}), got shape {a.shape}")
    if not np.isfinite(a).all():
        i = int(np.argmax(~np.isfinite(a)))
        raise ValueError(f"{name} has a non-finite value {a[i]} at {what} {i}")
    return a


def check_vector(name, a):
    """Return `a` as a finite float64 2-vector; ValueError for text or booleans, even where they convert."""
    if np.asarray(a).dtype.kind in "bUS":
        raise ValueError(f"{name} must be a 2-vector of numbers, got {a!r}")
    a = np.asarray(a, dtype=np.float64)
    if a.shape != (2,):
        raise ValueError(f"{name} must be a 2-vector, got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} must be finite, got {a.tolist()}")
    return a


def check_unit_normal(name, n):
    """Return the half-space normal `n` as a 2-vector; it must have unit length (normalize it first)."""
    n = check_vector(name, n)
    length = float(np.hypot(n[0], n[1]))
    if abs(length - 1.0) > 1e-9:
        raise ValueError(f"{name} must be a unit vector, got {n.tolist()} of length {length:.6g}")
    return n


def as_float(name, value, requirement):
    """float(value), or a ValueError saying `name` {requirement} for anything that is not a number
    (a bool, or a string even where float() would parse it: '4' is text, not a count)."""
    if isinstance(value, (bool, np.bool_, str, bytes, np.str_, np.bytes_)):
        raise ValueError(f"{name} {requirement}, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} {requirement}, got {value!r}") from None


def check_positive(name, value):
    """Return `value` as a float; ValueError unless it is a finite number > 0."""
    value = as_float(name, value, "must be a finite number > 0")
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a finite number > 0, got {value}")
    return value


# eps_v below this makes f_hess_term's 1/eps_v^2 overflow float64 (1/eps_v^2 < 1.8e308 needs eps_v > 7.5e-155)
EPSV_MIN = 1e-150


def check_epsv(epsv):
    """Return eps_v as a float; ValueError unless it is a finite number >= EPSV_MIN."""
    epsv = check_positive("epsv", epsv)
    if epsv < EPSV_MIN:
        raise ValueError(f"epsv must be >= {EPSV_MIN:g} (f_hess_term's 1/eps_v^2 must fit in float64), got {epsv}")
    return epsv


def check_edges(name, e, n_nodes):
    """Return `e` as an int (E, 2) array of node indices in [0, n_nodes)."""
    e = np.asarray(e)
    if e.ndim != 2 or e.shape[1] != 2:
        raise ValueError(f"{name} must have shape (E, 2), got shape {e.shape}")
    if e.size and not np.issubdtype(e.dtype, np.integer):
        raise ValueError(f"{name} must hold integer node indices, got dtype {e.dtype}")
    e = e.astype(np.int64, copy=False)
    if e.size and (e.min() < 0 or e.max() >= n_nodes):
        bad = e[(e < 0) | (e >= n_nodes)][0]
        raise ValueError(f"{name} has node index {bad} outside [0, {n_nodes}) for {n_nodes} nodes")
    return e


def finite_result(what, value):
    """Return `value` if every entry is finite; a ValueError otherwise (an overflow at parameters
    beyond floating-point range, e.g. eps_v = 1e-160 or a node 1e-160 m from the slope), never a NaN."""
    if not np.isfinite(value).all():
        raise ValueError(f"{what} overflowed to a non-finite value: the arguments are beyond "
                         "float64 range (check eps_v, dhat, kappa and the distances to the slope)")
    return value


# ----------------------------------------------------------------------------------------------
# IJV triplets
# ----------------------------------------------------------------------------------------------

def block_dofs(nodes):
    """The DOFs (B, 2m) of element node lists (B, m): node a has DOFs 2a (x) and 2a + 1 (y)."""
    return (2 * nodes[:, :, None] + np.arange(2)).reshape(len(nodes), 2 * nodes.shape[1])


def blocks_to_ijv(nodes, blocks):
    """The IJV triplet of dense blocks (B, 2m, 2m) on element node lists (B, m): entry (r, c) of element
    b's block is H[dofs[b, r], dofs[b, c]] (block_dofs)."""
    dofs = block_dofs(nodes)
    size = dofs.shape[1]
    return np.repeat(dofs, size, axis=1).ravel(), np.tile(dofs, (1, size)).ravel(), blocks.reshape(-1)


def concat_ijv(triplets):
    """Several IJV triplets joined into one (their entries are summed when the matrix is built)."""
    return tuple(np.concatenate(parts) for parts in zip(*triplets))


def ijv_to_csr(ijv, n_dofs):
    """Sum an IJV triplet (duplicates added) into an (n_dofs, n_dofs) CSR matrix."""
    rows, cols, vals = ijv
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))


def add_to_pairs(e, f, n):
    """(n, 2) array: each pair (a, b) of `e` adds its row of f (E, 2) to node a and subtracts it from node b."""
    a, b = (2 * e[:, i:i + 1] + np.arange(2) for i in (0, 1))       # the DOFs of a and b, (E, 2) each
    return (np.bincount(a.ravel(), f.ravel(), 2 * n) - np.bincount(b.ravel(), f.ravel(), 2 * n)).reshape(n, 2)


# ----------------------------------------------------------------------------------------------
# The Newton system's SPD solve: what exists for speed, behind one call, solver.solve(H, b).
# A student can read it as scipy.sparse.linalg.spsolve(H, b).
# ----------------------------------------------------------------------------------------------

# Banded Cholesky while the band holds at most this many times the matrix's nonzeros (the lecture's
# grid, numbered row by row, has a band of about 2 n_seg); beyond that SuperLU's fill-reducing ordering
# needs less time and memory.
BAND_LIMIT = 40


@dataclass(frozen=True)
class SPDSolver:
    """Solves H p = b for the Incremental Potential's Hessian H, symmetric positive definite (M plus
    PSD-projected terms), given as element blocks on one mesh. `kind` is fixed per mesh by `for_mesh`:
    "banded", LAPACK's banded Cholesky (dpbtrf, dpbtrs) on the upper band; or "superlu", a sparse LU."""
    n_dofs: int
    bandwidth: int              # max |row - col| of an entry H can have
    kind: str
    node_slots: np.ndarray      # (N, 3) band positions of the upper triangle of node i's 2x2 block
    edges: np.ndarray           # (E, 2) the mesh's edges
    edge_slots: np.ndarray      # (E, 10) band positions of the upper triangle of edge j's 4x4 block

    @classmethod
    def for_mesh(cls, n_nodes, e, kind=None):
        """The solver for H on n_nodes nodes joined by edges e (H has a 2x2 block per node and per edge);
        `kind` None picks "banded" unless the band is over BAND_LIMIT times H's nonzeros."""
        e = np.array(e, dtype=np.int64).reshape(-1, 2)
        bandwidth = int(2 * np.abs(e[:, 0] - e[:, 1]).max(initial=0) + 1)
        nonzeros = 4 * n_nodes + 8 * len(e)
        if kind is None:
            kind = "banded" if (bandwidth + 1) * 2 * n_nodes <= BAND_LIMIT * nonzeros else "superlu"
        if kind not in ("banded", "superlu"):
            raise ValueError(f"kind must be 'banded' or 'superlu', got {kind!r}")
        node_slots = _band_slots(bandwidth, np.arange(n_nodes)[:, None], *_UPPER_TRIANGLE[2])
        edge_slots = _band_slots(bandwidth, e, *_UPPER_TRIANGLE[4])
        for a in (node_slots, e, edge_slots):
            a.setflags(write=False)
        return cls(2 * n_nodes, bandwidth, kind, node_slots, e, edge_slots)

    def solve(self, H, b):
        """p = H^-1 b, H given as element blocks: a list of (nodes (B, m), blocks (B, 2m, 2m)) whose sum it
        is (see blocks_to_ijv). np.linalg.LinAlgError when H is not positive definite."""
        if self.kind == "superlu":
            return self._superlu_solve(H, b)
        factor, info = lapack.dpbtrf(self.upper_band(H), lower=0, overwrite_ab=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"banded Cholesky failed (dpbtrf info {info}): H is not positive definite")
        return lapack.dpbtrs(factor, b, lower=0)[0]

    def _superlu_solve(self, H, b):
        """p = H^-1 b by SuperLU on H in CSC form (a mesh numbered with a wide band)."""
        rows, cols, vals = concat_ijv(blocks_to_ijv(nodes, blocks) for nodes, blocks in H)
        A = scipy.sparse.csc_matrix((vals, (rows, cols)), shape=(self.n_dofs, self.n_dofs))
        try:
            return scipy.sparse.linalg.splu(A).solve(b)
        except RuntimeError as err:         # SuperLU: the matrix is singular
            raise np.linalg.LinAlgError(str(err)) from None

    def upper_band(self, H):
        """H's upper band in LAPACK's storage, ab[bandwidth + r - c, c] = H[r, c] for r <= c, from each
        symmetric element block's upper triangle (its lower one mirrors it), duplicates summed."""
        slots, values = [], []
        for nodes, blocks in H:
            i, j = _UPPER_TRIANGLE[blocks.shape[1]]
            slots.append(self._slots(nodes, i, j))
            values.append(blocks[:, i, j])
        band = np.bincount(np.concatenate(slots, axis=None), np.concatenate(values, axis=None),
                           (self.bandwidth + 1) * self.n_dofs)
        return band.reshape(self.bandwidth + 1, self.n_dofs, order="F")

    def _slots(self, nodes, i, j):
        """_band_slots(nodes, i, j), looked up where the elements are nodes or the mesh's edges."""
        if nodes.shape[1] == 1:
            return self.node_slots.take(nodes[:, 0], axis=0)
        if nodes.shape == self.edges.shape and np.array_equal(nodes, self.edges):
            return self.edge_slots
        return _band_slots(self.bandwidth, nodes, i, j)


def _band_slots(bandwidth, nodes, i, j):
    """Where entry (i, j) of each element's block lands in the flat upper band: H[r, c] with r <= c is at
    bandwidth + r - c + (bandwidth + 1) c = bandwidth + r + bandwidth c, (B, len(i))."""
    dofs = block_dofs(nodes)
    r, c = dofs[:, i], dofs[:, j]
    return bandwidth + np.minimum(r, c) + bandwidth * np.maximum(r, c)


# the (row, col) indices of the upper triangle of a 2x2 and a 4x4 element block, constants
_UPPER_TRIANGLE = {size: np.triu_indices(size) for size in (2, 4)}

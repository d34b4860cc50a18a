"""Shared helpers: PSD projection of small symmetric matrices, IJV triplets, input checks, and the
Newton system's fixed sparsity pattern with its SPD solve.

Every energy returns its Hessian as an IJV triplet (rows, cols, values) with DOF index
2*node + axis; the helpers here turn a batch of dense per-element blocks into such a triplet
and a triplet into a CSR matrix, so no energy repeats that bookkeeping. The time integrator skips
the triplets: `BlockPattern` maps each block entry to its slot of a pattern fixed per scene.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.linalg import lapack


# ----------------------------------------------------------------------------------------------
# Input checks: one line each in the energies, a ValueError that names the argument.
# ----------------------------------------------------------------------------------------------

def check_points(name, x):
    """Return `x` as a float64 (N, 2) array; ValueError if the shape is wrong or a value is not finite."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"{name} must have shape (N, 2), got shape {x.shape}")
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
    """Return `a` as a finite float64 2-vector."""
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


def check_positive(name, value):
    """Return `value` as a float; ValueError unless it is a finite number > 0."""
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a finite number > 0, got {value}")
    return value


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


# ----------------------------------------------------------------------------------------------
# PSD projection
# ----------------------------------------------------------------------------------------------

def project_psd(H):
    """Clamp the negative eigenvalues of a batch of symmetric matrices (B, d, d) to zero.

    General route: one batched eigen-decomposition, H+ = Q max(Lambda, 0) Q^T.
    """
    H = np.asarray(H, dtype=np.float64)
    if H.shape[-1] == 2 and H.shape[-2] == 2:
        return project_psd_2x2(H)
    lam, Q = np.linalg.eigh(H)
    P = (Q * np.maximum(lam, 0.0)[..., None, :]) @ np.swapaxes(Q, -1, -2)
    return 0.5 * (P + np.swapaxes(P, -1, -2))      # exactly symmetric, as the true result is


def project_psd_2x2(H):
    """Closed-form PSD projection of a batch of symmetric 2x2 matrices (B, 2, 2).

    Eigenvalues lambda_{1,2} = m +- r with m = (a + c)/2, r = hypot((a - c)/2, b). When
    lambda_2 < 0 < lambda_1, the projection keeps lambda_1 P_1, and the spectral projector is
    P_1 = (H - lambda_2 I) / (lambda_1 - lambda_2), so no eigenvector is ever formed.
    """
    a = H[..., 0, 0]
    b = 0.5 * (H[..., 0, 1] + H[..., 1, 0])
    c = H[..., 1, 1]
    m = 0.5 * (a + c)
    r = np.hypot(0.5 * (a - c), b)
    lam1, lam2 = m + r, m - r
    out = np.array(H, dtype=np.float64, copy=True)
    out[..., 0, 1] = out[..., 1, 0] = b
    mixed = (lam2 < 0.0) & (lam1 > 0.0)
    if mixed.any():
        scale = lam1[mixed] / (lam1[mixed] - lam2[mixed])
        out[mixed, 0, 0] = scale * (a[mixed] - lam2[mixed])
        out[mixed, 1, 1] = scale * (c[mixed] - lam2[mixed])
        out[mixed, 0, 1] = out[mixed, 1, 0] = scale * b[mixed]
    out[lam1 <= 0.0] = 0.0
    return out


# ----------------------------------------------------------------------------------------------
# IJV triplets
# ----------------------------------------------------------------------------------------------

def scatter_add_pairs(e, values, n):
    """(n, 2) array: each pair (a, b) of `e` adds values[j] to row a and -values[j] to row b."""
    dofs = (2 * e[:, :, None] + np.arange(2)).reshape(-1)
    signed = np.stack([values, -values], axis=1).reshape(-1)
    return np.bincount(dofs, signed, minlength=2 * n).reshape(n, 2)


def empty_ijv():
    """An IJV triplet with no entries (a term whose Hessian is zero)."""
    return (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0))


def block_dofs(nodes):
    """DOF indices (B, 2m) of element node lists (B, m): node a -> (2a, 2a + 1)."""
    nodes = np.asarray(nodes, dtype=np.int64)
    return (2 * nodes[:, :, None] + np.arange(2)).reshape(len(nodes), 2 * nodes.shape[1])


def block_entries(nodes):
    """Row and column DOF of every entry of the (2m, 2m) blocks on element nodes (B, m): two (B, 4m^2)."""
    dofs = block_dofs(nodes)
    size = dofs.shape[1]
    return np.repeat(dofs, size, axis=1), np.tile(dofs, (1, size))


def blocks_to_ijv(nodes, blocks):
    """Scatter dense blocks (B, 2m, 2m) acting on element nodes (B, m) into one IJV triplet."""
    rows, cols = block_entries(nodes)
    return rows.ravel(), cols.ravel(), np.asarray(blocks, dtype=np.float64).reshape(-1)


def ijv_to_csr(ijv, n_dofs):
    """Sum an IJV triplet (duplicates added) into an (n_dofs, n_dofs) CSR matrix."""
    rows, cols, vals = ijv
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))


def concat_ijv(triplets):
    """Join several IJV triplets into one (entries are summed later, at assembly)."""
    triplets = list(triplets)
    if not triplets:
        return empty_ijv()
    return tuple(np.concatenate([t[i] for t in triplets]) for i in range(3))


def scale_ijv(ijv, factor):
    """The same triplet with every value multiplied by `factor`."""
    return ijv[0], ijv[1], ijv[2] * factor


# ----------------------------------------------------------------------------------------------
# The Newton system: a sparsity pattern fixed per scene, filled per iteration, and its SPD solve
# ----------------------------------------------------------------------------------------------

# Banded Cholesky is used while the band holds at most this many times the matrix's nonzeros.
# On the lecture's grid (nodes numbered row by row, band ~ 2 n_seg) LAPACK's banded Cholesky
# (dpbtrf) factors 2 to 5 times faster than SuperLU from n_seg = 4 up to n_seg = 192 (ratio 41,
# a 230 MB band); beyond that, or for a mesh numbered with a wide band, SuperLU's fill-reducing
# ordering needs less time and memory.
BAND_LIMIT = 40


def _readonly(*arrays):
    for a in arrays:
        a.setflags(write=False)


@dataclass(frozen=True)
class BlockPattern:
    """Sparsity pattern of the Incremental Potential's Hessian on N nodes and edges e: a 2x2 block
    on every node's diagonal (inertia, barrier, friction) and one off it at (a, b) and (b, a) for
    every edge (springs). Only the upper triangle is stored, one value per slot (rows[s], cols[s]).

    `node_slots` (N, 4) and `edge_slots` (E, 16) give the slot of each entry of a node's 2x2 block
    and an edge's 4x4 block in row-major order; entries below the diagonal go to the extra slot
    `dump` and are dropped (the blocks are symmetric). Built once per scene by `build`, read-only.
    """
    n_dofs: int
    rows: np.ndarray
    cols: np.ndarray
    node_slots: np.ndarray
    edge_slots: np.ndarray
    diagonal_slots: np.ndarray      # slot of (d, d) for every DOF d
    solver: str                     # "banded" (LAPACK dpbtrf) or "superlu"
    bandwidth: int                  # max(cols - rows)
    band_index: np.ndarray          # slot -> flat index of the (bandwidth + 1, n_dofs) band, Fortran order
    csc_indptr: np.ndarray          # the full symmetric pattern in CSC form, for SuperLU
    csc_indices: np.ndarray
    full_from_upper: np.ndarray     # slot of every stored entry of the full CSC pattern

    @property
    def dump(self):
        return len(self.rows)

    @classmethod
    def build(cls, n_nodes, e, solver=None):
        """The pattern of N nodes and edges e; `solver` None picks "banded" or "superlu" (BAND_LIMIT)."""
        n = 2 * n_nodes
        entries = [block_entries(np.arange(n_nodes)[:, None]), block_entries(e)]
        keys = [np.maximum(r, c) * n + np.minimum(r, c) for r, c in entries]    # column-major upper
        upper = np.unique(np.concatenate([k.ravel() for k in keys]))
        rows, cols = upper % n, upper // n
        dump = len(upper)
        node_slots, edge_slots = (np.where(r <= c, np.searchsorted(upper, k), dump)
                                  for (r, c), k in zip(entries, keys))
        diagonal_slots = np.searchsorted(upper, np.arange(n) * (n + 1))
        bandwidth = int((cols - rows).max())
        if solver is None:
            solver = "banded" if (bandwidth + 1) * n <= BAND_LIMIT * len(upper) else "superlu"
        if solver not in ("banded", "superlu"):
            raise ValueError(f"solver must be 'banded' or 'superlu', got {solver!r}")
        band_index = (bandwidth + rows - cols) + (bandwidth + 1) * cols
        indptr, indices, full_from_upper = _full_csc(rows, cols, n)
        _readonly(rows, cols, node_slots, edge_slots, diagonal_slots, band_index, indptr, indices,
                  full_from_upper)
        return cls(n, rows, cols, node_slots, edge_slots, diagonal_slots, solver, bandwidth,
                   band_index, indptr, indices, full_from_upper)

    def sum_into_slots(self, slots, blocks):
        """Upper-triangle values: every block entry added into its slot (one np.bincount)."""
        index = np.concatenate([s.reshape(-1) for s in slots])
        values = np.concatenate([b.reshape(-1) for b in blocks])
        return np.bincount(index, values, minlength=self.dump + 1)[:self.dump]

    def to_csc(self, upper):
        """The full symmetric matrix of the slot values `upper`, as a scipy CSC matrix."""
        return scipy.sparse.csc_matrix((upper[self.full_from_upper], self.csc_indices, self.csc_indptr),
                                       shape=(self.n_dofs, self.n_dofs))

    def matrix(self, upper):
        """The slot values in the form `factor_solve` takes: LAPACK upper band storage, or CSC."""
        if self.solver == "superlu":
            return self.to_csc(upper)
        band = np.zeros((self.bandwidth + 1) * self.n_dofs)
        band[self.band_index] = upper
        return band.reshape(self.bandwidth + 1, self.n_dofs, order="F")

    def factor_solve(self, A, b):
        """x = A^-1 b for A = matrix(...) symmetric positive definite; a band A is overwritten.

        Banded: Cholesky A = U^T U (dpbtrf), then two triangular band solves (dpbtrs). SuperLU: in
        symmetric mode with a minimum-degree ordering of A^T + A and no off-diagonal pivoting
        (diag_pivot_thresh=0), which an SPD matrix needs none of; the factor stays as sparse as a
        Cholesky factor instead of the larger unsymmetric LU.
        """
        if self.solver == "superlu":
            lu = scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                          options={"SymmetricMode": True})
            return lu.solve(b)
        factor, info = lapack.dpbtrf(A, lower=0, overwrite_ab=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"banded Cholesky failed (dpbtrf info {info}): the matrix "
                                        "is not positive definite")
        return lapack.dpbtrs(factor, b, lower=0)[0]


def _full_csc(rows, cols, n):
    """CSC arrays (indptr, indices) of the symmetric pattern whose upper triangle is (rows, cols),
    and for each stored entry the upper slot it mirrors."""
    off = rows != cols
    slot = np.arange(len(rows))
    full_rows = np.concatenate([rows, cols[off]])
    full_cols = np.concatenate([cols, rows[off]])
    order = np.lexsort((full_rows, full_cols))
    indptr = np.concatenate([[0], np.cumsum(np.bincount(full_cols, minlength=n))])
    return indptr, full_rows[order], np.concatenate([slot, slot[off]])[order]

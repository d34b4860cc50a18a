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
    """Closed-form PSD projection of a batch of symmetric 2x2 matrices (B, 2, 2) (see
    project_psd_2x2_entries); the result is exactly symmetric."""
    H = np.asarray(H, dtype=np.float64)
    a, b, c = project_psd_2x2_entries(H[..., 0, 0], 0.5 * (H[..., 0, 1] + H[..., 1, 0]), H[..., 1, 1])
    return np.stack([np.stack([a, b], axis=-1), np.stack([b, c], axis=-1)], axis=-2)


def project_psd_2x2_entries(a, b, c):
    """Closed-form PSD projection of symmetric 2x2 matrices [[a, b], [b, c]], given entry by entry
    (arrays of any one shape); returns the projected (a, b, c).

    Eigenvalues lambda_{1,2} = m +- r with m = (a + c)/2, r = hypot((a - c)/2, b). When
    lambda_2 < 0 < lambda_1, the projection keeps lambda_1 P_1, and the spectral projector is
    P_1 = (H - lambda_2 I) / (lambda_1 - lambda_2), so no eigenvector is ever formed. When
    lambda_1 <= 0 it is zero; when lambda_2 >= 0, H itself.
    """
    m = 0.5 * (a + c)
    r = np.hypot(0.5 * (a - c), b)
    lam1, lam2 = m + r, m - r
    if not (lam2 < 0.0).any():
        return a, b, c
    mixed = (lam2 < 0.0) & (lam1 > 0.0)
    scale = np.where(mixed, lam1 / np.where(mixed, lam1 - lam2, 1.0), 1.0)
    shift = np.where(mixed, lam2, 0.0)
    keep = lam1 > 0.0
    return (np.where(keep, scale * (a - shift), 0.0), np.where(keep, scale * b, 0.0),
            np.where(keep, scale * (c - shift), 0.0))


def outer_entries(a, scale):
    """The entries (h00, h01, h11), (3, k), of the symmetric 2x2 matrices scale_k a a^T, for one
    2-vector a and k factors `scale` (the barrier's n n^T and friction's t t^T blocks)."""
    return np.multiply.outer(np.array([a[0] * a[0], a[0] * a[1], a[1] * a[1]]), scale)


def outer_blocks(a, scale):
    """The same matrices scale_k a a^T whole, entry-major (2, 2, k) (the public hess kernels' form)."""
    return (a[:, None] * a)[:, :, None] * scale


# ----------------------------------------------------------------------------------------------
# IJV triplets
# ----------------------------------------------------------------------------------------------

def scatter_add_pairs(e, gx, gy, n):
    """(n, 2) array: each pair (a, b) of `e` adds (gx, gy)[j] to row a and subtracts it from row b."""
    a, b = e[:, 0], e[:, 1]
    out = np.empty((n, 2))
    out[:, 0] = np.bincount(a, gx, n) - np.bincount(b, gx, n)
    out[:, 1] = np.bincount(a, gy, n) - np.bincount(b, gy, n)
    return out


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
    """Scatter dense blocks acting on element nodes (B, m) into one IJV triplet. The blocks are
    entry-major, (2m, 2m, B): blocks[r, c] holds entry (r, c) of every element's block as one
    contiguous array, the layout the energies' kernels compute in (numpy is fast on long arrays and
    slow on many tiny blocks)."""
    rows, cols = block_entries(nodes)
    blocks = np.asarray(blocks, dtype=np.float64)
    per_element = blocks.reshape(blocks.shape[0] * blocks.shape[1], blocks.shape[2])
    return rows.ravel(), cols.ravel(), per_element.T.reshape(-1)


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

    A symmetric element block is read through its own upper triangle (np.triu_indices): entry
    (r, c), r <= c, goes to the slot of (min, max) of its two DOFs. `node_slots` (3, N) and
    `edge_slots` (10, E) hold those slots for a node's 2x2 and an edge's 4x4 block, and
    `diagonal_slots` (2N,) the slot of every (d, d). Built once per scene by `build`; read-only.
    """
    n_dofs: int
    rows: np.ndarray
    cols: np.ndarray
    node_slots: np.ndarray
    edge_slots: np.ndarray
    diagonal_slots: np.ndarray
    solver: str                     # "banded" (LAPACK dpbtrf) or "superlu"
    bandwidth: int                  # max(cols - rows)
    band_index: np.ndarray          # slot -> flat index of the (bandwidth + 1, n_dofs) band, Fortran order
    csc_indptr: np.ndarray          # the full symmetric pattern in CSC form, for SuperLU
    csc_indices: np.ndarray
    full_from_upper: np.ndarray     # slot of every stored entry of the full CSC pattern
    spring_sum: scipy.sparse.csr_matrix   # (slots, 3E): the springs' (h00, h01, h11) -> slot values
    spring_scatter: scipy.sparse.csr_matrix   # (2N, 2E): the springs' forces on node a -> per DOF

    @classmethod
    def build(cls, n_nodes, e, solver=None):
        """The pattern of N nodes and edges e; `solver` None picks "banded" or "superlu" (BAND_LIMIT)."""
        n = 2 * n_nodes
        keys = [_upper_keys(np.arange(n_nodes)[:, None], n), _upper_keys(e, n)]
        upper = np.unique(np.concatenate([k.ravel() for k in keys]))
        rows, cols = upper % n, upper // n
        node_slots, edge_slots = (np.searchsorted(upper, k) for k in keys)
        diagonal_slots = np.searchsorted(upper, np.arange(n) * (n + 1))
        bandwidth = int((cols - rows).max())
        if solver is None:
            solver = "banded" if (bandwidth + 1) * n <= BAND_LIMIT * len(upper) else "superlu"
        if solver not in ("banded", "superlu"):
            raise ValueError(f"solver must be 'banded' or 'superlu', got {solver!r}")
        band_index = (bandwidth + rows - cols) + (bandwidth + 1) * cols
        indptr, indices, full_from_upper = _full_csc(rows, cols, n)
        # stored as the index type scipy picks, which it would otherwise convert to at every to_csc
        index = np.int32 if max(n, len(indices)) <= np.iinfo(np.int32).max else np.int64
        indptr, indices = indptr.astype(index), indices.astype(index)
        spring_sum, spring_scatter = _spring_sum(edge_slots, len(upper)), _spring_scatter(e, n)
        _readonly(rows, cols, node_slots, edge_slots, diagonal_slots, band_index, indptr, indices,
                  full_from_upper, *(getattr(S, a) for S in (spring_sum, spring_scatter)
                                                   for a in ("data", "indices", "indptr")))
        return cls(n, rows, cols, node_slots, edge_slots, diagonal_slots, solver, bandwidth,
                   band_index, indptr, indices, full_from_upper, spring_sum, spring_scatter)

    def sum_spring_blocks(self, H):
        """Upper-triangle values of the sum of the springs' 4x4 blocks [[H, -H], [-H, H]], each
        spring's 2x2 H given by its entries H = (h00, h01, h11), (3, E): one sparse matrix-vector
        product with `spring_sum` (see _spring_sum)."""
        return self.spring_sum @ H.reshape(-1)

    def sum_spring_forces(self, f):
        """The (N, 2) gradient of the springs from each spring's f = dE/dx_a = -dE/dx_b, (E, 2): one
        sparse matrix-vector product with `spring_scatter`, +f to node a and -f to node b."""
        return (self.spring_scatter @ f.reshape(-1)).reshape(-1, 2)

    def node_block_slots(self, nodes):
        """The slots (3, k) of the entries (h00, h01, h11) of the 2x2 blocks of the distinct nodes
        `nodes` (of one term: an active set or the contacts, each node once)."""
        return self.node_slots.take(nodes, axis=1)

    def add_node_blocks(self, upper, slots, H):
        """upper += the nodes' 2x2 blocks, given by their entries H = (h00, h01, h11), (3, k), at
        their `slots` (node_block_slots), in place; no slot is hit twice."""
        upper[slots] += H

    def diagonal(self, d):
        """Slot values of the diagonal matrix diag(d), d one value per DOF."""
        upper = np.zeros(len(self.rows))
        upper[self.diagonal_slots] = d
        return upper

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

    def factor(self, A):
        """Factor A = matrix(...), symmetric positive definite; a band A is overwritten.

        Banded: Cholesky A = U^T U (LAPACK dpbtrf). SuperLU: in symmetric mode with a minimum-degree
        ordering of A^T + A and no off-diagonal pivoting (diag_pivot_thresh=0), which an SPD matrix
        needs none of; the factor stays as sparse as a Cholesky factor instead of the larger
        unsymmetric LU. LinAlgError (banded) or RuntimeError (SuperLU) when A is not SPD.
        """
        if self.solver == "superlu":
            return scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                            options={"SymmetricMode": True})
        factor, info = lapack.dpbtrf(A, lower=0, overwrite_ab=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"banded Cholesky failed (dpbtrf info {info}): the matrix "
                                        "is not positive definite")
        return factor

    def solve(self, factor, b):
        """A^-1 b from factor(A): two triangular solves (dpbtrs for the band)."""
        if self.solver == "superlu":
            return factor.solve(b)
        return lapack.dpbtrs(factor, b, lower=0)[0]

    def factor_solve(self, A, b):
        """x = A^-1 b for A = matrix(...) symmetric positive definite: solve(factor(A), b)."""
        return self.solve(self.factor(A), b)


def _upper_entries(size):
    """Row-major flat indices r * size + c of the upper triangle (r <= c) of a (size, size) block."""
    r, c = np.triu_indices(size)
    return r * size + c


def _upper_keys(nodes, n):
    """For the upper triangle (r <= c) of each element's (2m, 2m) block on nodes (B, m): the key
    max * n + min of its two DOFs, (n_upper, B) (a column-major index into the upper triangle)."""
    rows, cols = block_entries(nodes)
    entries = _upper_entries(2 * nodes.shape[1])
    rows, cols = rows[:, entries].T, cols[:, entries].T
    return np.maximum(rows, cols) * n + np.minimum(rows, cols)


def _spring_sum(edge_slots, n_slots):
    """The (n_slots, 3E) matrix S with S @ H.ravel() = the slot values of the sum of the springs'
    blocks [[H, -H], [-H, H]], H (3, E) = (h00, h01, h11) per spring: entry (r, c), r <= c, of a
    spring's 4x4 block is h_{i+j} (i = r % 2, j = c % 2), + on the nodes' diagonal blocks and - off
    them, so S holds +-1 at (edge_slots[entry, edge], (i + j) E + edge). Fixed per scene: filling
    the pattern is then one sparse product instead of a gather, a scaling and a scatter."""
    n_edges = edge_slots.shape[1]
    r, c = np.triu_indices(4)
    source = (r % 2 + c % 2)[:, None] * n_edges + np.arange(n_edges)
    sign = np.broadcast_to(np.where(r // 2 == c // 2, 1.0, -1.0)[:, None], edge_slots.shape)
    return scipy.sparse.csr_matrix((sign.ravel(), (edge_slots.ravel(), source.ravel())),
                                   shape=(n_slots, 3 * n_edges))


def _spring_scatter(e, n):
    """The (2N, 2E) matrix with +1 at (2a + i, 2j + i) and -1 at (2b + i, 2j + i) for spring j = (a, b)
    and axis i: applied to the springs' forces f (E, 2) raveled, it sums them per node and axis."""
    dofs = block_dofs(e)                                  # (E, 4): 2a, 2a + 1, 2b, 2b + 1
    columns = np.arange(2 * len(e)).reshape(-1, 2)
    return scipy.sparse.csr_matrix(
        (np.repeat([[1.0, 1.0, -1.0, -1.0]], len(e), axis=0).ravel(),
         (dofs.ravel(), np.concatenate([columns, columns], axis=1).ravel())), shape=(n, 2 * len(e)))


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

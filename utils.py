"""Shared helpers: PSD projection of small symmetric matrices, IJV triplets, input checks.

Every energy returns its Hessian as an IJV triplet (rows, cols, values) with DOF index
2*node + axis; the helpers here turn a batch of dense per-element blocks into such a triplet
and a triplet into a CSR matrix, so no energy repeats that bookkeeping.
"""
import numpy as np
import scipy.sparse


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


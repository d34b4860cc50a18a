"""Shared helpers: input checks, IJV triplets, and the SPD solve of the Newton system.

A Hessian is an IJV triplet (rows, cols, values), DOF index 2*node + axis, duplicates summed.
"""
import decimal
import functools
import types
from dataclasses import dataclass

import numpy as np

# ---- Input checks: one line each in the energies, a ValueError that names the argument ----------


class ParameterError(ValueError):
    """A ValueError about one parameter, `parameter` its name (the command line finds its flag)."""

    def __init__(self, parameter, message):
        super().__init__(message)
        self.parameter = parameter


def _real(value):
    """float(value) for one real number; TypeError for a bool, text, a complex number or an array,
    even where float() would convert it; OverflowError for an int beyond float64 (10**400)."""
    try:
        a = np.asarray(value)
    except ValueError:                      # a ragged nesting of lists
        raise TypeError from None
    if a.ndim != 0 or a.dtype.kind not in "iufO":   # O: an int beyond int64, a Fraction
        raise TypeError
    return float(value)                     # TypeError or ValueError where an object is no number


def _typed(value):
    """repr(value), an int beyond float64's range in 3 digits (10**400: 1.00e+400)."""
    if isinstance(value, int) and not -2 ** 1024 < value < 2 ** 1024:
        return f"{decimal.Decimal(value):.3g}"
    return repr(value)


def as_float(name, value, requirement):
    """float(value), or a ValueError saying `name` {requirement} unless it is one real number."""
    try:
        return float(value) if type(value) in (int, float) else _real(value)
    except OverflowError:
        message = f"{name} {requirement}, got {_typed(value)}, beyond float64's range"
        raise ParameterError(name, message) from None
    except (TypeError, ValueError):
        raise ParameterError(name, f"{name} {requirement}, got {value!r}") from None


def _as_array(name, a):
    """np.asarray(a); a ValueError naming `name` where numpy cannot (ragged lists)."""
    try:
        return np.asarray(a)
    except ValueError:
        message = f"{name} must be an array of numbers, got a ragged {type(a).__name__}"
        raise ParameterError(name, message) from None


def _real_array(name, a):
    """`a` as a float64 array of real numbers (an int or float dtype, or objects each _real);
    a ValueError naming `name` for booleans, text and complex numbers."""
    a = _as_array(name, a)
    if a.dtype.kind == "O":
        try:
            return np.array([_real(item) for item in a.ravel()], dtype=np.float64).reshape(a.shape)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(name, f"{name} must hold real numbers, got an object array that "
                                       f"holds another kind of object") from None
    if a.dtype.kind not in "iuf":
        raise ParameterError(name, f"{name} must hold real numbers, got dtype {a.dtype}")
    return a.astype(np.float64, copy=False)


def check_points(name, x, shape=None):
    """`x` as a finite float64 (N, 2) array, of `shape` if given."""
    x = x if isinstance(x, np.ndarray) and x.dtype == np.float64 else _real_array(name, x)
    if x.ndim != 2 or x.shape[1] != 2 or shape not in (None, x.shape):
        raise ParameterError(name, f"{name} must have shape {shape or '(N, 2)'}, got {x.shape}")
    if not np.isfinite(x).all():
        node, axis = np.argwhere(~np.isfinite(x))[0]
        raise ParameterError(name, f"{name} has a non-finite value {x[node, axis]} at node {node}")
    return x


def check_per_item(name, a, count, what="node", must_be=None):
    """`a` as a finite float64 (count,) array (one number is broadcast); with must_be "> 0" or
    ">= 0", a ValueError naming the first item that is not."""
    array = _as_array(name, a)
    if array.ndim == 0:
        a = np.full(count, as_float(name, a, "must be a number"))
    else:
        a = _real_array(name, array)
    if a.shape != (count,):
        message = f"{name} must have one value per {what} ({count}), got shape {a.shape}"
        raise ParameterError(name, message)
    if not np.isfinite(a).all():
        i = int(np.argmax(~np.isfinite(a)))
        raise ParameterError(name, f"{name} has a non-finite value {a[i]} at {what} {i}")
    if must_be is not None:
        bad = a <= 0.0 if must_be == "> 0" else a < 0.0
        if bad.any():
            i = int(np.argmax(bad))
            message = f"{name} must be {must_be} at every {what}, got {a[i]} at {what} {i}"
            raise ParameterError(name, message)
    return a


def check_vector(name, a):
    """`a` as a finite float64 2-vector of two real numbers (see _real)."""
    try:
        shape = np.shape(a)
    except ValueError:                      # a ragged nesting of lists
        shape = None
    if shape != (2,):
        got = f"shape {shape}" if shape is not None else repr(a)
        raise ParameterError(name, f"{name} must be a 2-vector, got {got}")
    try:
        a = np.array([_real(c) for c in a])
    except OverflowError:
        message = (f"{name} must be a 2-vector of numbers, got ({', '.join(map(_typed, a))}), "
                   f"beyond float64's range")
        raise ParameterError(name, message) from None
    except (TypeError, ValueError):
        raise ParameterError(name, f"{name} must be a 2-vector of numbers, got {a!r}") from None
    if not np.isfinite(a).all():
        raise ParameterError(name, f"{name} must be finite, got {a.tolist()}")
    return a


def check_unit_normal(name, n):
    """The half-space normal `n` as a 2-vector of unit length (normalize it first)."""
    n = check_vector(name, n)
    length = float(np.hypot(n[0], n[1]))
    if abs(length - 1.0) > 1e-9:
        message = f"{name} must be a unit vector, got {n.tolist()} of length {length:.6g}"
        raise ParameterError(name, message)
    return n


def check_positive(name, value, bound="> 0"):
    """`value` as a float, a finite number > 0 (bound ">= 0": or zero)."""
    requirement = f"must be a finite number {bound}"
    number = as_float(name, value, requirement)
    if not np.isfinite(number) or number < 0.0 or (number == 0.0 and bound == "> 0"):
        raise ParameterError(name, f"{name} {requirement}, got {number}")
    return number


def check_whole(name, value, minimum=1):
    """`value` as an int, a whole number >= minimum."""
    if type(value) is int and minimum <= value <= 2 ** 53:      # exact in float64: as it is
        return value
    number = as_float(name, value, f"must be a whole number >= {minimum}")
    if not np.isfinite(number) or not number.is_integer() or number < minimum:
        raise ParameterError(name, f"{name} must be a whole number >= {minimum}, got {value}")
    return int(number)


NEWTON_STARTS = ("x_n", "x_tilde")     # where Newton may start (time_integrator.newton_start)


def check_choice(name, value, choices):
    """`value` if it is one of the strings `choices`."""
    if not isinstance(value, str) or value not in choices:
        message = f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}"
        raise ParameterError(name, message)
    return value


# f_hess_term's 1/max(||vbar||, eps_v)^2 overflows float64 for eps_v below 7.5e-155, and its
# max(||vbar||, eps_v)^2 for eps_v above 1.3e154 (-1/inf: a zero Hessian, Newton stalls)
EPSV_MIN, EPSV_MAX = 1e-150, 1e150


def check_epsv(epsv):
    """eps_v as a float, a finite number in [EPSV_MIN, EPSV_MAX]."""
    epsv = check_positive("epsv", epsv)
    if not EPSV_MIN <= epsv <= EPSV_MAX:
        raise ParameterError("epsv", f"epsv must be in [{EPSV_MIN:g}, {EPSV_MAX:g}] m/s (eps_v^2 "
                                     f"in float64), got {epsv}")
    return epsv


def check_edges(name, e, n_nodes):
    """`e` as an int (E, 2) array of node indices in [0, n_nodes)."""
    e = _as_array(name, e)
    if e.ndim != 2 or e.shape[1] != 2:
        raise ParameterError(name, f"{name} must have shape (E, 2), got shape {e.shape}")
    if e.size and not np.issubdtype(e.dtype, np.integer):
        raise ParameterError(name, f"{name} must hold integer node indices, got dtype {e.dtype}")
    e = e.astype(np.int64, copy=False)
    if e.size and (e.min() < 0 or e.max() >= n_nodes):
        bad = e[(e < 0) | (e >= n_nodes)][0]
        message = f"{name} has node index {bad} outside [0, {n_nodes}) for {n_nodes} nodes"
        raise ParameterError(name, message)
    return e


def check_pair(name, value):
    """check_vector's 2-vector as a tuple, a scene parameter's form."""
    return tuple(check_vector(name, value).tolist())


# A table's checks, check(name, value) (check_params), and the solver's that every scene has.
check_nonnegative = functools.partial(check_positive, bound=">= 0")
SOLVER_CHECKS = types.MappingProxyType({
    **dict.fromkeys(("h", "k", "dhat", "kappa", "tol"), check_positive),
    "epsv": lambda name, value: check_epsv(value),
    "friction_updates": functools.partial(check_whole, minimum=0),
    **dict.fromkeys(("max_newton_iterations", "max_halvings"), check_whole),
    "newton_start": functools.partial(check_choice, choices=NEWTON_STARTS),
    "gravity": check_pair,
})


def check_params(checks, defaults, overrides, scene, aliases=types.MappingProxyType({})):
    """`defaults` updated by `overrides` (aliases renamed); p[name] = checks[name](name, p[name])
    in the table's order."""
    unknown = sorted(set(overrides) - set(defaults) - set(aliases))
    if unknown:
        raise ParameterError(unknown[0], f"unknown {scene} parameter(s): {', '.join(unknown)}; "
                                         f"valid: {', '.join(sorted([*defaults, *aliases]))}")
    p = dict(defaults)
    for name, value in overrides.items():
        real = aliases.get(name, name)
        if real != name and real in overrides:
            raise ParameterError(real, f"{real} is given twice, as {real} and as its alias {name}; "
                                       f"give one")
        p[real] = value
    for name, check in checks.items():
        p[name] = check(name, p[name])
    return p


def finite_result(what, value, arguments):
    """`value` if every entry is finite; else a ValueError (never a NaN): finite `arguments` (their
    names) overflowed float64, e.g. springs stretched to 1e308 m."""
    if not np.isfinite(value).all():
        raise ValueError(f"{what} overflowed to a non-finite value: its arguments are beyond "
                         f"float64's range (check {arguments})")
    return value


# ---- IJV triplets --------------------------------------------------------------------------------

def block_dofs(nodes):
    """The DOFs (B, 2m) of element node lists (B, m): node a has DOFs 2a (x) and 2a + 1 (y)."""
    return (2 * nodes[:, :, None] + np.arange(2)).reshape(len(nodes), 2 * nodes.shape[1])


def blocks_to_ijv(nodes, blocks):
    """The IJV triplet of dense blocks (B, 2m, 2m) on element node lists (B, m): entry (r, c) of
    block b is H[dofs[b, r], dofs[b, c]] (block_dofs)."""
    dofs = block_dofs(nodes)
    size = dofs.shape[1]
    return np.repeat(dofs, size, axis=1).ravel(), np.tile(dofs, (1, size)).ravel(), blocks.ravel()


def ijv_to_csr(ijv, n_dofs):
    """Sum an IJV triplet (duplicates added) into an (n_dofs, n_dofs) CSR matrix."""
    import scipy.sparse             # here: the banded solve, every run's, needs no sparse matrix
    rows, cols, vals = ijv
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))


def add_to_pairs(e, f, n):
    """(n, 2): each pair (a, b) of `e` adds its row of f (E, 2) to node a, subtracts it from b."""
    a, b = ((2 * e[:, i:i + 1] + np.arange(2)).ravel() for i in (0, 1))     # DOFs of a, of b
    return (np.bincount(a, f.ravel(), 2 * n) - np.bincount(b, f.ravel(), 2 * n)).reshape(n, 2)


# ---- The Newton system's SPD solve, solver.solve(H, b): read it as spsolve(H, b) ----------------

# Banded Cholesky while the band holds at most this many times the nonzeros (the lecture's grid has
# a band of about 2 n_seg); beyond it SuperLU's fill-reducing ordering is faster.
BAND_LIMIT = 40


class OutOfBand(RuntimeError):
    """A block of H couples DOFs further apart than the solver's band: refused, never a wrong p.
    Not a ValueError: the step reports it as it is (a scene that did not declare its elements)."""


@dataclass(frozen=True)
class SPDSolver:
    """Solves H p = b for the SPD Hessian H of the Incremental Potential, given as element blocks
    on one mesh: "banded", LAPACK's banded Cholesky (dpbtrf, dpbtrs), or "superlu", a sparse LU.
    The band covers every element the scene's terms produce; a block beyond it raises OutOfBand."""
    n_dofs: int
    bandwidth: int              # max |row - col| of an entry H can have
    kind: str
    node_slots: np.ndarray      # (3, N) band positions of node i's 2x2 block's upper triangle
    edges: np.ndarray           # (E, 2) the mesh's edges
    edge_slots: np.ndarray      # (10, E) band positions of edge j's 4x4 block's upper triangle
    # Kept for the run, refilled each Newton iteration: a new array of a megabyte each time costs
    # glibc an mmap, a page fault per 4 kB and a munmap (benchmarks/README.md, "Speed against")
    band: np.ndarray            # (bandwidth + 1, n_dofs), Fortran order: H's upper band (solve)
    edge_blocks: np.ndarray     # (E, 4, 4): the springs' blocks (MassSpringEnergy.hess_kernel)

    @classmethod
    def for_mesh(cls, n_nodes, e, kind=None, elements=()):
        """The solver for H with a 2x2 block per node, a 4x4 one per edge of e and the blocks of
        the element node lists (B, m) in `elements`; band 2 max(node span) + 1. `kind` None picks
        "banded" unless the band is over BAND_LIMIT times the nodes' and edges' nonzeros."""
        e = np.array(e, dtype=np.int64).reshape(-1, 2)
        span = max(np.ptp(np.asarray(nodes), axis=1).max(initial=0) for nodes in [e, *elements])
        bandwidth = int(2 * span + 1)
        nonzeros = 4 * n_nodes + 8 * len(e)
        if kind is None:
            banded = (bandwidth + 1) * 2 * n_nodes <= BAND_LIMIT * nonzeros
            kind = "banded" if banded else "superlu"
        if kind not in ("banded", "superlu"):
            raise ParameterError("kind", f"kind must be 'banded' or 'superlu', got {kind!r}")
        node_slots = _band_slots(bandwidth, np.arange(n_nodes)[:, None], *_UPPER_TRIANGLE[2])
        edge_slots = _band_slots(bandwidth, e, *_UPPER_TRIANGLE[4])
        for a in (node_slots, e, edge_slots):
            a.setflags(write=False)
        band = np.zeros((bandwidth + 1, 2 * n_nodes) if kind == "banded" else 0, order="F")
        return cls(2 * n_nodes, bandwidth, kind, node_slots, e, edge_slots, band,
                   np.zeros((len(e), 4, 4)))

    def solve(self, H, b):
        """p = H^-1 b, H the sum of a list of (nodes (B, m), blocks (B, 2m, 2m)) (blocks_to_ijv).
        np.linalg.LinAlgError when H is not positive definite."""
        if self.kind == "superlu":
            return self._superlu_solve(H, b)
        from scipy.linalg import lapack     # here: a command line refused never pays its 0.25 s
        factor, info = lapack.dpbtrf(self.upper_band(H), lower=0, overwrite_ab=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"H is not positive definite (dpbtrf info {info})")
        return lapack.dpbtrs(factor, b, lower=0)[0]

    def _superlu_solve(self, H, b):
        import scipy.sparse.linalg      # here: only a mesh with too wide a band needs SuperLU
        A = sum(ijv_to_csr(blocks_to_ijv(nodes, blocks), self.n_dofs) for nodes, blocks in H)
        try:
            return scipy.sparse.linalg.splu(A.tocsc()).solve(b)
        except RuntimeError as err:         # SuperLU: the matrix is singular
            raise np.linalg.LinAlgError(str(err)) from None

    def upper_band(self, H):
        """H's upper band in LAPACK's storage, ab[bandwidth + r - c, c] = H[r, c] for r <= c, from
        each symmetric block's upper triangle, duplicates summed; written into self.band."""
        flat = self.band.reshape(-1, order="F")         # a view: ab[k, c] at k + (bandwidth + 1) c
        flat.fill(0.0)
        for nodes, blocks in H:
            i, j = _UPPER_TRIANGLE[blocks.shape[1]]
            entries = blocks.transpose(1, 2, 0)[i, j]       # (len(i), B): entry k of every block
            np.add.at(flat, self._slots(nodes, i, j).ravel(), entries.ravel())
        return self.band

    def _slots(self, nodes, i, j):
        """_band_slots, looked up where the elements are nodes or the mesh's edges."""
        if nodes.shape[1] == 1:
            return self.node_slots.take(nodes[:, 0], axis=1)
        if nodes.shape == self.edges.shape and np.array_equal(nodes, self.edges):
            return self.edge_slots
        return _band_slots(self.bandwidth, nodes, i, j)


def _band_slots(bandwidth, nodes, i, j):
    """Where entry (i[k], j[k]) of element b's block lands in the flat upper band, (len(i), B):
    H[r, c], r <= c, at bandwidth + r + bandwidth c. OutOfBand where |r - c| > bandwidth."""
    dofs = block_dofs(nodes).T
    r, c = dofs[i], dofs[j]
    reach = np.abs(r - c).max(axis=0, initial=0)
    if reach.size and reach.max() > bandwidth:
        b = int(np.argmax(reach))
        raise OutOfBand(f"a block on nodes {nodes[b].tolist()} couples DOFs {reach[b]} apart, "
                        f"beyond the band of {bandwidth} this banded solver was built for: build "
                        f"it with every element the scene's terms produce "
                        f"(SPDSolver.for_mesh(..., elements=...)), or kind='superlu'")
    return bandwidth + np.minimum(r, c) + bandwidth * np.maximum(r, c)


_UPPER_TRIANGLE = {size: np.triu_indices(size) for size in (2, 4)}  # of 2x2 and 4x4 blocks

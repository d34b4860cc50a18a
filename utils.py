"""Shared helpers: input checks, IJV triplets, and (below its own banner) the SPD solve of the Newton system.

Every energy returns its Hessian as an IJV triplet (rows, cols, values) with DOF index 2*node + axis;
duplicate entries are summed when the matrix is built. The helpers here turn a batch of dense
per-element blocks into such a triplet, so no energy repeats that bookkeeping.
"""
import decimal
import math
import os
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
    if np.asarray(a).dtype.kind in "bUSO":
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
# Scene checks, run once by simulator.build_scene: each parameter, then the start, against what
# float64 and this machine can hold. Not the lecture's path: a student can skip this section.
# ----------------------------------------------------------------------------------------------

EPS = np.finfo(float).eps
# A node nearer the slope than ROUNDOFF_ULPS eps (max_i |x_i| + |o|) touches it as far as float64 can
# tell: x_i carries up to 2 roundings (rotation, centre), the normalized n 1, d = n . (x_i - o) 2 more
# per dot product, each at most eps/2 of its scale; 8 covers their sum with a margin.
ROUNDOFF_ULPS = 8
# The first step squares and sums its scales (||grad E||_2, the energies over the nodes): 1e150^2
# summed over the 1e8 nodes that at most fit in memory is still below float64's 1.8e308.
FLOAT64_SCALE_LIMIT = 1e150
# M + h^2 K: its smallest eigenvalue is a node mass m (K is singular along translations), its largest
# about m + h^2 k. Cholesky loses m once h^2 k / m nears 1/eps (measured: LAPACK's banded Cholesky
# fails from 0.5/eps); 0.1/eps leaves a factor 5 for the barrier's curvature at contact.
NEWTON_RATIO_LIMIT = 0.1 / EPS
# Peak resident memory of build_scene plus one step, per node, measured at n_seg 128 (banded solve,
# 7.6 KiB) to 400 (SuperLU, 8.4 to 10 KiB, growing slowly with its fill-in), rounded up.
MEMORY_PER_NODE = 16 * 1024


def check_whole(name, value, minimum):
    """Return `value` as an int; ValueError unless it is a whole number >= minimum."""
    number = as_float(name, value, f"must be a whole number >= {minimum}")
    if not np.isfinite(number) or not number.is_integer() or number < minimum:
        raise ValueError(f"{name} must be a whole number >= {minimum}, got {value}")
    return int(number)


def check_params(defaults, aliases, overrides):
    """`defaults` updated by `overrides` (each alias renamed to its parameter), every value checked."""
    unknown = sorted(set(overrides) - set(defaults) - set(aliases))
    if unknown:
        raise ValueError(f"unknown scene parameter(s): {', '.join(unknown)}; valid: "
                         f"{', '.join(sorted([*defaults, *aliases]))}")
    p = dict(defaults)
    for name, value in overrides.items():
        if aliases.get(name, name) != name and aliases[name] in overrides:
            raise ValueError(f"{aliases[name]} is given twice, as {aliases[name]} and as its alias {name}; give one")
        p[aliases.get(name, name)] = value
    if p["mass"] is not None and "rho" in overrides:
        raise ValueError(f"mass = {p['mass']} and rho = {p['rho']} are both given: the total mass is mass, "
                         f"or rho side_len^2; give one")
    for name in ("side_len", "rho", "k", "h", "dhat", "kappa", "tol") + ("mass",) * (p["mass"] is not None):
        p[name] = check_positive(name, p[name])
    p["epsv"] = check_epsv(p["epsv"])
    for name, minimum in (("n_seg", 1), ("friction_updates", 0), ("max_newton_iterations", 1), ("max_halvings", 1)):
        p[name] = check_whole(name, p[name], minimum)
    check_memory(p["n_seg"])
    for name in ("mu", "angle"):
        p[name] = as_float(name, p[name], "must be a finite number")
        if not np.isfinite(p[name]):
            raise ValueError(f"{name} must be finite, got {p[name]}")
    if p["mu"] < 0:
        raise ValueError(f"mu must be >= 0, got {p['mu']}")
    for name in ("gravity", "slope_point", "v0", "center") + ("slope",) * (p["slope"] is not None):
        p[name] = tuple(check_vector(name, p[name]).tolist())
    if p["slope"] is not None and not 0.0 < np.hypot(*p["slope"]) < np.inf:
        problem = "must be non-zero" if np.hypot(*p["slope"]) == 0.0 else "is too long to normalize"
        raise ValueError(f"slope normal {problem}, got {list(p['slope'])}")
    return p


def total_mass(p):
    """The scene's total mass M, kg: `mass` where given, else rho side_len^2 (a product: inf, never an
    OverflowError, for a size beyond float64)."""
    return p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] * p["side_len"]


def physical_memory():
    """This machine's physical memory in bytes, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(n_seg):
    """ValueError if the (n_seg + 1)^2 nodes, MEMORY_PER_NODE each, would not fit this machine's memory."""
    nodes, have = (n_seg + 1) ** 2, physical_memory()      # Python ints: exact at any n_seg
    if have is not None and MEMORY_PER_NODE * nodes > have:
        raise ValueError(f"n_seg = {float(n_seg):g} makes {decimal.Decimal(nodes):.3g} nodes, about "
                         f"{decimal.Decimal(MEMORY_PER_NODE * nodes) / 2**30:.3g} GiB of memory at "
                         f"{MEMORY_PER_NODE // 1024} KiB each, more than this machine's {have / 2**30:.3g} GiB "
                         f"(largest n_seg that fits: {math.isqrt(have // MEMORY_PER_NODE) - 1})")


def roundoff(x, o):
    """How near the slope a node can be and still be told apart from touching it: ROUNDOFF_ULPS eps
    (max_i |x_i| + |o|)."""
    return ROUNDOFF_ULPS * EPS * (float(np.hypot(x[:, 0], x[:, 1]).max()) + float(np.hypot(*o)))


def _shown(value):
    """A parameter's value as the user typed it: a number, or a vector's numbers joined by ', '."""
    return ", ".join(f"{float(a):g}" for a in value) if np.ndim(value) else f"{value:g}"


def _culprit(p, defaults, powers):
    """Of the parameters a scale grows with (name -> exponent), the one that moved it furthest from the
    lecture's scene: the largest exponent * log10(size / lecture's size) (1 for a zero vector)."""
    def size(name, of):
        if name == "mass":
            return total_mass(of)
        return float(np.hypot(*of[name])) if np.ndim(of[name]) else abs(of[name])
    def push(name):
        return powers[name] * math.log10(max(size(name, p), 1e-300) / (size(name, defaults) or 1.0))
    return max(powers, key=push)


def check_start(p, defaults, x, n, o, d):
    """ValueError, naming the parameter and its value, where the first time step from x leaves what
    float64 can do: a scale of its arithmetic above FLOAT64_SCALE_LIMIT (M total mass, D = |v0| h + |g|
    h^2 how far it moves, X = max |x|, l = side_len / n_seg, w the contact area, d the nearest node's
    distance to the slope); h^2 k / m above NEWTON_RATIO_LIMIT; the spacing l or dhat below the
    coordinates' round-off; or a node within round-off of the slope (d from BarrierEnergy.distances)."""
    h, k, v, g = p["h"], p["k"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    Mp = {"mass": 1} if p["mass"] is not None else {"rho": 1, "side_len": 2}
    M = total_mass(p)
    l, D, X = p["side_len"] / p["n_seg"], v * h + g * h * h, float(np.abs(x).max())
    scales = [("the total mass M", M, Mp), ("the kinetic energy 1/2 M |v0|^2", 0.5 * M * v * v, {**Mp, "v0": 2}),
              ("the first step's inertia term 1/2 M (|v0| h + |g| h^2)^2", 0.5 * M * D * D,
               {**Mp, "v0": 2, "h": 2, "gravity": 2}),
              ("gravity's term h^2 M |g| (max |x| + |v0| h + |g| h^2)", h * h * M * g * (X + D),
               {**Mp, "h": 2, "gravity": 1, "center": 1, "side_len": 1}),
              ("the springs' stiffness h^2 k", h * h * k, {"h": 2, "k": 1}),
              ("the springs' energy scale h^2 k l^2", h * h * k * l * l, {"h": 2, "k": 1, "side_len": 2, "n_seg": -2})]
    if d is not None:
        w, barrier = l, {"h": 2, "kappa": 1, "side_len": 1, "n_seg": -1}
        near = min(max(float(d.min()), roundoff(x, o)), p["dhat"])     # at most dhat: grows like 1/dhat
        scales += [("the barrier's energy scale h^2 kappa w dhat", h * h * p["kappa"] * w * p["dhat"],
                    {**barrier, "dhat": 1}),
                   ("the barrier's curvature h^2 kappa w (1/d + dhat/d^2) / 2",
                    h * h * p["kappa"] * w * (1 / near + p["dhat"] / near / near) / 2, {**barrier, "dhat": -1}),
                   ("friction's stiffness h mu M |g| / eps_v", h * p["mu"] * M * g / p["epsv"],
                    {**Mp, "h": 1, "mu": 1, "gravity": 1, "epsv": -1})]
    for what, value, powers in scales:
        if not value <= FLOAT64_SCALE_LIMIT:
            name = _culprit(p, defaults, powers)
            raise ValueError(f"{name} = {_shown(p[name])} is beyond float64's range in this scene: {what} would "
                             f"be {value:.3g}, above the {FLOAT64_SCALE_LIMIT:g} whose squares still sum to a "
                             f"finite number")
    m = M / len(x)
    ratio = h * h * k / m if m > 0.0 else math.inf         # a mass that underflowed to 0 resolves nothing
    if not ratio <= NEWTON_RATIO_LIMIT:
        name = _culprit(p, defaults, {"k": 1, "h": 2, "n_seg": 2, **{a: -b for a, b in Mp.items()}})
        raise ValueError(f"{name} = {_shown(p[name])}: float64 cannot resolve the Newton matrix M + h^2 K, as "
                         f"h^2 k / m = {ratio:.3g} (h = {h:g} s, k = {k:g}, node mass m = {m:.3g} kg) is "
                         f"above 0.1/eps = {NEWTON_RATIO_LIMIT:.2g}, where m is lost in the round-off of h^2 k "
                         f"(lower k or h, or raise the mass)")
    if not h * h >= np.finfo(float).tiny:
        raise ValueError(f"h = {h:g} s is too small for float64: h^2 = {h * h:.3g} underflows (h >= 1.5e-154 s)")
    scale = X + (0.0 if o is None else float(np.abs(o).max())) + D
    for what, length, powers in (("the mesh spacing side_len / n_seg", l, {"side_len": -1, "n_seg": 1}),
                                 ("dhat", p["dhat"], {"dhat": -1, "side_len": 1})):
        if not length > ROUNDOFF_ULPS * EPS * scale:
            name = _culprit(p, defaults, {"center": 1, "slope_point": 1, "v0": 1, "gravity": 1, "h": 1, **powers})
            raise ValueError(f"{name} = {_shown(p[name])} leaves {what} = {length:.3g} m below the round-off of "
                             f"the first step's coordinates, which reach {scale:.3g} m (keep every coordinate "
                             f"below {1 / (ROUNDOFF_ULPS * EPS):.2g} times the spacing and dhat)")
    if d is not None and not d.min() > roundoff(x, o):
        i = int(np.argmin(d))
        moved = np.array(p["center"]) + (p["dhat"] - d[i]) * n
        raise ValueError(f"the square starts touching or below the slope: node {i} at {x[i].tolist()} has distance "
                         f"{d[i]:.3g} m, not above the round-off of its coordinates ({roundoff(x, o):.2g} m); move "
                         f"center (now {_shown(p['center'])}) away from the slope, e.g. to "
                         f"{_shown(moved).replace(', ', ',')}, which puts that node dhat = {p['dhat']:g} m above it")


def scene_warnings(p, x, n, d):
    """What a scene's results cannot be trusted for, as sentences for the user (each stable, unresolved):
    1. One step moves the body more than its size (|v0| h + |g| h^2 > side_len): the impact happens inside
       a step, inelastic whatever the physics. The largest h that resolves is the root of |g| h^2 + |v0| h
       = side_len, as 2 L / (v + sqrt(v^2 + 4 g L)) (no cancellation, no overflow), rounded down.
    2. A square resting on the slope gains a h = (|g_t| - mu |g_n|) h of speed per step; where that is below
       tol, Newton may stop before it ever leaves static friction.
    3. Newton cannot resolve a residual below r_floor = sqrt(eps E_scale / m) / h: a step of ||p||_inf = h r
       lowers E by about m (h r)^2, which drowns in E's rounding eps E_scale, E_scale = h^2 M |g| (max|x| +
       side_len) (2.9e-7 m/s estimated on the lecture's scene, stalls measured at 1e-7 to 2.1e-7)."""
    warnings, h, v, g = [], p["h"], math.hypot(*p["v0"]), math.hypot(*p["gravity"])
    travel = v * h + g * h * h
    if travel > p["side_len"]:
        largest = 2.0 * p["side_len"] / (v + math.hypot(v, 2.0 * math.sqrt(g * p["side_len"])))
        exact = decimal.Decimal(largest)
        rounded = exact.quantize(decimal.Decimal(1).scaleb(exact.adjusted() - 2), rounding=decimal.ROUND_FLOOR)
        warnings.append(f"time step h = {h:g} s moves the square {travel:.3g} m per step, more than its "
                        f"size {p['side_len']:g} m: impacts are not resolved in time (results are qualitative "
                        f"only; use h <= {rounded.normalize():g} s)")
    if n is not None and p["mu"] > 0:
        gn = float(np.dot(p["gravity"], n))
        slide = float(np.hypot(*(np.array(p["gravity"]) - gn * n))) + p["mu"] * min(gn, 0.0)
        v_t = float(np.hypot(*(np.array(p["v0"]) - np.dot(p["v0"], n) * n)))
        if (d < p["dhat"]).any() and v_t < p["epsv"] and 0.0 < slide * h < p["tol"]:
            warnings.append(f"the square starts at rest on the slope and should slide at {slide:.3g} m/s^2, gaining "
                            f"{slide * h:.3g} m/s per step, less than tol = {p['tol']:g} m/s: Newton may stop "
                            f"before it leaves static friction (use tol <= {slide * h / 10:.2g})")
    M = total_mass(p)
    reach = float(np.abs(x).max()) + p["side_len"]
    floor = max(math.sqrt(EPS * h * h * M * g * reach / (M / len(x))), EPS * reach) / h
    if p["tol"] < floor:
        warnings.append(f"tol = {p['tol']:g} m/s is below the residual float64 can resolve in this scene (about "
                        f"{floor:.2g} m/s: E's rounding hides smaller Newton steps): Newton stops at that floor "
                        f"where it must, and log.csv flags those steps newton_stalled")
    return tuple(warnings)


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


class OutOfBand(RuntimeError):
    """A block of H couples two DOFs further apart than the band its SPDSolver was built for: the banded
    solve would drop it and return a wrong p, so it is refused. Not a ValueError: the time step reports
    it as it is (a scene that did not declare a term's elements), not as a numerical breakdown."""


@dataclass(frozen=True)
class SPDSolver:
    """Solves H p = b for the Incremental Potential's Hessian H, symmetric positive definite (M plus
    PSD-projected terms), given as element blocks on one mesh. `kind` is fixed per mesh by `for_mesh`:
    "banded", LAPACK's banded Cholesky (dpbtrf, dpbtrs) on the upper band; or "superlu", a sparse LU.

    The band rule: the band is derived once from every element a scene's terms can produce (the mesh's
    edges, and `elements` for any other coupling); a block that does not fit raises OutOfBand at once,
    never a silently wrong banded solve. (Node blocks, 2x2 on one node, always fit.)"""
    n_dofs: int
    bandwidth: int              # max |row - col| of an entry H can have
    kind: str
    node_slots: np.ndarray      # (N, 3) band positions of the upper triangle of node i's 2x2 block
    edges: np.ndarray           # (E, 2) the mesh's edges
    edge_slots: np.ndarray      # (E, 10) band positions of the upper triangle of edge j's 4x4 block

    @classmethod
    def for_mesh(cls, n_nodes, e, kind=None, elements=()):
        """The solver for H on n_nodes nodes joined by edges e (H has a 2x2 block per node and a 4x4 one per
        edge) and the element node lists (B, m) of `elements`, the other blocks the scene's terms produce;
        its band, 2 max(node span) + 1, covers them all. `kind` None picks "banded" unless the band is over
        BAND_LIMIT times the nonzeros of the nodes' and edges' blocks."""
        e = np.array(e, dtype=np.int64).reshape(-1, 2)
        spans = [np.abs(e[:, 0] - e[:, 1]).max(initial=0)]
        spans += [np.ptp(np.asarray(nodes, dtype=np.int64), axis=1).max(initial=0) for nodes in elements]
        bandwidth = int(2 * max(spans) + 1)
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
    bandwidth + r - c + (bandwidth + 1) c = bandwidth + r + bandwidth c, (B, len(i)). OutOfBand where an
    entry has |r - c| > bandwidth: its slot would be another entry's, or outside the band."""
    dofs = block_dofs(nodes)
    r, c = dofs[:, i], dofs[:, j]
    reach = np.abs(r - c).max(axis=1, initial=0)
    if reach.size and reach.max() > bandwidth:
        b = int(np.argmax(reach))
        raise OutOfBand(f"a block on nodes {nodes[b].tolist()} couples DOFs {reach[b]} apart, beyond the band "
                        f"of {bandwidth} this banded solver was built for: build it with every element the "
                        f"scene's terms produce (SPDSolver.for_mesh(..., elements=...)), or kind='superlu'")
    return bandwidth + np.minimum(r, c) + bandwidth * np.maximum(r, c)


# the (row, col) indices of the upper triangle of a 2x2 and a 4x4 element block, constants
_UPPER_TRIANGLE = {size: np.triu_indices(size) for size in (2, 4)}

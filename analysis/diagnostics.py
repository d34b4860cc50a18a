"""What a state tells beyond the step's report: contacts (d_k = n . (x_k - o) < dhat), sticking
(||(I - n n^T)(v_k - v_s)|| < eps_v) and sliding, forces, inverted cells, the energy budget, the
tip; with pushed surfaces (scene.pushed), over every surface, and the body without their rows."""
import math

import numpy as np

import BarrierEnergy
import FrictionEnergy
import time_integrator

LECTURE_TERMS = ("gravity", "spring", "barrier")     # always in the budget, 0 where absent


def energy_terms(scene):
    """The budget's potential terms: the lecture's three, then the scene's others storing energy."""
    others = tuple(name for name in scene.terms if name not in LECTURE_TERMS + ("inertia",)
                   and time_integrator.TERMS.get(name, scene.pushed).stores_energy)
    return LECTURE_TERMS + others


def term_energy(scene, name, x, targets=None):
    """One term's energy at x (J), with the hand's `targets`; 0 for a term the scene lacks."""
    if name not in scene.terms and not (name == "gravity" and scene.g is not None):
        return 0.0
    term = time_integrator.TERMS.get(name, scene.pushed)    # the kernel: the scene is checked
    lagged = time_integrator.Lagged(x, x, None, targets)
    return term.module.val_kernel(*term.args(scene, lagged, x, None))


def energies(scene, x, v, t=0.0):
    """Energy by term (J) at (x, v) and time t: kinetic, each of energy_terms, and their total."""
    out = {"kinetic": 0.5 * float(scene.m @ np.einsum("ij,ij->i", v, v))}
    at_t = scene.hand.targets(t) if scene.hand is not None else None
    out.update({name: term_energy(scene, name, x, at_t) for name in energy_terms(scene)})
    out["total"] = sum(out.values())
    return out


def hand_work(scene, x, t1, before):
    """W_hand = P_hand(x^n, targets(t1)) - P_hand(x^n, targets(t0)) (J; 0 without a hand), so that
    E^{n+1} - E^n = W_hand + W_friction - (numerical dissipation); `before` is the second term."""
    if "hand" not in scene.terms:
        return 0.0
    return term_energy(scene, "hand", x, scene.hand.targets(t1)) - before


def body(scene, x):
    """The rows of x (N, 2) that are the body's: all but pushed surfaces' own."""
    return x if scene.pushed is None else scene.pushed.body(x)


def centre_of_mass(scene, a):
    """sum_i m_i a_i / sum_i m_i of per-node vectors a (N, 2): the body's (the block's, without the
    pushed surfaces' rows)."""
    if scene.pushed is not None:
        return scene.pushed.centre_of_mass(scene, a)
    return scene.m @ a / scene.m.sum()


def tangent(scene):
    """The slope's unit tangent down to the right, (n_y, -n_x); pushed surfaces'; (1, 0) without
    either."""
    if scene.pushed is not None:
        return scene.pushed.tangent
    return np.array([1.0, 0.0]) if scene.n is None else FrictionEnergy.tangent(scene.n)


def min_distance(scene, x):
    """min_k n . (x_k - o), or to pushed surfaces (inf without either)."""
    if scene.pushed is not None:
        return scene.pushed.min_distance(x)
    if scene.n is None:
        return math.inf
    return float(BarrierEnergy.distances(x, scene.n, scene.o).min())


def contact_velocities(scene, x, v, v_s=0.0):
    """t . (v_k - v_s) (m/s) of the nodes with d_k < dhat: the relative tangential velocity along
    `tangent` (v_s 0: a still surface); pushed surfaces' (their contact_velocities)."""
    if scene.pushed is not None:
        return scene.pushed.contact_velocities(scene, x, v, v_s)
    if scene.n is None:
        return np.zeros(0)
    in_contact = BarrierEnergy.distances(x, scene.n, scene.o) < scene.dhat
    return (v[in_contact] - v_s) @ tangent(scene)


def contact_speeds(scene, x, v, v_s=0.0):
    """||(I - n n^T)(v_k - v_s)|| = |t . (v_k - v_s)| (m/s) of the nodes with d_k < dhat."""
    return np.abs(contact_velocities(scene, x, v, v_s))


def sticking_sliding(speeds, epsv):
    """(contact nodes below eps_v, contact nodes at or above it)."""
    sticking = int(np.count_nonzero(speeds < epsv))
    return sticking, len(speeds) - sticking


def at_rest(sticking, sliding):
    """At rest on the slope: in contact, every contact sticking."""
    return sticking > 0 and sliding == 0


def normal_forces(scene, x):
    """lambda_k n at every node (N, 2): BarrierEnergy.compute_mu_lambda's kernel with mu = 1; the
    sum over pushed surfaces of lambda_fk n_f with theirs."""
    if scene.pushed is not None:
        return scene.pushed.lambdas(scene, x).T @ scene.pushed.n
    if "barrier" not in scene.terms:
        return np.zeros_like(x)
    lam = BarrierEnergy.compute_mu_lambda_kernel(x, scene.n, scene.o, scene.contact_area, 1.0,
                                                 scene.dhat, scene.kappa)
    return lam[:, None] * scene.n


def tip(scene, x):
    """The tip, the node nearest the board: (its index, its distance in m)."""
    d = BarrierEnergy.distances(x, scene.n, scene.o)
    k = int(np.argmin(d))
    return k, float(d[k])


def tip_stuck(scene, x, v):
    """Whether the tip's tangential speed is below eps_v; None where it is not within dhat."""
    k, d = tip(scene, x)
    if not d < scene.dhat:
        return None
    return bool(abs(float(v[k] @ tangent(scene))) < scene.epsv)


def tip_figures(scene, x, v, t):
    """The tip's x and speed along the board at time t, the hand's speed over the last step, and the
    board's total normal force (N)."""
    k, _ = tip(scene, x)
    board = tangent(scene)
    moved = scene.hand.displacement(t) - scene.hand.displacement(max(t - scene.h, 0.0))
    drive = float(moved @ board / scene.h)
    return {"tip_x": float(x[k] @ board), "tip_speed": abs(float(v[k] @ board)),
            "drive_speed": drive, "normal_force": float((normal_forces(scene, x) @ scene.n).sum())}


def signed_areas(x, triangles):
    """Twice each triangle's signed area, (b - a) x (c - a); > 0 as the mesh is built."""
    a, b, c = x[triangles[:, 0]], x[triangles[:, 1]], x[triangles[:, 2]]
    ab, ac = b - a, c - a
    return ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]


def inverted_triangles(x, triangles):
    """How many triangles have turned over (negative signed area)."""
    return int(np.count_nonzero(signed_areas(x, triangles) < 0.0))

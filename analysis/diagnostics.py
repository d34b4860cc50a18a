"""What a state tells beyond the step's report: contacts (d_k = n . (x_k - o) < dhat), sticking
(||(I - n n^T)(v_k - v_s)|| < eps_v) and sliding, forces, inverted cells, the energy budget, the
tip; over every surface of the scene's contact, and the body without the contact's own rows."""
import math

import numpy as np

import BarrierEnergy
import time_integrator

LECTURE_TERMS = ("gravity", "spring", "barrier")     # always in the budget, 0 where absent


def energy_terms(scene):
    """The budget's potential terms: the lecture's three, then the scene's others storing energy."""
    others = tuple(name for name in scene.terms if name not in LECTURE_TERMS + ("inertia",)
                   and time_integrator.TERMS.get(name, scene.contact).stores_energy)
    return LECTURE_TERMS + others


def term_energy(scene, name, x, targets=None):
    """One term's energy at x (J), with the hand's `targets`; 0 for a term the scene lacks."""
    if name not in scene.terms and not (name == "gravity" and scene.g is not None):
        return 0.0
    term = time_integrator.TERMS.get(name, scene.contact)   # the kernel: the scene is checked
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
    """The rows of x (N, 2) that are the body's: all but the contact's own (its `rows`)."""
    return x if scene.contact is None else x[scene.contact.rows]


def centre_of_mass(scene, a):
    """sum_i m_i a_i / sum_i m_i of per-node vectors a (N, 2) over the body's rows."""
    m = body(scene, scene.m)
    return m @ body(scene, a) / m.sum()


def tangent(scene):
    """The contact's unit tangent t = (n_y, -n_x) (the slope's: down to the right); (1, 0)
    without one."""
    return np.array([1.0, 0.0]) if scene.contact is None else scene.contact.tangent


def min_distance(scene, x):
    """min_k d_k to the contact's surfaces (inf without one)."""
    return math.inf if scene.contact is None else float(scene.contact.distances(x).min())


def contact_velocities(scene, x, v, v_s=0.0):
    """t . (v_k - v_s) (m/s) of the body's nodes with d_k < dhat, surface by surface: the relative
    tangential velocity along `tangent` (v_s 0: a still surface)."""
    if scene.contact is None:
        return np.zeros(0)
    in_contact = scene.contact.distances(x) < scene.dhat    # (N,), or (surfaces, body's nodes)
    u = (body(scene, v) - v_s) @ tangent(scene)
    return u[in_contact.nonzero()[-1]]          # the node of each contact, surface by surface


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
    """sum_f lambda_fk n_f at every node k (N, 2), over the contact's surfaces f (its `lambdas`,
    (F, N), and `normals`, (F, 2)); zero without one."""
    if scene.contact is None:
        return np.zeros_like(x)
    return scene.contact.lambdas(scene, x).T @ scene.contact.normals


def lambdas(scene, x):
    """lambda_k = n . sum_f lambda_fk n_f (N,): each node's normal force along the scene's n (the
    board's, for the chalk)."""
    return normal_forces(scene, x) @ scene.n


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


def tip_figures(scene, x, v, t, lam):
    """The tip's x and speed along the board at time t, the hand's speed over the last step, and the
    board's total normal force sum_k lam_k (N), lam = `lambdas` at x."""
    k, _ = tip(scene, x)
    board = tangent(scene)
    moved = scene.hand.displacement(t) - scene.hand.displacement(max(t - scene.h, 0.0))
    drive = float(moved @ board / scene.h)
    return {"tip_x": float(x[k] @ board), "tip_speed": abs(float(v[k] @ board)),
            "drive_speed": drive, "normal_force": float(lam.sum())}


def signed_areas(x, triangles):
    """Twice each triangle's signed area, (b - a) x (c - a); > 0 as the mesh is built."""
    a, b, c = x.take(triangles.T, axis=0)      # the corners, (T, 2) each (take: x[triangles.T])
    ab, ac = b - a, c - a
    return ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]


def inverted_triangles(x, triangles):
    """How many triangles have turned over (negative signed area)."""
    return int(np.count_nonzero(signed_areas(x, triangles) < 0.0))

"""What a state tells beyond the solver's step report: contacts, sticking and sliding, forces, inverted cells.

Contact nodes are those within the barrier's reach, d_k = n . (x_k - o) < dhat. Their tangential
speed is ||(I - n n^T) v_k||, the ||vbar_k|| the friction of the lecture acts on (T is the same for
every node of a half-space); a contact node sticks when it is below eps_v (the static branch of the
mollifier f1) and slides otherwise.
"""
import math

import numpy as np

import BarrierEnergy
import FrictionEnergy
import square_mesh
import time_integrator


LECTURE_TERMS = ("gravity", "spring", "barrier")     # always in the budget (0 where a scene lacks one)


def energy_terms(scene):
    """The potential terms of the energy budget, as time_integrator.TERMS declares them: the lecture's
    three (every square's log has the same columns) and every other term the scene has that stores
    energy (the chalk's hand), in TERMS's order after them."""
    return LECTURE_TERMS + tuple(t for t in time_integrator.TERMS if t not in LECTURE_TERMS and t in scene.terms
                                 and time_integrator.TERMS[t].stores_energy)


def term_energy(scene, name, x, targets=None):
    """One term's potential energy at x (J), with the hand's `targets` (those of the state's time); a
    lecture term the scene lacks is 0, except gravity, whose scene value is always there ((0, 0) without
    gravity)."""
    if name not in scene.terms and not (name == "gravity" and scene.g is not None):
        return 0.0
    term = time_integrator.TERMS[name]      # the kernel: the scene's arrays were checked when it was built
    return term.module.val_kernel(*term.args(scene, time_integrator.Lagged(x, x, None, targets), x, None))


def targets(scene, t):
    """The hand's targets at time t, or None without a hand."""
    return scene.hand.targets(t) if scene.hand is not None else None


def energies(scene, x, v, t=0.0):
    """Mechanical energy by term (J): kinetic, then each term of energy_terms at the state (x, v) at
    time t, and their total."""
    out = {"kinetic": 0.5 * float(scene.m @ np.einsum("ij,ij->i", v, v))}
    at_t = targets(scene, t)
    out.update({name: term_energy(scene, name, x, at_t) for name in energy_terms(scene)})
    out["total"] = sum(out.values())
    return out


def hand_work(scene, x, t0, t1, before=None):
    """The work the hand's moving targets do on its springs over a step from x = x^n at t0 to t1:
    P_hand(x^n, targets(t1)) - P_hand(x^n, targets(t0)) (J; 0 without a hand), the energy the step's
    Incremental Potential (targets of t1) holds against x^n beyond E^n. With it the budget closes step
    by step: E^{n+1} - E^n = W_hand + W_friction - (implicit Euler's dissipation). `before`: P_hand(x^n,
    targets(t0)) where the caller has it (the state's own E_hand)."""
    if scene.hand is None or "hand" not in scene.terms:
        return 0.0
    before = term_energy(scene, "hand", x, targets(scene, t0)) if before is None else before
    return term_energy(scene, "hand", x, targets(scene, t1)) - before


def centre_of_mass(scene, a):
    """The mass-weighted mean sum_i m_i a_i / sum_i m_i of per-node vectors a (N, 2): x gives the centre of
    mass, v its velocity."""
    return scene.m @ a / scene.m.sum()


def tangent(scene):
    """The unit tangent of the slope, pointing down it to the right: (n_y, -n_x); (1, 0) without one."""
    if scene.n is None:
        return np.array([1.0, 0.0])
    return FrictionEnergy.tangent(scene.n)


def min_distance(scene, x):
    """The smallest node distance to the slope, min_k n . (x_k - o) (inf without a slope)."""
    return math.inf if scene.n is None else float(BarrierEnergy.distances(x, scene.n, scene.o).min())


def contact_speeds(scene, x, v):
    """Tangential speeds ||(I - n n^T) v_k|| (m/s) of the nodes with d_k < dhat (none without a slope)."""
    if scene.n is None:
        return np.zeros(0)
    in_contact = BarrierEnergy.distances(x, scene.n, scene.o) < scene.dhat
    u = v[in_contact]
    return np.abs(u @ tangent(scene))       # in 2-D, (I - n n^T) u = (u . t) t


def sticking_sliding(speeds, epsv):
    """(contact nodes below eps_v, contact nodes at or above it)."""
    sticking = int(np.count_nonzero(speeds < epsv))
    return sticking, len(speeds) - sticking


def at_rest(sticking, sliding):
    """Whether a state is at rest on the slope: in contact, and every contact node sticking. A run came to
    rest at the first state from which every later one is (recording.Track.rest_since)."""
    return sticking > 0 and sliding == 0


def normal_forces(scene, x):
    """lambda_k n at every node (N, 2), lambda_k = -w_k dP/dd (BarrierEnergy.compute_mu_lambda with mu = 1;
    its kernel: the scene's arrays were checked when it was built)."""
    if "barrier" not in scene.terms:
        return np.zeros_like(x)
    lam = BarrierEnergy.compute_mu_lambda_kernel(x, scene.n, scene.o, scene.contact_area, 1.0, scene.dhat, scene.kappa)
    return lam[:, None] * scene.n


def tip(scene, x):
    """The tip: the index of the node nearest the board (the chalk's lowest node) and its distance, m."""
    d = BarrierEnergy.distances(x, scene.n, scene.o)
    k = int(np.argmin(d))
    return k, float(d[k])


def tip_stuck(scene, x, v):
    """Whether the tip is stuck at this state (its tangential speed below eps_v), None where it is
    not within dhat of the board."""
    k, d = tip(scene, x)
    if not d < scene.dhat:
        return None
    return bool(abs(float(v[k] @ tangent(scene))) < scene.epsv)


def tip_figures(scene, x, v, t):
    """The chalk's figures of a state at time t (recording.Sample's tip_x, tip_speed, drive_speed,
    normal_force): the tip's position and speed along the board, the hand's targets' speed along it over
    the last step (of h), the board's total normal force (N)."""
    k, _ = tip(scene, x)
    tangent_ = tangent(scene)
    before = max(t - scene.h, 0.0)
    drive = (scene.hand.displacement(t) - scene.hand.displacement(before)) @ tangent_ / scene.h if t > 0 else 0.0
    normal = float((normal_forces(scene, x) @ scene.n).sum())
    return {"tip_x": float(x[k] @ tangent_), "tip_speed": abs(float(v[k] @ tangent_)),
            "drive_speed": float(drive), "normal_force": normal}


def signed_areas(x, triangles):
    """Twice the signed area of each triangle (a, b, c): (b - a) x (c - a); > 0 as the mesh is built."""
    a, b, c = (x.take(triangles[:, i], axis=0) for i in range(3))       # (take: x[triangles[:, i]], faster)
    ab, ac = b - a, c - a
    return ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]


def mesh_triangles(scene):
    """The mesh's triangles, two per cell of scene.cells (square_mesh.triangles)."""
    return square_mesh.triangles(*scene.cells)


def inverted_triangles(x, triangles):
    """How many triangles have turned over (negative signed area): the mass-spring model has no
    barrier against it, a soft square can fold at an impact."""
    return int(np.count_nonzero(signed_areas(x, triangles) < 0.0))

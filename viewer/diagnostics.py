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
import GravityEnergy
import MassSpringEnergy
import square_mesh


def energies(scene, x, v):
    """Mechanical energy by term: kinetic, gravity, spring, barrier (J), and their total."""
    out = {"kinetic": 0.5 * float(np.sum(scene.m * np.einsum("ij,ij->i", v, v))),
           "gravity": GravityEnergy.val(x, scene.m, scene.g),
           "spring": MassSpringEnergy.val(x, scene.e, scene.l2, scene.k),
           "barrier": 0.0}
    if "barrier" in scene.terms:
        out["barrier"] = BarrierEnergy.val(x, scene.n, scene.o, scene.contact_area, scene.dhat, scene.kappa)
    out["total"] = sum(out.values())
    return out


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
    """lambda_k n at every node (N, 2), lambda_k = -w_k dP/dd (BarrierEnergy.compute_mu_lambda with mu = 1)."""
    if "barrier" not in scene.terms:
        return np.zeros_like(x)
    lam = BarrierEnergy.compute_mu_lambda(x, scene.n, scene.o, scene.contact_area, 1.0, scene.dhat, scene.kappa)
    return lam[:, None] * scene.n


def signed_areas(x, triangles):
    """Twice the signed area of each triangle (a, b, c): (b - a) x (c - a); > 0 as the mesh is built."""
    a, b, c = x[triangles[:, 0]], x[triangles[:, 1]], x[triangles[:, 2]]
    ab, ac = b - a, c - a
    return ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]


def mesh_triangles(scene):
    """The mesh's triangles, two per cell (square_mesh.triangles)."""
    return square_mesh.triangles(scene.n_seg)


def inverted_triangles(x, triangles):
    """How many triangles have turned over (negative signed area): the mass-spring model has no
    barrier against it, a soft square can fold at an impact."""
    return int(np.count_nonzero(signed_areas(x, triangles) < 0.0))

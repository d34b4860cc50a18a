"""utils: IJV assembly and the Newton system's SPD solve (banded Cholesky or SuperLU, the band
derived from every declared element)."""
import numpy as np
import pytest
import scipy.sparse.linalg

import InertiaEnergy
import MassSpringEnergy
import square_mesh
import utils


def test_ijv_assembles_symmetric_matrix_of_right_size():
    x, e = square_mesh.generate(1.0, 2)
    d = x[e[:, 0]] - x[e[:, 1]]
    ijv = concat_ijv([MassSpringEnergy.hess(1.1 * x, e, np.einsum("ij,ij->i", d, d), 3.0),
                      InertiaEnergy.hess(x, x, np.ones(len(x)))])
    A = utils.ijv_to_csr(ijv, 2 * len(x))
    assert A.shape == (2 * len(x), 2 * len(x))
    # symmetric up to the order of summation: entry (i, j) and (j, i) add the same values (every
    # block is exactly symmetric), but scipy sorts each row's duplicates on its own, so two orders
    # may differ by up to (count - 1) eps times the sum of the magnitudes added (count: duplicates
    # per entry)
    count = utils.ijv_to_csr((ijv[0], ijv[1], np.ones(len(ijv[2]))), 2 * len(x)).toarray()
    magnitude = utils.ijv_to_csr((ijv[0], ijv[1], np.abs(ijv[2])), 2 * len(x)).toarray()
    asymmetry = abs(A - A.T).toarray()
    assert (asymmetry <= np.maximum(count - 1, 0) * np.finfo(float).eps * magnitude).all()
    assert all(a.ndim == 1 and len(a) == len(ijv[0]) for a in ijv)


def concat_ijv(triplets):
    """Several IJV triplets joined into one."""
    return tuple(np.concatenate(parts) for parts in zip(*triplets))


def to_csr(blocks, n_dofs):
    """The sparse matrix that element blocks [(nodes, blocks), ...] sum to."""
    return utils.ijv_to_csr(concat_ijv(utils.blocks_to_ijv(*h) for h in blocks), n_dofs)


def system_setup(n_seg, seed=0):
    """M = I, the springs' blocks on the mesh's edges and random SPD 2x2 blocks on a few nodes, as
    element blocks, and the dense matrix they sum to (built from their IJV triplets)."""
    rng = np.random.default_rng(seed)
    x, e = square_mesh.generate(1.0, n_seg)
    d = x[e[:, 0]] - x[e[:, 1]]
    y = x * 0.9 + 0.02 * rng.normal(size=x.shape)
    l2, k = np.einsum("ij,ij->i", d, d), np.full(len(e), 1e3)
    nodes = rng.choice(len(x), size=len(x) // 3, replace=False)[:, None]
    A = rng.normal(size=(len(nodes), 2, 2))
    H = [InertiaEnergy.hess_kernel(x, x, np.ones(len(x))),
         MassSpringEnergy.hess_kernel(y, e, l2, k), (nodes, A @ np.swapaxes(A, 1, 2))]
    dense = to_csr(H, 2 * len(x)).toarray()
    return x, e, H, dense


def test_upper_band_is_lapack_s_storage_of_the_summed_blocks():
    x, e, H, expected = system_setup(3)
    solver = utils.SPDSolver.for_mesh(len(x), e)
    band = solver.upper_band(H).copy()         # the solver's own array, refilled by each call
    assert band.shape == (solver.bandwidth + 1, 2 * len(x))
    # LAPACK's upper band storage: ab[u + i - j, j] = A[i, j]
    i, j = np.triu_indices(2 * len(x))
    inside = j - i <= solver.bandwidth
    r, c = i[inside], j[inside]
    assert np.allclose(band[solver.bandwidth + r - c, c], expected[r, c],
                       rtol=0, atol=1e-12 * np.abs(expected).max())
    assert not expected[i[~inside], j[~inside]].any()
    # elements given on other node lists than the mesh's edges land where their DOFs say
    reversed_edges = [(n[:, ::-1], b[:, [2, 3, 0, 1]][:, :, [2, 3, 0, 1]]) for n, b in H[1:2]]
    assert np.allclose(solver.upper_band(H[:1] + reversed_edges + H[2:]), band,
                       rtol=0, atol=1e-12 * np.abs(band).max())


def test_the_solver_s_kept_arrays_carry_nothing_over():
    """The band and the springs' blocks are one array each for the run, refilled in place: a solve
    after another system's gives what a new solver gives, and the springs' blocks written into
    edge_blocks (full of NaN before) are those of a new array."""
    x, e, H, _ = system_setup(4, seed=3)
    b = np.random.default_rng(4).normal(size=2 * len(x))
    solver = utils.SPDSolver.for_mesh(len(x), e)
    solver.solve([(nodes, 2.0 * blocks) for nodes, blocks in H], b)
    assert np.array_equal(solver.solve(H, b), utils.SPDSolver.for_mesh(len(x), e).solve(H, b))
    assert np.shares_memory(solver.upper_band(H), solver.band)
    y = x * 0.9
    l2, k = MassSpringEnergy.squared_lengths(x, e), np.full(len(e), 1e3)
    solver.edge_blocks.fill(np.nan)
    kept = MassSpringEnergy.hess_kernel(y, e, l2, k, out=solver.edge_blocks)[1]
    assert kept is solver.edge_blocks
    assert np.array_equal(kept, MassSpringEnergy.hess_kernel(y, e, l2, k)[1])


def test_both_solvers_solve_the_spd_system():
    x, e, H, dense = system_setup(6, seed=1)
    b = np.random.default_rng(2).normal(size=2 * len(x))
    solutions = [utils.SPDSolver.for_mesh(len(x), e, kind).solve(H, b)
                 for kind in ("banded", "superlu")]
    for p in solutions:
        assert np.allclose(dense @ p, b, rtol=0, atol=1e-10 * np.abs(b).max())
    assert np.allclose(solutions[0], solutions[1], rtol=1e-10, atol=1e-12)


def test_solver_choice_follows_the_band():
    x, e = square_mesh.generate(1.0, 32)
    # the lecture's numbering
    assert utils.SPDSolver.for_mesh(len(x), e).kind == "banded"
    shuffled = np.random.default_rng(0).permutation(len(x))[e]               # a wide band
    assert utils.SPDSolver.for_mesh(len(x), shuffled).kind == "superlu"
    with pytest.raises(ValueError, match="kind must be"):
        utils.SPDSolver.for_mesh(len(x), e, kind="dense")


@pytest.mark.parametrize("kind", ["banded", "superlu"])
def test_solver_refuses_a_singular_or_indefinite_matrix(kind):
    x, e = square_mesh.generate(1.0, 2)
    solver = utils.SPDSolver.for_mesh(len(x), e, kind)
    H = [(np.arange(len(x))[:, None], np.zeros((len(x), 2, 2)) - (kind == "banded") * np.eye(2))]
    with pytest.raises(np.linalg.LinAlgError):
        solver.solve(H, np.ones(2 * len(x)))


def test_add_to_pairs_sums_each_pair_s_rows():
    e = np.array([[0, 1], [1, 2], [0, 2], [2, 1]])
    f = np.arange(8.0).reshape(4, 2)
    expected = np.zeros((3, 2))
    for (a, b), row in zip(e, f):
        expected[a] += row
        expected[b] -= row
    assert np.array_equal(utils.add_to_pairs(e, f, 3), expected)      # small integers: exact


def test_a_block_outside_the_band_is_refused_and_a_declared_one_solves_as_spsolve():
    """Issue 28: a 4x4 block coupling nodes 0 and 24 of the n_seg 4 mesh lies outside the band its
    edges give (before, the banded solve then differed from spsolve by 0.89, silently). It is
    refused at once; declared as an element of the scene, the band covers it and the banded solve
    agrees with spsolve."""
    x, e, H, _ = system_setup(4, seed=3)
    rng = np.random.default_rng(4)
    A = rng.normal(size=(1, 4, 4))
    coupled = H + [(np.array([[0, 24]]), A @ np.swapaxes(A, 1, 2))]
    matrix = to_csr(coupled, 2 * len(x)).tocsc()
    b = rng.normal(size=2 * len(x))
    reference = scipy.sparse.linalg.spsolve(matrix, b)
    mesh_only = utils.SPDSolver.for_mesh(len(x), e)
    assert mesh_only.kind == "banded" and mesh_only.bandwidth == 2 * 6 + 1
    message = r"nodes \[0, 24\] couples DOFs 49 apart, beyond the band of 13"
    with pytest.raises(utils.OutOfBand, match=message):
        mesh_only.solve(coupled, b)
    declared = utils.SPDSolver.for_mesh(len(x), e, elements=[np.array([[0, 24]])])
    assert declared.kind == "banded" and declared.bandwidth == 2 * 24 + 1
    for solver in (declared, utils.SPDSolver.for_mesh(len(x), e, "superlu")):
        assert np.allclose(solver.solve(coupled, b), reference,
                           rtol=0, atol=1e-10 * np.abs(reference).max())
    # node blocks (the hand's, the barrier's) couple a node to itself only: the mesh's band
    nodes = [np.arange(20, 25)[:, None]]
    assert utils.SPDSolver.for_mesh(len(x), e, elements=nodes).bandwidth == 13

"""PSD projection, IJV assembly and the square mesh."""
import os

import numpy as np
import pytest

import InertiaEnergy
import MassSpringEnergy
import square_mesh
import utils


def eig_route(H):
    """Reference: numpy's eigen-decomposition, negative eigenvalues clamped, one matrix at a time."""
    out = []
    for A in H:
        lam, Q = np.linalg.eigh(A)
        out.append(Q @ np.diag(np.maximum(lam, 0)) @ Q.T)
    return np.array(out)


def random_symmetric(rng, count, size, scale=1.0):
    A = rng.normal(size=(count, size, size)) * scale
    return 0.5 * (A + np.swapaxes(A, 1, 2))


@pytest.mark.parametrize("size", [2, 3, 4])
@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e8])
def test_project_psd_matches_eigen_route(size, scale):
    rng = np.random.default_rng(size)
    H = random_symmetric(rng, 500, size, scale)
    P = utils.project_psd(H)
    assert np.allclose(P, eig_route(H), rtol=1e-10, atol=1e-12 * scale)
    assert np.linalg.eigvalsh(P).min() >= -1e-12 * scale          # the result is PSD
    # and exactly symmetric: the 2x2 closed form writes one b to both corners, the eigen route returns
    # (P + P^T)/2, and IEEE addition is commutative: both halves are the same operation
    assert np.array_equal(P, np.swapaxes(P, 1, 2))


@pytest.mark.parametrize("size", [2, 4])
def test_project_psd_keeps_psd_input(size):
    rng = np.random.default_rng(7)
    A = rng.normal(size=(200, size, size))
    H = A @ np.swapaxes(A, 1, 2)                                    # PSD (and some singular ones)
    H[:50] = np.outer(np.ones(size), np.ones(size))                 # rank one
    assert np.allclose(utils.project_psd(H), H, rtol=1e-12, atol=1e-12)


def test_project_psd_2x2_limits():
    H = np.array([[[0.0, 0.0], [0.0, 0.0]], [[-1.0, 0.0], [0.0, -2.0]], [[3.0, 0.0], [0.0, -1.0]],
                  [[1.0, 1.0], [1.0, 1.0]], [[1e-300, 0.0], [0.0, -1e-300]]])
    P = utils.project_psd_2x2(H)
    assert np.array_equal(P[0], np.zeros((2, 2))) and np.array_equal(P[1], np.zeros((2, 2)))
    assert np.allclose(P[2], [[3.0, 0.0], [0.0, 0.0]]) and np.allclose(P[3], H[3])
    # tiny values, no underflow; exact, as every step is exact here: r = hypot(1e-300, 0) = 1e-300,
    # lambda = +-1e-300, the scale lambda_1 / (lambda_1 - lambda_2) = 1/2, (a - lambda_2) / 2 = 1e-300
    assert P[4, 0, 0] == 1e-300 and P[4, 1, 1] == 0.0 and P[4, 0, 1] == 0.0


def test_spring_closed_form_equals_4x4_eigen_projection():
    rng = np.random.default_rng(2)
    x, e = square_mesh.generate(1.0, 3)
    d = x[e[:, 0]] - x[e[:, 1]]
    l2 = np.einsum("ij,ij->i", d, d)
    x = x * 0.8 + 0.05 * rng.normal(size=x.shape)                   # mostly compressed springs
    rows, cols, vals = MassSpringEnergy.hess(x, e, l2, 1e4, project_psd=False)
    blocks = vals.reshape(len(e), 4, 4)
    projected = MassSpringEnergy.hess(x, e, l2, 1e4)[2].reshape(len(e), 4, 4)
    assert np.allclose(projected, eig_route(blocks), rtol=1e-10, atol=1e-8)


def test_ijv_assembles_symmetric_matrix_of_right_size():
    x, e = square_mesh.generate(1.0, 2)
    d = x[e[:, 0]] - x[e[:, 1]]
    ijv = utils.concat_ijv([MassSpringEnergy.hess(1.1 * x, e, np.einsum("ij,ij->i", d, d), 3.0),
                            InertiaEnergy.hess(x, x, np.ones(len(x)))])
    A = utils.ijv_to_csr(ijv, 2 * len(x))
    assert A.shape == (2 * len(x), 2 * len(x))
    # symmetric up to the order of summation: entry (i, j) and (j, i) add the same values (every block
    # is exactly symmetric), but scipy sorts each row's duplicates on its own, so two orders may differ
    # by up to (count - 1) eps times the sum of the magnitudes added (count: duplicates per entry)
    count = utils.ijv_to_csr((ijv[0], ijv[1], np.ones(len(ijv[2]))), 2 * len(x)).toarray()
    magnitude = utils.ijv_to_csr((ijv[0], ijv[1], np.abs(ijv[2])), 2 * len(x)).toarray()
    asymmetry = abs(A - A.T).toarray()
    assert (asymmetry <= np.maximum(count - 1, 0) * np.finfo(float).eps * magnitude).all()
    assert all(a.ndim == 1 and len(a) == len(ijv[0]) for a in ijv)


def test_mesh_order_and_springs():
    x, e = square_mesh.generate(2.0, 2)
    # node i*(n_seg+1)+j at (-1 + i, -1 + j)
    # exact by construction: -1 + i * (2 / 2), integers in float64
    assert np.array_equal(x, [[-1, -1], [-1, 0], [-1, 1], [0, -1], [0, 0], [0, 1], [1, -1], [1, 0], [1, 1]])
    assert e.dtype == np.int64 and e.shape == (2 * 3 * 2 + 2 * 4, 2)
    assert e[:6].tolist() == [[0, 3], [1, 4], [2, 5], [3, 6], [4, 7], [5, 8]]       # horizontal
    assert e[6:12].tolist() == [[0, 1], [1, 2], [3, 4], [4, 5], [6, 7], [7, 8]]     # vertical
    assert e[12:].tolist() == [[0, 4], [3, 1], [1, 5], [4, 2], [3, 7], [6, 4], [4, 8], [7, 5]]
    assert len({tuple(sorted(p)) for p in e.tolist()}) == len(e)                    # no duplicates


@pytest.mark.parametrize("n_seg", [1, 4, 64])
def test_mesh_counts(n_seg):
    x, e = square_mesh.generate(1.0, n_seg)
    assert x.shape == ((n_seg + 1) ** 2, 2) and len(e) == 2 * n_seg * (n_seg + 1) + 2 * n_seg ** 2
    lengths = np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1)
    assert np.allclose(np.sort(np.unique(lengths.round(12))), [1 / n_seg, np.sqrt(2) / n_seg])


def test_obj_output(tmp_path):
    x, _ = square_mesh.generate(1.0, 2)
    path = tmp_path / "f.obj"
    square_mesh.write_obj(str(path), x, 2)
    lines = path.read_text().splitlines()
    assert lines[0] == "v -0.500000 -0.500000 0.0" and len(lines) == 9 + 8
    faces = np.array([[int(t) for t in line.split()[1:]] for line in lines if line.startswith("f")])
    assert faces.min() == 1 and faces.max() == 9
    assert os.listdir(tmp_path) == ["f.obj"]                         # no temporary left behind


def test_atomic_write_leaves_old_file_on_failure(tmp_path):
    path = tmp_path / "a.txt"
    square_mesh.write_atomic(str(path), "old")

    class Boom:
        def encode(self):
            raise RuntimeError("boom")
    with pytest.raises((RuntimeError, TypeError)):
        square_mesh.write_atomic(str(path), Boom())
    assert path.read_text() == "old" and os.listdir(tmp_path) == ["a.txt"]


# --- the Newton system's fixed pattern and its SPD solve -------------------------------------

def pattern_setup(n_seg, seed=0):
    """Random spring blocks on the mesh's edges and random 2x2 blocks on a few nodes, and the SPD
    matrix M + springs + node blocks they make (M = I)."""
    rng = np.random.default_rng(seed)
    x, e = square_mesh.generate(1.0, n_seg)
    d = x[e[:, 0]] - x[e[:, 1]]
    y = x * 0.9 + 0.02 * rng.normal(size=x.shape)
    l2, k = np.einsum("ij,ij->i", d, d), np.full(len(e), 1e3)
    spring_H = MassSpringEnergy.val_grad_hess_kernel(y, e, l2, k)[2][1]   # each spring's 2x2 H, (3, E)
    _, spring = MassSpringEnergy.hess_kernel(y, e, l2, k)                   # the same as 4x4 blocks
    nodes = rng.choice(len(x), size=len(x) // 3, replace=False)
    A = rng.normal(size=(len(nodes), 2, 2))
    node_blocks = np.moveaxis(A @ np.swapaxes(A, 1, 2), 0, -1)       # entry-major (2, 2, k)
    return x, e, nodes, spring_H, spring, node_blocks


@pytest.mark.parametrize("solver", ["banded", "superlu"])
def test_block_pattern_assembles_what_the_triplets_do(solver):
    x, e, nodes, spring_H, spring, node_blocks = pattern_setup(3)
    P = utils.BlockPattern.build(len(x), e, solver=solver)
    upper = P.sum_spring_blocks(spring_H)
    P.add_node_blocks(upper, P.node_block_slots(nodes), node_blocks[[0, 0, 1], [0, 1, 1]])
    ijv = utils.concat_ijv([utils.blocks_to_ijv(e, spring), utils.blocks_to_ijv(nodes[:, None], node_blocks)])
    expected = utils.ijv_to_csr(ijv, 2 * len(x)).toarray()
    assert np.allclose(P.to_csc(upper).toarray(), expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    assert (P.rows <= P.cols).all() and P.bandwidth == int((P.cols - P.rows).max())
    if solver == "banded":                  # LAPACK's upper band storage: ab[u + i - j, j] = A[i, j]
        band = P.matrix(upper)
        i, j = np.triu_indices(2 * len(x))
        inside = j - i <= P.bandwidth
        assert np.allclose(band[P.bandwidth + i[inside] - j[inside], j[inside]], expected[i[inside], j[inside]],
                           rtol=0, atol=1e-12 * np.abs(expected).max())
        assert not expected[i[~inside], j[~inside]].any()


def test_block_pattern_sums_the_spring_forces_per_node():
    """The springs' forces, summed per node by the pattern's fixed sparse product, are grad E_s."""
    rng = np.random.default_rng(4)
    x, e = square_mesh.generate(1.0, 5)
    y = x * 1.1 + 0.02 * rng.normal(size=x.shape)
    l2, k = np.full(len(e), 0.04), rng.uniform(1e3, 1e4, len(e))
    forces = MassSpringEnergy.val_grad_hess_kernel(y, e, l2, k)[1][1]
    expected = MassSpringEnergy.grad_kernel(y, e, l2, k)
    summed = utils.BlockPattern.build(len(x), e).sum_spring_forces(forces)
    assert summed.shape == x.shape
    assert np.allclose(summed, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_both_solvers_solve_the_spd_system():
    x, e, nodes, spring_H, spring, node_blocks = pattern_setup(6, seed=1)
    b = np.random.default_rng(2).normal(size=2 * len(x))
    solutions = []
    for solver in ("banded", "superlu"):
        P = utils.BlockPattern.build(len(x), e, solver=solver)
        upper = P.diagonal(np.ones(2 * len(x))) + P.sum_spring_blocks(spring_H)
        P.add_node_blocks(upper, P.node_block_slots(nodes), node_blocks[[0, 0, 1], [0, 1, 1]])
        dense_A = P.to_csc(upper).toarray()
        solutions.append(P.factor_solve(P.matrix(upper), b))
        assert np.allclose(dense_A @ solutions[-1], b, rtol=0, atol=1e-10 * np.abs(b).max())
    assert np.allclose(solutions[0], solutions[1], rtol=1e-10, atol=1e-12)


def test_solver_choice_follows_the_band():
    x, e = square_mesh.generate(1.0, 32)
    assert utils.BlockPattern.build(len(x), e).solver == "banded"          # the lecture's numbering
    shuffled = np.random.default_rng(0).permutation(len(x))[e]              # a wide band
    assert utils.BlockPattern.build(len(x), shuffled).solver == "superlu"
    with pytest.raises(ValueError, match="solver must be"):
        utils.BlockPattern.build(len(x), e, solver="dense")


def test_banded_solver_refuses_an_indefinite_matrix():
    x, e = square_mesh.generate(1.0, 2)
    P = utils.BlockPattern.build(len(x), e, solver="banded")
    upper = P.diagonal(-np.ones(2 * len(x)))
    with pytest.raises(np.linalg.LinAlgError, match="not positive definite"):
        P.factor_solve(P.matrix(upper), np.ones(2 * len(x)))

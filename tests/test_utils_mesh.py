"""IJV assembly, the Newton system's SPD solve and the square mesh."""
import os

import numpy as np
import pytest
import scipy.sparse.linalg

import InertiaEnergy
import MassSpringEnergy
import square_mesh
import utils
from viewer import whole_files


def eig_route(H):
    """Reference: numpy's eigen-decomposition, negative eigenvalues clamped, one matrix at a time (the
    lecture's make_PD)."""
    out = []
    for A in H:
        lam, Q = np.linalg.eigh(A)
        out.append(Q @ np.diag(np.maximum(lam, 0)) @ Q.T)
    return np.array(out)


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
    whole_files.write_atomic(str(path), square_mesh.obj_text(x, 2))
    lines = path.read_text().splitlines()
    assert lines[0] == "v -0.500000 -0.500000 0.0" and len(lines) == 9 + 8
    faces = np.array([[int(t) for t in line.split()[1:]] for line in lines if line.startswith("f")])
    assert faces.min() == 1 and faces.max() == 9
    assert os.listdir(tmp_path) == ["f.obj"]                         # no temporary left behind


def test_atomic_write_leaves_old_file_on_failure(tmp_path):
    path = tmp_path / "a.txt"
    whole_files.write_atomic(str(path), "old")

    class Boom:
        def encode(self):
            raise RuntimeError("boom")
    with pytest.raises((RuntimeError, TypeError)):
        whole_files.write_atomic(str(path), Boom())
    assert path.read_text() == "old" and os.listdir(tmp_path) == ["a.txt"]


# --- the Newton system's SPD solve ---------------------------------------------------------------

def system_setup(n_seg, seed=0):
    """M = I, the springs' blocks on the mesh's edges and random SPD 2x2 blocks on a few nodes, as element
    blocks, and the dense matrix they sum to (built from their IJV triplets)."""
    rng = np.random.default_rng(seed)
    x, e = square_mesh.generate(1.0, n_seg)
    d = x[e[:, 0]] - x[e[:, 1]]
    y = x * 0.9 + 0.02 * rng.normal(size=x.shape)
    l2, k = np.einsum("ij,ij->i", d, d), np.full(len(e), 1e3)
    nodes = rng.choice(len(x), size=len(x) // 3, replace=False)[:, None]
    A = rng.normal(size=(len(nodes), 2, 2))
    H = [InertiaEnergy.hess_kernel(x, x, np.ones(len(x))), MassSpringEnergy.hess_kernel(y, e, l2, k),
         (nodes, A @ np.swapaxes(A, 1, 2))]
    dense = utils.ijv_to_csr(utils.concat_ijv(utils.blocks_to_ijv(*h) for h in H), 2 * len(x)).toarray()
    return x, e, H, dense


def test_upper_band_is_lapack_s_storage_of_the_summed_blocks():
    x, e, H, expected = system_setup(3)
    solver = utils.SPDSolver.for_mesh(len(x), e)
    band = solver.upper_band(H)
    assert band.shape == (solver.bandwidth + 1, 2 * len(x))
    i, j = np.triu_indices(2 * len(x))              # LAPACK's upper band storage: ab[u + i - j, j] = A[i, j]
    inside = j - i <= solver.bandwidth
    assert np.allclose(band[solver.bandwidth + i[inside] - j[inside], j[inside]], expected[i[inside], j[inside]],
                       rtol=0, atol=1e-12 * np.abs(expected).max())
    assert not expected[i[~inside], j[~inside]].any()
    # elements given on other node lists than the mesh's edges land where their DOFs say
    reversed_edges = [(n[:, ::-1], b[:, [2, 3, 0, 1]][:, :, [2, 3, 0, 1]]) for n, b in H[1:2]]
    assert np.allclose(solver.upper_band(H[:1] + reversed_edges + H[2:]), band, rtol=0, atol=1e-12 * np.abs(band).max())


def test_both_solvers_solve_the_spd_system():
    x, e, H, dense = system_setup(6, seed=1)
    b = np.random.default_rng(2).normal(size=2 * len(x))
    solutions = [utils.SPDSolver.for_mesh(len(x), e, kind).solve(H, b) for kind in ("banded", "superlu")]
    for p in solutions:
        assert np.allclose(dense @ p, b, rtol=0, atol=1e-10 * np.abs(b).max())
    assert np.allclose(solutions[0], solutions[1], rtol=1e-10, atol=1e-12)


def test_solver_choice_follows_the_band():
    x, e = square_mesh.generate(1.0, 32)
    assert utils.SPDSolver.for_mesh(len(x), e).kind == "banded"             # the lecture's numbering
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


# --- the rectangle of nx x ny cells, and the square as its nx = ny = n_seg case --------------------

def lecture_square(side_len, n_seg):
    """The square as the lecture's scene script builds it, in plain loops: node i*(n_seg+1)+j at
    (-side_len/2 + i step, -side_len/2 + j step), then the horizontal, vertical and diagonal springs."""
    step, n = side_len / n_seg, n_seg
    x = [[-side_len / 2 + i * step, -side_len / 2 + j * step] for i in range(n + 1) for j in range(n + 1)]
    e = [[i * (n + 1) + j, (i + 1) * (n + 1) + j] for i in range(n) for j in range(n + 1)]
    e += [[i * (n + 1) + j, i * (n + 1) + j + 1] for i in range(n + 1) for j in range(n)]
    for i in range(n):
        for j in range(n):
            e += [[i * (n + 1) + j, (i + 1) * (n + 1) + j + 1], [(i + 1) * (n + 1) + j, i * (n + 1) + j + 1]]
    return np.array(x), np.array(e, dtype=np.int64)


@pytest.mark.parametrize("side_len, n_seg", [(1.0, 1), (1.0, 4), (0.3, 7), (2.5, 16), (1e-3, 33)])
def test_the_square_is_the_lecture_s_node_for_node_and_edge_for_edge(side_len, n_seg):
    """Bit for bit: the same IEEE operations in the same order give the same doubles (the goldens depend
    on it), and the rectangle function with nx = ny = n_seg gives the same arrays as generate."""
    x, e = square_mesh.generate(side_len, n_seg)
    x_lecture, e_lecture = lecture_square(side_len, n_seg)
    assert x.dtype == np.float64 and x.tobytes() == x_lecture.tobytes()
    assert e.dtype == np.int64 and np.array_equal(e, e_lecture)
    xr, er = square_mesh.rectangle(side_len, side_len, n_seg, n_seg, (-side_len / 2, -side_len / 2))
    assert xr.tobytes() == x.tobytes() and np.array_equal(er, e)


@pytest.mark.parametrize("nx, ny", [(18, 2), (1, 3), (5, 1), (4, 7)])
def test_rectangle_counts_order_and_spacing(nx, ny):
    width, height, origin = 0.09, 0.01, (0.25, -0.5)
    x, e = square_mesh.rectangle(width, height, nx, ny, origin)
    dx, dy = width / nx, height / ny
    assert x.shape == ((nx + 1) * (ny + 1), 2)
    assert len(e) == nx * (ny + 1) + (nx + 1) * ny + 2 * nx * ny
    i, j = np.divmod(np.arange(len(x)), ny + 1)                 # node i*(ny+1)+j at (x0 + i dx, y0 + j dy)
    assert np.allclose(x, np.stack([origin[0] + i * dx, origin[1] + j * dy], 1), rtol=0, atol=1e-15)
    lengths = np.sort(np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1))
    expected = np.sort([dx] * (nx * (ny + 1)) + [dy] * ((nx + 1) * ny) + [np.hypot(dx, dy)] * (2 * nx * ny))
    assert np.allclose(lengths, expected, rtol=1e-12, atol=0)
    assert len({tuple(sorted(p)) for p in e.tolist()}) == len(e)                # no spring twice
    chains = square_mesh.polylines(nx, ny)
    covered = sorted(tuple(sorted(p)) for c in chains for p in zip(c[:-1].tolist(), c[1:].tolist()))
    assert covered == sorted(tuple(sorted(p)) for p in e.tolist())           # the polylines draw each spring once
    tri = square_mesh.triangles(nx, ny)
    assert tri.shape == (2 * nx * ny, 3) and tri.max() == len(x) - 1
    area = 0.5 * np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
    assert np.allclose(area, dx * dy / 2, rtol=1e-9)                          # counter-clockwise, no overlap
    text = square_mesh.obj_text(x, nx, ny)
    assert text.count("v ") == len(x) and text.count("f ") == len(tri)
    with pytest.raises(ValueError, match=f"nx x ny = {nx} x {ny} cells needs {len(x)}"):
        square_mesh.obj_text(x[:-1], nx, ny)
    with pytest.raises(ValueError, match="ny must be a whole number >= 1, got 0"):
        square_mesh.rectangle(width, height, nx, 0)


def test_a_block_outside_the_band_is_refused_and_a_declared_one_solves_as_spsolve():
    """Issue 28: a 4x4 block coupling nodes 0 and 24 of the n_seg 4 mesh lies outside the band its edges
    give (before, the banded solve then differed from spsolve by 0.89, silently). It is refused at once;
    declared as an element of the scene, the band covers it and the banded solve agrees with spsolve."""
    x, e, H, _ = system_setup(4, seed=3)
    rng = np.random.default_rng(4)
    A = rng.normal(size=(1, 4, 4))
    coupled = H + [(np.array([[0, 24]]), A @ np.swapaxes(A, 1, 2))]
    matrix = utils.ijv_to_csr(utils.concat_ijv(utils.blocks_to_ijv(*h) for h in coupled), 2 * len(x)).tocsc()
    b = rng.normal(size=2 * len(x))
    reference = scipy.sparse.linalg.spsolve(matrix, b)
    mesh_only = utils.SPDSolver.for_mesh(len(x), e)
    assert mesh_only.kind == "banded" and mesh_only.bandwidth == 2 * 6 + 1
    with pytest.raises(utils.OutOfBand, match=r"nodes \[0, 24\] couples DOFs 49 apart, beyond the band of 13"):
        mesh_only.solve(coupled, b)
    declared = utils.SPDSolver.for_mesh(len(x), e, elements=[np.array([[0, 24]])])
    assert declared.kind == "banded" and declared.bandwidth == 2 * 24 + 1
    for solver in (declared, utils.SPDSolver.for_mesh(len(x), e, "superlu")):
        assert np.allclose(solver.solve(coupled, b), reference, rtol=0, atol=1e-10 * np.abs(reference).max())
    # node blocks (the hand's, the barrier's) couple a node to itself only: they keep the mesh's band
    assert utils.SPDSolver.for_mesh(len(x), e, elements=[np.arange(20, 25)[:, None]]).bandwidth == 13

"""square_mesh: the lecture's node order, the rectangle of nx x ny cells (the square its nx = ny =
n_seg case), triangles and OBJ text."""
import os

import numpy as np
import pytest

import square_mesh


def test_mesh_order_and_springs():
    x, e = square_mesh.generate(2.0, 2)
    # node i*(n_seg+1)+j at (-1 + i, -1 + j)
    # exact by construction: -1 + i * (2 / 2), integers in float64
    assert np.array_equal(x, [[-1, -1], [-1, 0], [-1, 1], [0, -1], [0, 0], [0, 1], [1, -1], [1, 0],
                              [1, 1]])
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
    path.write_text(square_mesh.obj_text(x, 2))
    lines = path.read_text().splitlines()
    assert lines[0] == "v -0.500000 -0.500000 0.0" and len(lines) == 9 + 8
    faces = np.array([[int(t) for t in line.split()[1:]] for line in lines if line.startswith("f")])
    assert faces.min() == 1 and faces.max() == 9
    assert os.listdir(tmp_path) == ["f.obj"]                         # no temporary left behind


def lecture_square(side_len, n_seg):
    """The square as the lecture's scene script builds it, in plain loops: node i*(n_seg+1)+j at
    (-side_len/2 + i step, -side_len/2 + j step), then the horizontal, vertical and diagonal
    springs."""
    step, n = side_len / n_seg, n_seg
    x = [[-side_len / 2 + i * step, -side_len / 2 + j * step]
         for i in range(n + 1) for j in range(n + 1)]
    e = [[i * (n + 1) + j, (i + 1) * (n + 1) + j] for i in range(n) for j in range(n + 1)]
    e += [[i * (n + 1) + j, i * (n + 1) + j + 1] for i in range(n + 1) for j in range(n)]
    for i in range(n):
        for j in range(n):
            e += [[i * (n + 1) + j, (i + 1) * (n + 1) + j + 1],
                  [(i + 1) * (n + 1) + j, i * (n + 1) + j + 1]]
    return np.array(x), np.array(e, dtype=np.int64)


@pytest.mark.parametrize("side_len, n_seg", [(1.0, 1), (1.0, 4), (0.3, 7), (2.5, 16), (1e-3, 33)])
def test_the_square_is_the_lecture_s_node_for_node_and_edge_for_edge(side_len, n_seg):
    """Bit for bit: the same IEEE operations in the same order give the same doubles (the goldens
    depend on it), and the rectangle function with nx = ny = n_seg gives the same arrays as
    generate."""
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
    # node i*(ny+1)+j at (x0 + i dx, y0 + j dy)
    i, j = np.divmod(np.arange(len(x)), ny + 1)
    assert np.allclose(x, np.stack([origin[0] + i * dx, origin[1] + j * dy], 1), rtol=0, atol=1e-15)
    lengths = np.sort(np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1))
    expected = np.sort([dx] * (nx * (ny + 1)) + [dy] * ((nx + 1) * ny)
                       + [np.hypot(dx, dy)] * (2 * nx * ny))
    assert np.allclose(lengths, expected, rtol=1e-12, atol=0)
    assert len({tuple(sorted(p)) for p in e.tolist()}) == len(e)                # no spring twice
    chains = square_mesh.polylines(nx, ny)
    covered = sorted(tuple(sorted(p)) for c in chains for p in zip(c[:-1].tolist(), c[1:].tolist()))
    # the polylines draw each spring once
    assert covered == sorted(tuple(sorted(p)) for p in e.tolist())
    tri = square_mesh.triangles(nx, ny)
    assert tri.shape == (2 * nx * ny, 3) and tri.max() == len(x) - 1
    ab, ac = x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]]
    # 2-D cross (numpy 2 refuses 2-vectors)
    area = 0.5 * (ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    # counter-clockwise, no overlap
    assert np.allclose(area, dx * dy / 2, rtol=1e-9)
    text = square_mesh.obj_text(x, nx, ny)
    assert text.count("v ") == len(x) and text.count("f ") == len(tri)
    with pytest.raises(ValueError, match=f"nx x ny = {nx} x {ny} cells needs {len(x)}"):
        square_mesh.obj_text(x[:-1], nx, ny)
    with pytest.raises(ValueError, match="ny must be a whole number >= 1, got 0"):
        square_mesh.rectangle(width, height, nx, 0)

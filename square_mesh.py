"""A rectangle of nx x ny cells and its springs (the lecture's square: nx = ny = n_seg), and OBJ.

Node i*(ny+1) + j sits at (x0 + i*dx, y0 + j*dy), the lecture's order. Springs: horizontal, then
vertical, then both diagonals of every cell.
"""
import numpy as np

import utils


def _cells(nx, ny):
    """(nx, ny) checked; ny None is the square's ny = nx (the functions below take n_seg alone)."""
    return utils.check_whole("nx", nx), utils.check_whole("ny", nx if ny is None else ny)


def _grid(nx, ny):
    """idx[i, j] = i*(ny+1) + j, the node at column i, row j."""
    return np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)


def rectangle(width, height, nx, ny, origin=(0.0, 0.0)):
    """Nodes (N, 2) float64 and edges (E, 2) int64 of a width x height rectangle of nx x ny cells,
    node 0 at origin = (x0, y0): node i*(ny+1) + j at (x0 + i*width/nx, y0 + j*height/ny)."""
    width, height = utils.check_positive("width", width), utils.check_positive("height", height)
    nx, ny = _cells(nx, ny)
    x0, y0 = utils.check_vector("origin", origin).tolist()
    xs = x0 + np.arange(nx + 1) * (width / nx)
    ys = y0 + np.arange(ny + 1) * (height / ny)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    idx = _grid(nx, ny)
    horizontal = np.stack([idx[:-1, :], idx[1:, :]], -1).reshape(-1, 2)
    vertical = np.stack([idx[:, :-1], idx[:, 1:]], -1).reshape(-1, 2)
    diagonals = np.stack([np.stack([idx[:-1, :-1], idx[1:, 1:]], -1),
                          np.stack([idx[1:, :-1], idx[:-1, 1:]], -1)], axis=2).reshape(-1, 2)
    edges = np.concatenate([horizontal, vertical, diagonals]).astype(np.int64)
    return np.stack([X.ravel(), Y.ravel()], axis=1), edges


def generate(side_len, n_seg):
    """Nodes and edges of the lecture's square of n_seg x n_seg cells, centred at the origin."""
    side_len = utils.check_positive("side_len", side_len)
    n_seg = utils.check_whole("n_seg", n_seg)
    return rectangle(side_len, side_len, n_seg, n_seg, (-side_len / 2.0, -side_len / 2.0))


def triangles(nx, ny=None):
    """Two triangles per cell (0-based node indices); `triangles(n_seg)` is the square's."""
    idx = _grid(*_cells(nx, ny))
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    return np.stack([np.stack([a, b, c], -1), np.stack([a, c, d], -1)], axis=2).reshape(-1, 3)


def polylines(nx, ny=None):
    """Node chains that cover every spring once: rows, columns and both families of diagonals, so
    a frame takes O(nx + ny) polyline calls; `polylines(n_seg)` is the square's."""
    nx, ny = _cells(nx, ny)
    idx = _grid(nx, ny)
    chains = [idx[:, j] for j in range(ny + 1)] + [idx[i, :] for i in range(nx + 1)]
    chains += [np.diagonal(idx, k) for k in range(-nx + 1, ny)]
    chains += [np.diagonal(idx[:, ::-1], k) for k in range(-nx + 1, ny)]
    return chains


def obj_text(x, nx, ny=None):
    """The OBJ text of one frame: a vertex per node (z = 0), two triangles per cell;
    `obj_text(x, n_seg)` is the square's."""
    x = utils.check_points("x", x)
    nx, ny = _cells(nx, ny)
    if len(x) != (nx + 1) * (ny + 1):
        cells = (nx + 1) * (ny + 1)
        raise ValueError(f"x has {len(x)} nodes but nx x ny = {nx} x {ny} cells needs {cells}")
    faces = triangles(nx, ny) + 1
    # one C-level format call per block of lines, no Python loop over nodes or faces
    vertices = ("v %.6f %.6f 0.0\n" * len(x)) % tuple(x.ravel().tolist())
    return vertices + ("f %d %d %d\n" * len(faces)) % tuple(faces.ravel().tolist())

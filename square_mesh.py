"""A rectangle of nx x ny cells and its springs (the lecture's square: nx = ny = n_seg), and OBJ output.

Node i*(ny+1) + j sits at (x0 + i*dx, y0 + j*dy), the lecture's order (for the square, x0 = y0 =
-side_len/2 and dx = dy = side_len/n_seg). Springs: horizontal, then vertical, then both diagonals of
every cell.
"""

import numpy as np

import utils


def _node_index(i, j, ny):
    return i * (ny + 1) + j


def _cells(nx, ny):
    """(nx, ny) checked; ny None is the square's ny = nx (the functions below take n_seg alone)."""
    if ny is None:
        return (utils.check_whole("n_seg", nx, 1),) * 2
    return utils.check_whole("nx", nx, 1), utils.check_whole("ny", ny, 1)


def rectangle(width, height, nx, ny, origin=(0.0, 0.0)):
    """Nodes (N, 2) float64 and edges (E, 2) int64 of a width x height rectangle of nx x ny cells with
    its corner node 0 at origin = (x0, y0): node i*(ny+1) + j at (x0 + i*dx, y0 + j*dy), dx = width/nx,
    dy = height/ny; N = (nx+1)(ny+1), E = nx(ny+1) + (nx+1)ny + 2 nx ny."""
    width, height = utils.check_positive("width", width), utils.check_positive("height", height)
    nx, ny = _cells(nx, ny)
    x0, y0 = utils.check_vector("origin", origin).tolist()
    xs = x0 + np.arange(nx + 1) * (width / nx)
    ys = y0 + np.arange(ny + 1) * (height / ny)
    I, J = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="ij")
    x = np.stack([xs[I.ravel()], ys[J.ravel()]], axis=1)

    hi, hj = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="ij")          # (i, j)-(i+1, j)
    horizontal = np.stack([_node_index(hi, hj, ny), _node_index(hi + 1, hj, ny)], -1).reshape(-1, 2)
    vi, vj = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="ij")          # (i, j)-(i, j+1)
    vertical = np.stack([_node_index(vi, vj, ny), _node_index(vi, vj + 1, ny)], -1).reshape(-1, 2)
    qi, qj = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")              # cell (i, j)
    diagonals = np.stack([
        np.stack([_node_index(qi, qj, ny), _node_index(qi + 1, qj + 1, ny)], -1),
        np.stack([_node_index(qi + 1, qj, ny), _node_index(qi, qj + 1, ny)], -1),
    ], axis=2).reshape(-1, 2)
    return x, np.concatenate([horizontal, vertical, diagonals]).astype(np.int64)


def generate(side_len, n_seg):
    """Nodes (N, 2) float64 and edges (E, 2) int64 of the lecture's square mesh, centred at the origin:
    the rectangle of n_seg x n_seg cells of side side_len with its corner at (-side_len/2, -side_len/2)."""
    side_len = utils.check_positive("side_len", side_len)
    n_seg = utils.check_whole("n_seg", n_seg, 1)
    return rectangle(side_len, side_len, n_seg, n_seg, (-side_len / 2.0, -side_len / 2.0))


def triangles(nx, ny=None):
    """Two triangles per cell (0-based node indices), for rendering and OBJ faces; `triangles(n_seg)`
    is the square's."""
    nx, ny = _cells(nx, ny)
    qi, qj = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    a, b = _node_index(qi, qj, ny), _node_index(qi + 1, qj, ny)
    c, d = _node_index(qi + 1, qj + 1, ny), _node_index(qi, qj + 1, ny)
    return np.stack([np.stack([a, b, c], -1), np.stack([a, c, d], -1)], axis=2).reshape(-1, 3)


def polylines(nx, ny=None):
    """Node chains that together cover every spring once: the rows, the columns and the two families
    of diagonals (i - j and i + j constant), so a frame is drawn with O(nx + ny) polyline calls;
    `polylines(n_seg)` is the square's."""
    nx, ny = _cells(nx, ny)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)     # idx[i, j] = i*(ny+1)+j
    flipped = idx[:, ::-1]
    chains = [idx[:, j] for j in range(ny + 1)] + [idx[i, :] for i in range(nx + 1)]
    chains += [np.diagonal(idx, k) for k in range(-nx + 1, ny)]
    chains += [np.diagonal(flipped, k) for k in range(-nx + 1, ny)]
    return chains


def obj_text(x, nx, ny=None):
    """The OBJ text of one frame: a vertex line per node (z = 0), two triangles per cell;
    `obj_text(x, n_seg)` is the square's."""
    x = utils.check_points("x", x)
    nx, ny = _cells(nx, ny)
    if len(x) != (nx + 1) * (ny + 1):
        cells = f"n_seg = {nx}" if nx == ny else f"nx x ny = {nx} x {ny} cells"
        raise ValueError(f"x has {len(x)} nodes but {cells} needs {(nx + 1) * (ny + 1)}")
    faces = triangles(nx, ny) + 1
    # one C-level format call per block of lines, no Python loop over nodes or faces
    vertices = ("v %.6f %.6f 0.0\n" * len(x)) % tuple(x.ravel().tolist())
    return vertices + ("f %d %d %d\n" * len(faces)) % tuple(faces.ravel().tolist())

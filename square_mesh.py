"""A square of (n_seg + 1)^2 nodes and its springs, and OBJ output of a frame.

Node i*(n_seg+1) + j sits at (-side_len/2 + i*side_len/n_seg, -side_len/2 + j*side_len/n_seg), the
lecture's order. Springs: horizontal, then vertical, then both diagonals of every cell.
"""

import numpy as np

import utils


def _node_index(i, j, n_seg):
    return i * (n_seg + 1) + j


def _check_n_seg(n_seg):
    return utils.check_whole("n_seg", n_seg, 1)


def generate(side_len, n_seg):
    """Nodes (N, 2) float64 and edges (E, 2) int64 of the lecture's square mesh, centred at the origin."""
    side_len = utils.check_positive("side_len", side_len)
    n_seg = _check_n_seg(n_seg)
    coords = -side_len / 2.0 + np.arange(n_seg + 1) * (side_len / n_seg)
    I, J = np.meshgrid(np.arange(n_seg + 1), np.arange(n_seg + 1), indexing="ij")
    x = np.stack([coords[I.ravel()], coords[J.ravel()]], axis=1)

    ci, cj = np.meshgrid(np.arange(n_seg), np.arange(n_seg + 1), indexing="ij")
    horizontal = np.stack([_node_index(ci, cj, n_seg), _node_index(ci + 1, cj, n_seg)], -1).reshape(-1, 2)
    vertical = np.stack([_node_index(cj, ci, n_seg), _node_index(cj, ci + 1, n_seg)], -1)
    vertical = vertical.transpose(1, 0, 2).reshape(-1, 2)
    qi, qj = np.meshgrid(np.arange(n_seg), np.arange(n_seg), indexing="ij")
    diagonals = np.stack([
        np.stack([_node_index(qi, qj, n_seg), _node_index(qi + 1, qj + 1, n_seg)], -1),
        np.stack([_node_index(qi + 1, qj, n_seg), _node_index(qi, qj + 1, n_seg)], -1),
    ], axis=2).reshape(-1, 2)
    return x, np.concatenate([horizontal, vertical, diagonals]).astype(np.int64)


def triangles(n_seg):
    """Two triangles per cell (0-based node indices), for rendering and OBJ faces."""
    n_seg = _check_n_seg(n_seg)
    qi, qj = np.meshgrid(np.arange(n_seg), np.arange(n_seg), indexing="ij")
    a, b = _node_index(qi, qj, n_seg), _node_index(qi + 1, qj, n_seg)
    c, d = _node_index(qi + 1, qj + 1, n_seg), _node_index(qi, qj + 1, n_seg)
    return np.stack([np.stack([a, b, c], -1), np.stack([a, c, d], -1)], axis=2).reshape(-1, 3)


def polylines(n_seg):
    """Node chains that together cover every spring once: the rows, the columns and the two families
    of diagonals (i - j and i + j constant), so a frame is drawn with O(n_seg) polyline calls."""
    n_seg = _check_n_seg(n_seg)
    idx = np.arange((n_seg + 1) ** 2).reshape(n_seg + 1, n_seg + 1)     # idx[i, j] = i*(n_seg+1)+j
    flipped = idx[:, ::-1]
    chains = [idx[:, j] for j in range(n_seg + 1)] + [idx[i, :] for i in range(n_seg + 1)]
    chains += [np.diagonal(idx, k) for k in range(-n_seg + 1, n_seg)]
    chains += [np.diagonal(flipped, k) for k in range(-n_seg + 1, n_seg)]
    return chains


def obj_text(x, n_seg):
    """The OBJ text of one frame: a vertex line per node (z = 0), two triangles per cell."""
    x = utils.check_points("x", x)
    n_seg = _check_n_seg(n_seg)
    if len(x) != (n_seg + 1) ** 2:
        raise ValueError(f"x has {len(x)} nodes but n_seg = {n_seg} needs {(n_seg + 1) ** 2}")
    faces = triangles(n_seg) + 1
    # one C-level format call per block of lines, no Python loop over nodes or faces
    vertices = ("v %.6f %.6f 0.0\n" * len(x)) % tuple(x.ravel().tolist())
    return vertices + ("f %d %d %d\n" * len(faces)) % tuple(faces.ravel().tolist())

"""log.csv: one row per step (and one for t = 0), appended and flushed as each step ends.

Each row goes to the file in one write before that step's frame is saved, so the file is never more
than one row (or one frame stride) ahead of the frames on disk and never holds half a row: a write
that fails part way (a full disk) is cut back to the last whole row (viewer.whole_files.LineFile).
"""
COLUMNS = ["step", "t", "wall_s", "com_x", "com_y", "v_tangential", "newton_iterations", "residual",
           "newton_stalled", "alpha_min", "line_search_steps", "min_distance", "friction_updates", "friction_converged",
           "contacts_sticking", "contacts_sliding", "inverted_triangles", "E_kinetic", "E_gravity", "E_spring",
           "E_barrier", "E_total", "W_friction", "D_numerical"]


def row(sample):
    """The CSV line of one Sample (see recording.Sample); the solver's figures are empty at t = 0."""
    s, rep, E = sample, sample.report, sample.energies
    if rep is None:
        solver = ["0", "", "0", "", "0", f"{s.min_distance:.9g}", "0", "1"]
    else:
        solver = [str(rep.newton_iterations), f"{rep.residual:.3e}", str(int(rep.stalled)),
                  f"{min(rep.alphas, default=1.0):.6g}",
                  str(len(rep.alphas)), f"{rep.min_distance:.9g}", str(rep.friction_updates),
                  str(int(rep.friction_converged))]
    return ",".join([str(s.step), f"{s.t:.6f}", f"{s.wall:.6f}", f"{s.com[0]:.9f}", f"{s.com[1]:.9f}",
                     f"{s.v_tangential:.9f}"] + solver + [str(s.sticking), str(s.sliding), str(s.inverted)]
                    + [f"{E[k]:.9g}" for k in ("kinetic", "gravity", "spring", "barrier", "total")]
                    + [f"{s.friction_work:.9g}", f"{s.numerical_dissipation:.9g}"])

"""The energies' public val + grad + hess and the CSR matrix M + h^2 sum hess, against one
scipy.sparse.linalg.splu factorization-and-solve of it (target: ratio < 0.5), on the square
stretched by 2 %, its bottom row 5 mm above flat ground and sliding (benchmarks/README.md).
"""
import argparse
import os
import statistics
import sys
import timeit

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

import BarrierEnergy
import FrictionEnergy
import GravityEnergy
import InertiaEnergy
import MassSpringEnergy
import square_mesh
from benchmarks import tables

H = 0.01
COLUMNS = ["n_seg", "nodes", "springs", "inertia_ms", "spring_ms", "gravity_ms", "barrier_ms",
           "friction_ms", "csr_ms", "energies_total_ms", "factor_solve_ms", "ratio"]
HEAD = ("n_seg  nodes springs   inertia    spring   gravity   barrier  friction       csr   sum ms"
        "    LU ms  ratio")
ROW = ("{n_seg:5} {nodes:6} {springs:7} {inertia_ms:9.2f} {spring_ms:9.2f} {gravity_ms:9.2f} "
       "{barrier_ms:9.2f} {friction_ms:9.2f} {csr_ms:9.2f} {energies_total_ms:8.2f} "
       "{factor_solve_ms:8.2f} {ratio:6.2f}")
NOTE = ("times in ms, medians; each term is its public val + grad + hess; csr: the CSR matrix "
        "from the triplets; LU: one splu factorization-and-solve; target ratio < 0.5")


def terms(n_seg):
    """{term: (its module, its arguments)} on the benchmark's configuration."""
    x0, e = square_mesh.generate(1.0, n_seg)
    l2 = np.sum((x0[e[:, 0]] - x0[e[:, 1]]) ** 2, axis=1)
    x = 1.02 * x0
    n, o = np.array([0.0, 1.0]), np.array([0.0, x[:, 1].min() - 0.005])
    m, area = np.full(len(x), 1000.0 / len(x)), np.full(len(x), 1.0 / n_seg)
    mu_lambda = BarrierEnergy.compute_mu_lambda(x, n, o, area, 0.11)
    assert (mu_lambda > 0).sum() == n_seg + 1, "the bottom row must be in contact"
    v = np.tile([0.4, -0.04], (len(x), 1))
    return {"inertia": (InertiaEnergy, (x, x + H * v, m)),
            "spring": (MassSpringEnergy, (x, e, l2, np.full(len(e), 2e4))),
            "gravity": (GravityEnergy, (x, m)), "barrier": (BarrierEnergy, (x, n, o, area)),
            "friction": (FrictionEnergy, (v, mu_lambda, H, n))}


def median_ms(f, repeats):
    """The median wall time of `repeats` calls of f, in ms (garbage collection on, as in a run)."""
    return 1e3 * statistics.median(timeit.repeat(f, setup="gc.enable()", repeat=repeats, number=1))


def measure(n_seg, repeats):
    """One row: each term's val + grad + hess, the CSR matrix, one factorization-and-solve."""
    print(f"n_seg {n_seg} ...", file=sys.stderr, flush=True)
    configuration, grads, hessians = terms(n_seg), [], []
    x, e = configuration["spring"][1][:2]
    row = {"n_seg": n_seg, "nodes": len(x), "springs": len(e)}
    for name, (module, args) in configuration.items():
        def evaluate():
            return module.val(*args), module.grad(*args), module.hess(*args)
        row[f"{name}_ms"] = median_ms(evaluate, repeats)
        _, grad, (rows, cols, vals) = evaluate()
        grads.append(grad)
        hessians.append((rows, cols, vals if name == "inertia" else H * H * vals))
    rows, cols, vals = (np.concatenate(parts) for parts in zip(*hessians))
    n_dofs = 2 * len(x)

    def csr():
        return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))
    row["csr_ms"] = median_ms(csr, repeats)
    A, b = csr().tocsc(), sum(grads).ravel()

    def factor_solve():
        return scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                        options={"SymmetricMode": True}).solve(b)
    row["factor_solve_ms"] = median_ms(factor_solve, repeats)
    row["energies_total_ms"] = sum(row[c] for c in COLUMNS[3:9])
    row["ratio"] = row["energies_total_ms"] / row["factor_solve_ms"]
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.energies", description=__doc__)
    ap.add_argument("--quick", action="store_true", help="n_seg 8 and 16, three repeats")
    ap.add_argument("--out", help="folder for energies.csv (default: see benchmarks/README.md)")
    args = ap.parse_args(argv)
    sizes, repeats = ((8, 16), 3) if args.quick else ((64, 128), 7)
    rows = [measure(n_seg, repeats) for n_seg in sizes]
    print("\n".join([HEAD] + [ROW.format(**row) for row in rows] + [NOTE]))
    out = tables.output_folder(args.out, not args.quick, "energies")
    tables.write_csv(os.path.join(out, "energies.csv"), COLUMNS, rows, digits=4)
    return rows


if __name__ == "__main__":
    main()

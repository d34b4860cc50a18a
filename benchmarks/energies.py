"""Cost of the energies against the floor of a Newton iteration, one sparse factorization.

On the generated square (n_seg = 64: 4225 nodes, 16512 springs; n_seg = 128: 16641 nodes, 65792
springs), stretched by 2 % and with its bottom row 5 mm above flat ground (so the barrier and friction
are active there) and moving along it, this times the public val + grad + hess of every term, then
building the CSR matrix M + h^2 sum hess from their IJV triplets, and compares the sum with one
factorization-and-solve of that matrix by scipy.sparse.linalg.splu (symmetric mode, minimum-degree
ordering of A^T + A), a sparse direct solve as a notebook would call it. (The simulator itself calls
the unchecked kernels and solves with utils.SPDSolver; see benchmarks.speed.) Target: ratio < 0.5.

    python -m benchmarks.energies            # n_seg 64 and 128
    python -m benchmarks.energies --quick    # n_seg 8 and 16, a smoke run

The full run writes energies.csv into benchmarks/results/ (what benchmarks/README.md quotes), --quick
into a new temporary folder, --out DIR into DIR.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import benchmarks         # noqa: E402
from benchmarks import tables  # noqa: E402

import BarrierEnergy      # noqa: E402  (the project's flat modules, after the path is set)
import FrictionEnergy     # noqa: E402
import GravityEnergy      # noqa: E402
import InertiaEnergy      # noqa: E402
import MassSpringEnergy   # noqa: E402
import square_mesh        # noqa: E402

H = 0.01
COLUMNS = ["n_seg", "nodes", "springs", "inertia_ms", "spring_ms", "gravity_ms", "barrier_ms", "friction_ms",
           "csr_ms", "energies_total_ms", "factor_solve_ms", "ratio"]


def setup(n_seg):
    """Positions, springs and contact data of the benchmark configuration."""
    x0, e = square_mesh.generate(1.0, n_seg)
    diff = x0[e[:, 0]] - x0[e[:, 1]]
    l2 = np.einsum("ij,ij->i", diff, diff)
    x = 1.02 * x0
    n = np.array([0.0, 1.0])                          # flat ground, 5 mm below the whole bottom row
    o = np.array([0.0, x[:, 1].min() - 0.005])
    m = np.full(len(x), 1000.0 / len(x))
    area = np.full(len(x), 1.0 / n_seg)
    mu_lambda = BarrierEnergy.compute_mu_lambda(x, n, o, area, 0.11)
    v = np.tile([0.4, -0.04], (len(x), 1))
    return dict(x=x, x_tilde=x + H * v, e=e, l2=l2, k=np.full(len(e), 2e4), m=m, n=n, o=o, area=area,
                mu_lambda=mu_lambda, v=v)


def terms(c):
    """name -> callable returning (val, grad, hess) of the term at the configuration."""
    return {
        "inertia": lambda: tuple(f(c["x"], c["x_tilde"], c["m"]) for f in
                                 (InertiaEnergy.val, InertiaEnergy.grad, InertiaEnergy.hess)),
        "spring": lambda: tuple(f(c["x"], c["e"], c["l2"], c["k"]) for f in
                                (MassSpringEnergy.val, MassSpringEnergy.grad, MassSpringEnergy.hess)),
        "gravity": lambda: tuple(f(c["x"], c["m"]) for f in (GravityEnergy.val, GravityEnergy.grad, GravityEnergy.hess)),
        "barrier": lambda: tuple(f(c["x"], c["n"], c["o"], c["area"]) for f in
                                 (BarrierEnergy.val, BarrierEnergy.grad, BarrierEnergy.hess)),
        "friction": lambda: tuple(f(c["v"], c["mu_lambda"], H, c["n"]) for f in
                                  (FrictionEnergy.val, FrictionEnergy.grad, FrictionEnergy.hess)),
    }


def median_ms(f, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def measure(n_seg, repeats):
    c = setup(n_seg)
    assert (c["mu_lambda"] > 0).sum() == n_seg + 1, "the bottom row must be in contact"
    row = {"n_seg": n_seg, "nodes": len(c["x"]), "springs": len(c["e"])}
    results = {}
    for name, f in terms(c).items():
        row[f"{name}_ms"] = median_ms(f, repeats)
        results[name] = f()
    # H = M + h^2 sum hess P: the potentials' values scaled by h^2, all triplets joined
    hessians = [results["inertia"][2]] + [(rows, cols, H * H * vals) for rows, cols, vals in
                                          (results[t][2] for t in ("spring", "gravity", "barrier", "friction"))]
    rows, cols, vals = (np.concatenate(parts) for parts in zip(*hessians))
    n_dofs = 2 * len(c["x"])

    def csr():
        return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))
    row["csr_ms"] = median_ms(csr, repeats)
    A = csr().tocsc()
    b = sum(results[t][1] for t in results).ravel()

    def factor_solve():
        return scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                        options={"SymmetricMode": True}).solve(b)
    row["factor_solve_ms"] = median_ms(factor_solve, repeats)
    row["energies_total_ms"] = sum(row[f"{t}_ms"] for t in results) + row["csr_ms"]
    row["ratio"] = row["energies_total_ms"] / row["factor_solve_ms"]
    return row


def format_table(rows):
    head = f"{'n_seg':>5} {'nodes':>6} {'springs':>7} " + " ".join(f"{c[:-3]:>9}" for c in COLUMNS[3:9]) \
        + f" {'sum ms':>8} {'LU ms':>8} {'ratio':>6}"
    lines = [head]
    for r in rows:
        lines.append(f"{r['n_seg']:>5} {r['nodes']:>6} {r['springs']:>7} "
                     + " ".join(f"{r[c]:>9.2f}" for c in COLUMNS[3:9])
                     + f" {r['energies_total_ms']:>8.2f} {r['factor_solve_ms']:>8.2f} {r['ratio']:>6.2f}")
    lines.append("times in ms, medians; each term is its public val + grad + hess; csr: the CSR matrix "
                 "from the triplets; LU: one splu factorization-and-solve; target ratio < 0.5")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="n_seg 8 and 16, three repeats")
    ap.add_argument("--out", help="folder for energies.csv (default: benchmarks/results/ for the full run, "
                                  "a new temporary folder with --quick)")
    args = ap.parse_args(argv)
    sizes, repeats = ((8, 16), 3) if args.quick else ((64, 128), 7)
    rows = []
    for n_seg in sizes:
        print(f"n_seg {n_seg} ...", file=sys.stderr, flush=True)
        rows.append(measure(n_seg, repeats))
    print(format_table(rows))
    path = os.path.join(benchmarks.output_folder(args.out, not args.quick, "energies"), "energies.csv")
    tables.write_csv(path, COLUMNS, rows, digits=4)
    print(f"wrote {path}", file=sys.stderr)
    return rows


if __name__ == "__main__":
    main()

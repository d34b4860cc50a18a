"""Error against run time over h, the Newton tolerance and the friction mode (lagged, or fully
implicit: Algorithm 5), on the cases of closed_forms.py and the full scene (benchmarks/README.md).
"""
import argparse
import itertools
import math
import os
import sys
import time
from collections import namedtuple

import numpy as np

import closed_forms as cases
import simulator
import time_integrator
from benchmarks import plot, tables
from scenes import square

HS = (0.04, 0.02, 0.01, 0.005, 0.0025)
QUICK_HS = (0.04, 0.02)
TOLS = (1e-2, 1e-4, 1e-6)
FIXED_POINT_CAP = 20
MODES = {"lagged": 0, "implicit": FIXED_POINT_CAP}
REFERENCE_H, REFERENCE_TOL = 0.000625, 1e-6  # the full scene's reference: 8x below the smallest h
COLUMNS = ["case", "error_measure", "friction", "tol", "h", "steps", "error", "observed_order",
           "wall_per_sim_second", "newton_per_step", "friction_updates_per_step",
           "unconverged_steps"]
HEAD = "friction     tol       h      error  order wall s/sim s newton/step updates/step"
ROW = ("{friction:9s} {tol:6.0e} {h:7g} {error:10.3e} {observed_order:6.2f} "
       "{wall_per_sim_second:12.2f} {newton_per_step:11.2f} {friction_updates_per_step:12.2f}")
TOL_COLORS = {1e-2: (214, 39, 40), 1e-4: (31, 119, 180), 1e-6: (44, 160, 44)}


# measure: what `error` measures; duration: simulated s per run; friction: False where there is
# no contact (one run stands for both modes); ordered: h causes the error, so observed orders in h
# are reported; build(h, tol, friction_updates) -> scene; error(scene, run, reference) -> float
Case = namedtuple("Case", "name measure duration friction ordered build error")


CASES = (
    Case("sliding", "relative acceleration error (mu 0.05, tan 0.1)", 0.4, True, False,
         lambda h, tol, fu: square.resting_scene(square.LECTURE_TAN, 0.05, h=h, tol=tol,
                                                friction_updates=fu),
         lambda scene, run, reference: abs(cases.acceleration_error(scene, run))),
    Case("sticking", "relative error of the creep over 0.2 s (mu 0.11)", 0.2, True, False,
         lambda h, tol, fu: square.resting_scene(square.LECTURE_TAN, 0.11, h=h, tol=tol,
                                                friction_updates=fu),
         lambda scene, run, reference: abs(       # the mean creep speed against the steady one
             run.downhill(scene)[0][-1] / run.t[-1] / cases.creep_speed(scene) - 1)),
    Case("free fall", "COM error at 0.4 s, m", 0.4, False, True,
         lambda h, tol, fu: square.free_fall_scene(h=h, tol=tol),
         lambda scene, run, reference: float(np.linalg.norm(
             run.com[-1] - square.free_fall_com(scene, run.t[-1:])[0]))),
    Case("full scene", f"max COM error over 0.6 s vs h = {REFERENCE_H:g}, m", 0.6, True, True,
         lambda h, tol, fu: simulator.build_scene(h=h, tol=tol, friction_updates=fu),
         lambda scene, run, reference: cases.max_com_error(run, reference)),
)


def sweep(quick=False):
    """Every run, progress on stderr: the CSV rows (dicts), and notes on the reference."""
    hs, chosen = (QUICK_HS, CASES[2:3]) if quick else (HS, CASES)
    runs = [(case, mode, tol, h) for case in chosen
            for mode in (MODES if case.friction else ("none",)) for tol in TOLS for h in hs]
    reference, notes = None, []
    if not quick:           # the full scene's reference, and the same run at twice its h
        print(f"reference: full scene, h={REFERENCE_H:g}, tol={REFERENCE_TOL:g}, lagged ...",
              file=sys.stderr, flush=True)
        full = CASES[3]
        reference = cases.run(full.build(REFERENCE_H, REFERENCE_TOL, 0), full.duration)
        coarser = cases.run(full.build(2 * REFERENCE_H, REFERENCE_TOL, 0), full.duration)
        spread = cases.max_com_error(coarser, reference)
        notes.append(f"full scene reference: h = {REFERENCE_H:g}, tol {REFERENCE_TOL:g}, lagged; "
                     f"the same run at h = {2 * REFERENCE_H:g} differs from it by up to "
                     f"{spread:.1e} m (an estimate of its own error)")
    rows = []
    for i, (case, mode, tol, h) in enumerate(runs, 1):
        scene = case.build(h, tol, MODES.get(mode, 0))
        row = {"case": case.name, "error_measure": case.measure, "friction": mode, "tol": tol,
               "h": h, "steps": int(round(case.duration / h)), "unconverged_steps": 0,
               **dict.fromkeys(COLUMNS[6:11], math.nan)}     # until measured
        try:
            run = cases.run(scene, case.duration)
            row.update(error=case.error(scene, run, reference),
                       wall_per_sim_second=run.wall / case.duration,
                       newton_per_step=float(run.newton_iterations.mean()),
                       friction_updates_per_step=float(run.friction_updates.mean()),
                       unconverged_steps=int(np.sum(~run.friction_converged)))
        except time_integrator.SimulationError as err:     # kept in the table as nan
            print(f"  failed: {err}", file=sys.stderr)
        before = rows[-1] if h != hs[0] else None     # the same line at the previous h
        if case.ordered and before and before["error"] > 0 and row["error"] > 0:
            row["observed_order"] = (math.log(before["error"] / row["error"])
                                     / math.log(before["h"] / row["h"]))
        rows.append(row)
        print(f"[{i:3d}/{len(runs)}] {case.name:10s} {mode:8s} tol={tol:.0e} h={h:<7g} "
              f"error={row['error']:.3e}  {row['wall_per_sim_second']:.2f} s/sim-s",
              file=sys.stderr, flush=True)
    return rows, notes


def table(rows):
    """The table as text, grouped by case, each group headed by its error measure; '-' for nan."""
    out = []
    for case, group in itertools.groupby(rows, key=lambda row: row["case"]):
        group = list(group)
        out += ["", f"{case}: {group[0]['error_measure']}", HEAD]
        out += [ROW.format(**row).replace("nan", "  -") for row in group]
    return "\n".join(out[1:])


def style(mode, tol):
    """A tolerance's colour; fully implicit friction dashed (with squares)."""
    return plot.Style(TOL_COLORS.get(tol, (0, 0, 0)), mode == "implicit")


def draw(path, rows):
    """The PNG: one panel per case, one line per (friction mode, tolerance) through its h."""
    panels, legend = {}, {}
    for row in rows:
        look = style(row["friction"], row["tol"])   # free fall's "none": named as lagged, if any
        legend.setdefault(look, f"{row['friction']}, tol {row['tol']:.0e}")
        series = panels.setdefault(f"{row['case']}: {row['error_measure']}", {})
        points = series.setdefault(look, [])
        if row["error"] > 0 and row["wall_per_sim_second"] > 0:     # False for nan: failed runs
            points.append((row["wall_per_sim_second"], row["error"]))
    hs = ", ".join(f"{h:g}" for h in sorted({row["h"] for row in rows}, reverse=True))
    notes = [f"Each line: one friction mode and Newton tolerance (m/s) through h = {hs} s;"
             " a smaller h costs more (further right).",
             "Free fall has no contact: its one run per tolerance is drawn solid. Fully implicit "
             f"friction: up to {FIXED_POINT_CAP} fixed-point updates per step."]
    if any(row["case"] == "sticking" for row in rows):
        creep = cases.creep_speed(CASES[1].build(HS[0], TOLS[-1], 0))
        notes += [f"Sticking: the mean creep speed against the mollified friction's steady creep,"
                  f" {creep:.3g} m/s, the converged answer (Coulomb",
                  "friction would not creep at all; a Newton tolerance that stops Newton early "
                  "creeps too slowly)."]
    plot.save_loglog_panels(path, "Error against run time", panels,
                            ("wall-clock s per simulated s", "error"), legend, notes)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.error_vs_runtime",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help=f"only free fall at h = {QUICK_HS}")
    ap.add_argument("--out", help="folder for error_vs_runtime.csv and .png")
    args = ap.parse_args(argv)
    out = tables.output_folder(args.out, not args.quick, "error_vs_runtime")
    start = time.perf_counter()
    rows, notes = sweep(quick=args.quick)
    print("\n".join([table(rows)] + ([""] + notes if notes else [])))
    paths = [os.path.join(out, f"error_vs_runtime.{ext}") for ext in ("csv", "png")]
    tables.write_csv(paths[0], COLUMNS, rows)
    draw(paths[1], rows)
    print(f"wrote {paths[1]}\n{len(rows)} runs in {time.perf_counter() - start:.0f} s",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

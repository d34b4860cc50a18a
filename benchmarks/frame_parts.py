"""Where a frame's time goes: CPU ms per frame of each part of FrameWriter.write within the default
`python simulator.py` run, each part's function wrapped in a timer, the frames drawn in the run's
process (not its frames' process, where no timer reaches) (benchmarks/README.md, frames).
`python -m benchmarks.frame_parts [--against REV] [--rounds N] [--quick]`."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")     # before numpy loads OpenBLAS
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import argparse
import contextlib
import functools
import importlib
import importlib.util
import io
import statistics
import sys
import tempfile
import time

# part: [(module, the attribute holding its function)], each timed where the tree has it (a part
# it never calls: "-"). The palette indices: draw.palette_rows on whole frames before issue 42's
# bands, draw.palette_indices on the bands that changed since (within frames.BandedPng.data)
PARTS = {"drawing": [("viewer.pictures.draw", "draw_frame")],
         "palette indices": [("viewer.pictures.draw", "palette_rows"),
                             ("viewer.pictures.draw", "palette_indices")],
         "PNG in bands": [("viewer.pictures.frames", "BandedPng.data")],
         "OBJ text": [("square_mesh", "obj_text")],
         "the two files": [("viewer.output.files", "RunFolder.write")],
         "whole frame": [("viewer.pictures.frames", "FrameWriter.write")]}


def timed(spent, part, function):
    """`function`, its CPU time and a call added to spent[part] at each call."""
    @functools.wraps(function)
    def run(*args, **kwargs):
        start = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            spent[part][0] += time.process_time() - start
            spent[part][1] += 1
    return run


def frame_parts(tree, scratch):
    """{part: CPU ms per frame, None where never called} of one default run with `tree`'s modules
    into a new folder in `scratch`, its output swallowed (the files: the run's plots, summary and
    page too, 3 of its 405)."""
    sys.path.insert(0, tree)
    from viewer import main
    spent = {part: [0.0, 0] for part in PARTS}
    for part, (module, name) in [(part, place) for part, places in PARTS.items()
                                 for place in places]:
        owner = importlib.import_module(module)
        *path, attribute = name.split(".")
        for step in path:
            owner = getattr(owner, step, None)
        if hasattr(owner, attribute):
            setattr(owner, attribute, timed(spent, part, getattr(owner, attribute)))
    in_this_process = importlib.import_module("viewer.pictures.frames").FrameWriter
    for module in ("viewer.command.recording", "viewer.command.frame_process"):   # a tree's own
        owner = importlib.util.find_spec(module) and importlib.import_module(module)
        if hasattr(owner, "frame_writer"):  # the frames in this process, each part timed here
            owner.frame_writer = in_this_process
    quiet = io.StringIO()
    with contextlib.redirect_stderr(quiet), contextlib.redirect_stdout(quiet):
        main.main(["--out", tempfile.mkdtemp(dir=scratch)])
    frames = spent["whole frame"][1]
    return {part: 1e3 * seconds / frames if calls else None
            for part, (seconds, calls) in spent.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.frame_parts", description=__doc__)
    ap.add_argument("--against", metavar="REV", help="also the tree at this commit, in turn")
    ap.add_argument("--rounds", type=int, default=5, help="runs of each tree (default 5)")
    ap.add_argument("--quick", action="store_true", help="a smoke run: one run of each tree")
    args = ap.parse_args(argv)
    args.rounds = 1 if args.quick else args.rounds
    if args.rounds < 1:
        print(f"{ap.prog}: error: --rounds: {args.rounds} runs; give 1 or more", file=sys.stderr)
        return 2
    # imported here, not above: it loads viewer, which frame_parts takes from the tree it is given
    from benchmarks import tables
    with tables.scratch("frame-parts-") as folder:
        trees = {"this tree": tables.ROOT}
        if args.against:
            trees = {args.against: tables.export_tree(args.against, folder), **trees}
        done = tables.in_turn({name: functools.partial(
            tables.in_fresh_process, "benchmarks.frame_parts", "frame_parts", tree, folder)
            for name, tree in trees.items()}, args.rounds)
    print(f"CPU ms per frame, medians of {args.rounds} runs, in turn: {', '.join(trees)}")
    for part in PARTS:
        figures = [[run[part] for run in runs] for runs in done.values()]
        print(f"  {part:16s}" + "".join(f"{statistics.median(ms):8.2f}" if None not in ms
                                        else f"{'-':>8s}" for ms in figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())

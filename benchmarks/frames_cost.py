"""The cost of the frames (`python -m benchmarks.speed --frames`): the default `python simulator.py`
against the same run with --no-frames, whole processes, run alternately.
"""
import csv
import os
import statistics
import subprocess
import sys
import time

from benchmarks.tables import spread

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

FRAMES_TARGET = 3.0         # the default run at most 3x the wall time of --no-frames (issue 16)


def frames_overhead(repeats=5, extra=()):
    """Whole-process wall time of `python simulator.py` and of `python simulator.py --no-frames`,
    run alternately (so both meet the machine in the same state), `repeats` times each: the medians,
    their ratio, and the frames written per simulated second."""
    import tempfile
    times = {"frames": [], "no-frames": []}
    with tempfile.TemporaryDirectory() as folder:
        for i in range(repeats):
            for kind in times:
                out = os.path.join(folder, f"{kind}-{i}")       # each run writes a new folder
                command = [sys.executable, os.path.join(ROOT, "simulator.py"), "--out", out, *extra]
                start = time.perf_counter()
                done = subprocess.run(command + (["--no-frames"] if kind == "no-frames" else []), cwd=ROOT,
                                      capture_output=True, text=True, env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
                times[kind].append(time.perf_counter() - start)
                if done.returncode != 0:
                    raise RuntimeError(f"simulator.py failed:\n{done.stderr}")
        frames = len([f for f in os.listdir(os.path.join(folder, "frames-0")) if f.endswith(".png") and f.startswith("frame_")])
        with open(os.path.join(folder, "frames-0", "log.csv")) as f:
            simulated = float(list(csv.DictReader(f))[-1]["t"])
    with_frames, without = statistics.median(times["frames"]), statistics.median(times["no-frames"])
    return {"frames_s": with_frames, "no_frames_s": without, "ratio": with_frames / without,
            "frames_per_simulated_s": (frames - 1) / simulated, "frames": frames,
            "spread": max(spread(times["frames"]), spread(times["no-frames"]))}


def print_frames_overhead(repeats):
    r = frames_overhead(repeats)
    verdict = "met" if r["ratio"] <= FRAMES_TARGET else "NOT met"
    print(f"python simulator.py: {r['frames_s']:.2f} s with {r['frames']} frames ({r['frames_per_simulated_s']:.1f} "
          f"per simulated second), {r['no_frames_s']:.2f} s with --no-frames (whole processes, medians of "
          f"{repeats}, run alternately): {r['ratio']:.2f}x (target <= {FRAMES_TARGET:g}x: {verdict}; "
          f"repeats spread {100 * r['spread']:.0f}%)")
    return 0

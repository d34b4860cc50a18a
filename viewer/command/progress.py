"""What a run says on stderr as it goes: progress lines and warnings about its steps (what it showed,
its closing words, are analysis.closing's). A run to files (recording.Track) and the window
(live.LiveDemo) say them, each warning the first time it applies.
"""
import time

from analysis import diagnostics

PROGRESS_EVERY = 2.0        # s of wall time: a progress line at least this often, whatever the run's length


class Progress:
    """Progress lines on `log`: at every tenth of the first run and at least every PROGRESS_EVERY s
    of wall time, whatever the run's length (a run of 1e308 steps says how far it got). A line for
    step N gives each run's figures of its own step N, as its log.csv has them: runs advance in turn,
    so a line waits until every run has reached step N or ended before it."""

    def __init__(self, tracks, log):
        self.log, self.tracks = log, tracks
        self.last = time.perf_counter()
        self.tenth = max(1, tracks[0].steps // 10)
        self.due = {}               # step N -> {track index: its figures at step N}, not yet said

    def tick(self, track):
        """`track` has just logged its step `track.step`."""
        now = time.perf_counter()
        if track.step % self.tenth == 0:
            self.due.setdefault(track.step, {})
        going = [tr.step for tr in self.tracks if tr.step < tr.steps]
        if now - self.last > PROGRESS_EVERY and going:      # the next step the runs going all reach
            self.last = now
            self.due.setdefault(1 + max(going), {})
        if track.step in self.due:
            self.due[track.step][self.tracks.index(track)] = self.words(track)
        for n in sorted(self.due):          # said once every run has logged step n, or has ended
            if all(k in self.due[n] or tr.step == tr.steps for k, tr in enumerate(self.tracks)):
                self.say(n, self.due.pop(n))

    def words(self, track):
        """One run's figures of the step it has just logged, as the progress line says them."""
        last, t = track.samples.last, ""
        if len({tr.scene.h for tr in self.tracks}) > 1:       # runs of different h: step N, other t
            t = f"t={track.t:.2f}s "
        return (f"{t}newton={last.report.newton_iterations}  residual={last.report.residual:.1e}  "
                f"min_d={last.min_distance:.2e}")

    def say(self, n, runs):
        """The line of step n: the first run's step count and time, each run's figures."""
        if runs:
            first = self.tracks[min(runs)]
            parts = [f"{self.tracks[k].label}: {text}" if len(self.tracks) > 1 else text
                     for k, text in sorted(runs.items())]
            print(f"step {n}/{first.steps}  t={n * first.scene.h:.2f}s  " + "  ".join(parts),
                  file=self.log, flush=True)

    def warn(self, track, text):
        who = f"{track.label}: " if len(self.tracks) > 1 else ""
        print(f"simulator.py: warning: {who}{text}", file=self.log, flush=True)


def step_warnings(scene, step, t, report, inverted):
    """What a run warns about the step that ended at `step` (time t, its StepReport, `inverted` mesh
    triangles turned over), by kind, in words: the mesh folded over ("inverted"); Newton stopped at
    float64's round-off floor ("stalled")."""
    said = {}
    if inverted:
        said["inverted"] = (f"at step {step} (t = {t:.2f} s) {inverted} of {len(diagnostics.mesh_triangles(scene))} "
                            f"mesh triangles are inverted (the square folded over; the mass-spring model has no "
                            f"inversion barrier): use a stiffer --k or a smaller --h")
    if report.stalled:
        said["stalled"] = (f"at step {step} (t = {t:.2f} s) Newton stopped at float64's round-off floor, residual "
                           f"{report.residual:.2g} m/s above tol = {scene.tol:g} m/s (E can no longer resolve a "
                           f"smaller step); the run goes on, such steps are flagged newton_stalled in log.csv")
    return said

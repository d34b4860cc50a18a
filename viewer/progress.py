"""What a run says on stderr as it goes: progress lines, warnings about its steps, and what it showed
(when the square came to rest, the chalk's stick-slip). The words of each are here once; a run to files
(recording.Track) and the window (live.LiveDemo) say them, each warning the first time it applies.
"""
import time

from viewer import diagnostics, stick_slip

PROGRESS_EVERY = 2.0        # s of wall time: a progress line at least this often, whatever the run's length


class Progress:
    """Progress lines on `log`: every tenth of the first run and at least every PROGRESS_EVERY s of
    wall time, whatever the run's length (a run of 1e308 steps says how far it got)."""

    def __init__(self, tracks, log):
        self.log, self.tracks = log, tracks
        self.last = time.perf_counter()
        self.tenth = max(1, tracks[0].steps // 10)

    def tick(self, track):
        now = time.perf_counter()
        if (track is self.tracks[0] and track.step % self.tenth == 0) or now - self.last > PROGRESS_EVERY:
            self.last = now
            parts = [f"{tr.label + ': ' if len(self.tracks) > 1 else ''}newton={tr.samples.last.report.newton_iterations}"
                     f"  residual={tr.samples.last.report.residual:.1e}  min_d={tr.samples.last.min_distance:.2e}"
                     for tr in self.tracks if tr.samples.last.report is not None]
            print(f"step {track.step}/{track.steps}  t={track.t:.2f}s  " + "  ".join(parts), file=self.log, flush=True)

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


def rest_words(tracks):
    """When each run came to rest (every contact node below eps_v from then on, as log.csv's
    contacts_sliding says), in words: 'came to rest at t = 5.53 s', or 'still sliding at t = 3.00 s'."""
    def words(track):
        if track.rest_since is None:
            return f"{'still sliding' if track.samples.last.sliding else 'not at rest'} at t = {track.t:.2f} s"
        return f"came to rest at t = {track.rest_since:.2f} s"
    if len(tracks) == 1:
        return "the square " + words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def stick_slip_words(tracks):
    """What each chalk run's tip did once the hand drove (viewer/stick_slip.py), in words: 'stick-slip: 25
    slips, mean slip 1.06 mm, period 107 ms, tip stuck 86 % of the drive'; for a comparison each run's,
    after its label."""
    said = [stick_slip.words(stick_slip.of_track(track)) for track in tracks]
    if len(tracks) == 1:
        return said[0]
    return "; ".join(f"{track.label}: {words}" for track, words in zip(tracks, said))


def closing_words(tracks):
    """What the run showed, as its closing line says it: for the square when it came to rest (rest_words),
    for the chalk its tip's stick-slip (stick_slip_words)."""
    return stick_slip_words(tracks) if tracks[0].scene.hand is not None else rest_words(tracks)


def closing_note(tracks):
    """closing_words with what they count, as the page (and the square's summary.png) says them."""
    if tracks[0].scene.hand is not None:
        return f"{stick_slip_words(tracks)} ({' '.join(stick_slip.definition(tracks[0].scene))})"
    return rest_words(tracks) + " (every contact below eps_v from then on)"

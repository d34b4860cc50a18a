"""What a run showed, in words: when the square came to rest, the chalk's stick-slip, or how far
the tablecloth's dish travelled."""
import closed_forms
from analysis import stick_slip


def each(tracks, words):
    """words(track) for one run; 'label: words; label: words' for a comparison."""
    if len(tracks) == 1:
        return words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def rest_words(tracks):
    """When each run came to rest (every contact below eps_v from then on): 'came to rest at
    t = 5.53 s', 'was still sliding at t = 3.00 s', or in the air 'had not come to rest by ...'."""
    def words(track):
        if track.rest_since is not None:
            return f"came to rest at t = {track.rest_since:.2f} s"
        if track.samples.last.sliding:
            return f"was still sliding at t = {track.t:.2f} s"
        return f"had not come to rest by t = {track.t:.2f} s"
    return ("the square " if len(tracks) == 1 else "") + each(tracks, words)


def travel_words(tracks):
    """Each dish's travel (its centre of mass along the pull, end minus start) beside the closed
    form: 'the dish travelled 0.1226 m, closed form mu g L^2 / U^2 = 0.1226 m (-0.0 %)'; for a
    comparison, in the order of its runs, 'the dish travelled 1.0000, 0.1226 m (closed form +0.0,
    -0.0 %)' ('-' where the closed form is 0)."""
    runs = []
    for track in tracks:
        scene, surface = track.scene, track.scene.surface
        moved = track.samples.last.com - track.samples.items[0].com
        travel, g = float(moved @ surface.tangent), -scene.g[1]
        U, L = surface.pull_speed, surface.pull_length
        exact = closed_forms.tablecloth_travel(U, L, scene.mu, g)
        off = f"{100 * (travel - exact) / exact:+.1f}" if exact else "-"
        runs.append((travel, exact, "mu g L^2 / U^2" if U * U >= scene.mu * g * L else "L", off))
    if len(runs) > 1:
        travels = ", ".join(f"{travel:.4f}" for travel, *_ in runs)
        return f"the dish travelled {travels} m (closed form {', '.join(r[-1] for r in runs)} %)"
    travel, exact, form, off = runs[0]
    off = f" ({off} %)" if exact else ""
    return f"the dish travelled {travel:.4f} m, closed form {form} = {exact:.4f} m{off}"


def stick_slip_words(tracks):
    """Each chalk's stick-slip (stick_slip.words); for a comparison whose runs all stick-slip, in
    the order of its runs: 'stick-slip: 21, 25 slips; mean slip 1.32, 1.06 mm; period 133, 107 ms;
    tip stuck 84, 86 %' (of the drive)."""
    counted = [stick_slip.of_track(track) for track in tracks]
    if len(counted) == 1 or not all(r.driven and len(r.slips) > 1 for r in counted):
        return each(tracks, lambda track: stick_slip.words(counted[tracks.index(track)]))

    def column(text):
        return ", ".join(map(text, counted))
    return (f"stick-slip: {column(lambda r: str(len(r.slips)))} slips; mean slip "
            f"{column(lambda r: f'{1e3 * r.length:.2f}')} mm; period "
            f"{column(lambda r: f'{1e3 * r.period:.0f}')} ms; tip stuck "
            f"{column(lambda r: f'{100 * r.stuck:.0f}')} %")


def closing_words(tracks):
    """The closing line's words: the chalk's stick-slip, the dish's travel, else the square's
    rest."""
    scene = tracks[0].scene
    if scene.hand is not None:
        return stick_slip_words(tracks)
    return travel_words(tracks) if scene.surface is not None else rest_words(tracks)


def closing_note(tracks):
    """closing_words with what they count, as the page and summary.png say them."""
    scene = tracks[0].scene
    if scene.hand is not None:
        what = " ".join(stick_slip.definition(scene))
    elif scene.surface is not None:
        what = "the centre of mass along the pull, end minus start"
    else:
        what = "every contact below eps_v from then on"
    return f"{closing_words(tracks)} ({what})"

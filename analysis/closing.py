"""What a run showed, in words: when the square came to rest, the chalk's stick-slip, or how far
the tablecloth's dish travelled."""
import closed_forms
from analysis import grasp, stick_slip


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
    form: 'the dish travelled 0.1226 m, closed form mu g L^2 / U^2 = 0.1226 m (-0.0 %)'."""
    def words(track):
        scene, surface = track.scene, track.scene.surface
        moved = track.samples.last.com - track.samples.items[0].com
        travel, g = float(moved @ surface.tangent), -scene.g[1]
        U, L = surface.pull_speed, surface.pull_length
        exact = closed_forms.tablecloth_travel(U, L, scene.mu, g)
        form = "mu g L^2 / U^2" if U * U >= scene.mu * g * L else "L"
        off = f" ({100 * (travel - exact) / exact:+.1f} %)" if exact else ""
        return f"the dish travelled {travel:.4f} m, closed form {form} = {exact:.4f} m{off}"
    return each(tracks, words)


def closing_words(tracks):
    """The closing line's words: the chalk's stick-slip (stick_slip.words), the dish's travel, else
    the square's rest."""
    scene = tracks[0].scene
    if scene.hand is not None:
        return each(tracks, lambda track: stick_slip.words(stick_slip.of_track(track)))
    if scene.fingers is not None:
        return ("the block " if len(tracks) == 1 else "") + each(tracks, grasp.of_track)
    return travel_words(tracks) if scene.surface is not None else rest_words(tracks)


def closing_note(tracks):
    """closing_words with what they count, as the page and summary.png say them."""
    scene = tracks[0].scene
    if scene.hand is not None:
        what = " ".join(stick_slip.definition(scene))
    elif scene.fingers is not None:
        what = "slip: the fingers' lift minus the block's rise; dropped: slid past the pads"
    elif scene.surface is not None:
        what = "the centre of mass along the pull, end minus start"
    else:
        what = "every contact below eps_v from then on"
    return f"{closing_words(tracks)} ({what})"

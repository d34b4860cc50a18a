"""What a run showed, in words, as its closing line, its page and its pictures say it: when the
square came to rest, the chalk's stick-slip (counted by analysis.stick_slip).
"""
from analysis import stick_slip


def rest_words(tracks):
    """When each run came to rest (every contact node below eps_v from then on, as log.csv's
    contacts_sliding says), as a sentence after its subject: 'came to rest at t = 5.53 s', 'was
    still sliding at t = 3.00 s', or (no contact slides: in the air) 'had not come to rest by t =
    0.60 s'."""
    def words(track):
        if track.rest_since is None:
            if track.samples.last.sliding:
                return f"was still sliding at t = {track.t:.2f} s"
            return f"had not come to rest by t = {track.t:.2f} s"
        return f"came to rest at t = {track.rest_since:.2f} s"
    if len(tracks) == 1:
        return "the square " + words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def stick_slip_words(tracks):
    """What each chalk run's tip did once the hand drove (analysis/stick_slip.py), in words:
    'stick-slip: 25 slips, mean slip 1.06 mm, period 107 ms, tip stuck 86 % of the drive'; for a
    comparison each run's, after its label."""
    said = [stick_slip.words(stick_slip.of_track(track)) for track in tracks]
    if len(tracks) == 1:
        return said[0]
    return "; ".join(f"{track.label}: {words}" for track, words in zip(tracks, said))


def closing_words(tracks):
    """What the run showed, as its closing line says it: for the square when it came to rest
    (rest_words), for the chalk its tip's stick-slip (stick_slip_words)."""
    return stick_slip_words(tracks) if tracks[0].scene.hand is not None else rest_words(tracks)


def closing_note(tracks):
    """closing_words with what they count, as the page (and the square's summary.png) says them."""
    if tracks[0].scene.hand is not None:
        return f"{stick_slip_words(tracks)} ({' '.join(stick_slip.definition(tracks[0].scene))})"
    return rest_words(tracks) + " (every contact below eps_v from then on)"

"""What a run showed, in words: when the square came to rest, or the chalk's stick-slip."""
from analysis import stick_slip


def rest_words(tracks):
    """When each run came to rest (every contact below eps_v from then on): 'came to rest at
    t = 5.53 s', 'was still sliding at t = 3.00 s', or in the air 'had not come to rest by ...'."""
    def words(track):
        if track.rest_since is not None:
            return f"came to rest at t = {track.rest_since:.2f} s"
        if track.samples.last.sliding:
            return f"was still sliding at t = {track.t:.2f} s"
        return f"had not come to rest by t = {track.t:.2f} s"
    if len(tracks) == 1:
        return "the square " + words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def stick_slip_words(tracks):
    """Each chalk run's stick-slip (stick_slip.words), after its label in a comparison."""
    said = [stick_slip.words(stick_slip.of_track(track)) for track in tracks]
    if len(tracks) == 1:
        return said[0]
    return "; ".join(f"{track.label}: {words}" for track, words in zip(tracks, said))


def closing_words(tracks):
    """The closing line's words: the chalk's stick-slip, else the square's rest."""
    return stick_slip_words(tracks) if tracks[0].scene.hand is not None else rest_words(tracks)


def closing_note(tracks):
    """closing_words with what they count, as the page and summary.png say them."""
    if tracks[0].scene.hand is not None:
        return f"{stick_slip_words(tracks)} ({' '.join(stick_slip.definition(tracks[0].scene))})"
    return rest_words(tracks) + " (every contact below eps_v from then on)"

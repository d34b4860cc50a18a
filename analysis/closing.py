"""What a run showed, in words: when the square stuck and how fast it still creeps, the chalk's
stick-slip, or how far the tablecloth's dish travelled."""
import closed_forms
from analysis import diagnostics, stick_slip
from scenes import square, tablecloth
from scenes.scene import fixed


def each(tracks, words):
    """words(track) for one run; 'label: words; label: words' for a comparison."""
    if len(tracks) == 1:
        return words(tracks[0])
    return "; ".join(f"{track.label}: {words(track)}" for track in tracks)


def creep(track):
    """How fast a run that sticks still creeps (m/s, downhill), None if it does not stick: the
    contact nodes' mean velocity t . (v_k - v_s) averaged over the states kept since every contact
    stuck (track.rest_since), so that the square's rocking averages out."""
    if track.rest_since is None:
        return None
    u = [s.contact_velocity for s in track.samples.all() if s.t >= track.rest_since]
    return downhill(track.scene, sum(u) / len(u))


def downhill(scene, u):
    """u (m/s) along diagnostics.tangent, turned downhill: -u where gravity pulls the other way."""
    g = scene.g
    return -u if g is not None and g @ diagnostics.tangent(scene) < 0 else u


def closed_creep(scene):
    """closed_forms.creep_speed (a grasp's: its closed_creep) in mm/s, or None where Coulomb
    friction would not hold."""
    if scene.pushed is not None:
        return scene.pushed.closed_creep(scene)
    return 1e3 * closed_forms.creep_speed(scene) if square.holds(scene) else None


def creep_figures(track):
    """(measured creep, closed_creep), in mm/s."""
    return 1e3 * creep(track), closed_creep(track.scene)


def state_words(scene, x, v, t):
    """A state where every contact sticks, as the window says it: 'sticks: every contact below
    eps_v, creeps 0.45 mm/s (closed form 0.70)', the contact nodes' mean velocity downhill; None
    where a contact slides or none touches."""
    u = diagnostics.contact_velocities(scene, x, v, scene.surface_velocity(t))
    if not diagnostics.at_rest(*diagnostics.sticking_sliding(abs(u), scene.epsv)):
        return None
    exact, measured = closed_creep(scene), 1e3 * downhill(scene, u.mean())
    form = "" if exact is None else f" (closed form {fixed(exact, 2)})"
    return f"sticks: every contact below eps_v, creeps {fixed(measured, 2)} mm/s{form}"


def blur(track):
    """How the Newton tolerance (m/s) stands to the creep u* (the closed form, else the measured
    creep), whose error it makes about -0.5 tol / u*: 'below' (tol >= u*: the solver cannot tell
    the creep from rest), 'near' (tol > u* / 10), or '' (measured well)."""
    scene = track.scene
    expected = abs(closed_forms.creep_speed(scene) if square.holds(scene) else creep(track))
    return "below" if scene.tol >= expected else "near" if scene.tol > 0.1 * expected else ""


def rest_words(tracks):
    """When each run stuck (every contact below eps_v from then on) and how fast it creeps then,
    beside closed_forms.creep_speed: 'the square sticks at 5.54 s, creeps 0.52 mm/s (closed form
    0.70, set by --epsv) below --tol 0.01'; 'still slides at 3.00 s', 'is in the air at ...'; a
    comparison's runs that stick, labelled 'name = value', together (stuck_together)."""
    one = len(tracks) == 1

    def words(track):
        if track.rest_since is None:
            state = "still slides" if track.samples.last.sliding else "is in the air"
            return f"{state} at {track.t:.2f} s"
        blurred, (measured, exact) = blur(track), creep_figures(track)
        digits = 2 if blurred else 3
        epsv = ", set by --epsv" if one else ""
        form = "" if exact is None else f" (closed form {fixed(exact, digits)}{epsv})"
        tol = f" {blurred} --tol {track.scene.tol:g}" if one and blurred else ""
        creeps = f"creeps {fixed(measured, digits)} mm/s"
        return f"sticks at {track.rest_since:.2f} s, {creeps}{form}{tol}"
    if one:
        return "the square " + words(tracks[0])
    stuck = [track for track in tracks if track.rest_since is not None]
    blurs = {blur(track) for track in stuck}
    word = next((word for word in ("below", "near") if word in blurs), "")
    names = {track.label.partition(" = ")[0] for track in stuck}
    if len(stuck) < 2 or len(names) > 1 or any(", " in track.label for track in stuck):
        tol = f", {word} --tol" if word else ""
        return each(tracks, words) + (f"; creep set by --epsv{tol}" if blurs else "")
    return "; ".join([f"{track.label}: {words(track)}" for track in tracks
                      if track.rest_since is None] + [stuck_together(stuck, names.pop(), word)])


def stuck_together(stuck, name, word):
    """A comparison's runs that stick, in one list a figure: 'mu = 0.11, 0.2: stick at 5.54,
    2.80 s, creep 0.52, 0.22 mm/s, below --tol (closed form 0.70, 0.29)' (`word`: blur's)."""
    digits = 2 if word else 3
    figures = [creep_figures(track) for track in stuck]

    def column(values):
        return ", ".join("-" if v is None else fixed(v, digits) for v in values)
    values = ", ".join(track.label.partition(" = ")[2] for track in stuck)
    since = ", ".join(f"{track.rest_since:.2f}" for track in stuck)
    tol = f", {word} --tol" if word else ""
    return (f"{name} = {values}: stick at {since} s, creep {column(f[0] for f in figures)} "
            f"mm/s{tol} (closed form {column(f[1] for f in figures)})")


def travel_words(tracks):
    """Each dish's travel (its centre of mass along the pull, end minus start) beside the closed
    form: 'the dish travelled 0.1226 m, closed form mu g L^2 / U^2 = 0.1226 m (-0.0 %)'; for a
    comparison, in the order of its runs, 'the dish travelled 1.0000, 0.1226 m (closed form +0.0 %,
    -0.0 %)' ('-' where the closed form is 0); 'unfinished' where the run ended before the closed
    form's dish stops (tablecloth.stop_time)."""
    runs = []
    for track in tracks:
        scene, surface = track.scene, track.scene.surface
        moved = track.samples.last.com - track.samples.items[0].com
        travel, g = float(moved @ surface.tangent), -scene.g[1]
        U, L = surface.pull_speed, surface.pull_length
        exact = tablecloth.travel(U, L, scene.mu, g)
        stop = tablecloth.stop_time(U, L, scene.mu, surface.t_pull, g)
        off = f"{100 * (travel - exact) / exact:+.1f}" if exact else "-"
        off = "unfinished" if track.t < stop else off
        runs.append((travel, exact, "mu g L^2 / U^2" if U * U >= scene.mu * g * L else "L", off,
                     stop))
    if len(runs) > 1:
        travels = ", ".join(fixed(travel, 4) for travel, *_ in runs)
        offs = ", ".join(r[3] + ("" if r[3] == "unfinished" else " %") for r in runs)
        return f"the dish travelled {travels} m (closed form {offs})"
    travel, exact, form, off, stop = runs[0]
    if off == "unfinished":
        return (f"the dish travelled {fixed(travel, 4)} m by {tracks[0].t:.2f} s, unfinished: "
                f"the closed form's stops at {fixed(stop, 2)} s")
    off = f" ({off} %)" if exact else ""
    return f"the dish travelled {fixed(travel, 4)} m, closed form {form} = {fixed(exact, 4)} m{off}"


def stick_slip_words(tracks, short=True):
    """Each chalk's stick-slip (stick_slip.words; `short`, short_words in a comparison whose runs do
    not all stick-slip); for a comparison whose runs all stick-slip, in the order of its runs:
    'stick-slip: 21, 25 slips; mean slip 1.32, 1.06 mm; tip stuck 84, 86 %; creeping 0.067-0.068
    mm/s' (stuck: of the drive; creeping: while stuck, least to most), short enough for the
    closing's lines (the period is on the page)."""
    counted = [stick_slip.of_track(track) for track in tracks]
    if len(counted) == 1:
        return stick_slip.words(counted[0])
    if not all(r.driven and len(r.slips) > 1 for r in counted):     # short: the closing's lines
        words = stick_slip.short_words if short else stick_slip.words
        return each(tracks, lambda track: words(counted[tracks.index(track)]))

    def column(text):
        return ", ".join(map(text, counted))
    creeps = sorted({f"{1e3 * r.creep_speed:.2g}" for r in counted}, key=float)
    return (f"stick-slip: {column(lambda r: str(len(r.slips)))} slips; mean slip "
            f"{column(lambda r: f'{1e3 * r.length:.2f}')} mm; tip stuck "
            f"{column(lambda r: f'{100 * r.stuck:.0f}')} %; creeping "
            f"{'-'.join(creeps[::len(creeps) - 1 or 1])} mm/s")


def closing_words(tracks):
    """The closing line's words: the chalk's stick-slip (stick_slip.words), the dish's travel, else
    the square's sticking and creep."""
    scene = tracks[0].scene
    if scene.hand is not None:
        return stick_slip_words(tracks)
    if scene.pushed is not None:          # the words its scene gives (short: a comparison's)
        return each(tracks, lambda track: scene.pushed.words(track, short=len(tracks) > 1))
    return travel_words(tracks) if scene.surface is not None else rest_words(tracks)


def counted(scene):
    """What closing_words count, in words."""
    if scene.hand is not None:
        return " ".join(stick_slip.definition(scene))
    if scene.pushed is not None:
        return scene.pushed.counted
    if scene.surface is not None:
        return "the centre of mass along the pull, end minus start"
    return ("sticks: every contact below eps_v from then on; creeps: the contact nodes' mean "
            "speed downhill since")


def closing_note(tracks):
    """closing_words with what they count, as the page says them (a chalk's in its long words)."""
    scene = tracks[0].scene
    said = closing_words(tracks) if scene.hand is None else stick_slip_words(tracks, short=False)
    return f"{said} ({counted(scene)})"

"""The command line as the tests run it in this process."""
import io
import json
import os
import re
import sys

import simulator
from viewer.command import progress, recording, run
from viewer.pictures import draw
import viewer.main


def run_main(*args):
    """viewer.command.viewer.main.main(args) in this process: (exit code, stderr lines)."""
    err, old = io.StringIO(), sys.stderr
    sys.stderr = err
    try:
        code = viewer.main.main(list(args))
    finally:
        sys.stderr = old
    return code, err.getvalue().splitlines()


def recorded(folder, scenes, steps, simulate=simulator.simulate):
    """The scenes run side by side for `steps` steps into `folder`, as a run without frames records
    them (viewer.command.recording): their Tracks, with what the pictures need, and their logs.
    `simulate`: where the StepRecords come from (helpers/runs.py Runs.simulate: shared runs)."""
    tags = [f"run{i}" for i in range(len(scenes))] if len(scenes) > 1 else [""]
    labels = [f"run {i}" for i in range(len(scenes))]
    plan = run.Plan(scenes, labels, tags, [steps] * len(scenes), str(folder),
                    stride=3, frames=False, forces=False)
    signals = run.Signals()
    out = plan.folder(signals)
    tracks = [recording.Track(scene, steps, simulate(scene, steps), label, tag,
                              draw.run_color(i), out)
              for i, (scene, label, tag) in enumerate(zip(scenes, plan.labels, tags))]
    recording.record(tracks, out, plan.stride, False, False, io.StringIO(), [])
    for track in tracks:
        track.csv.close()
    out.release()
    return tracks


def without_given(line, given):
    """`line` without what the user gave (a path or value may run longer than 100 columns), as
    given and as printed (%g, lists with ', ')."""
    forms = set()
    for value in map(str, given):
        forms.add(value)
        try:
            numbers = [f"{float(part):g}" for part in value.split(",")]
        except ValueError:
            continue
        forms.update((", ".join(numbers), ",".join(numbers)))
    for form in sorted(forms, key=len, reverse=True):
        line = line.replace(form, "")
    return line


def refused(args, out):
    """The command line run on `out` holding an earlier run's log.csv: its one error line, after
    checking exit code 2 and that `out` is as it was."""
    out.mkdir(exist_ok=True)
    (out / "log.csv").write_text("an earlier run\n")
    length = [] if {"--steps", "--duration"} & set(args) else ["--steps", "3"]
    code, lines = run_main(*args, "--out", str(out), *length)
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith("simulator.py: error: ")
    assert len(without_given(lines[0], [*args, out])) <= 100, lines[0]     # issue 40
    assert os.listdir(out) == ["log.csv"] and (out / "log.csv").read_text() == "an earlier run\n"
    return lines[0]


def ending(lines):
    """A run's ending line as one line would say it: from its last line that starts with
    'simulator.py: ' on, joined by '; ', after checking it took at most 3 lines of at most 100
    columns, paths aside (issue 40: run.say folds it between its parts, progress.columns)."""
    first = max(i for i, line in enumerate(lines) if line.startswith("simulator.py: "))
    said = lines[first:]
    assert len(said) <= 3, said
    assert all(progress.columns(line) <= 100 for line in said), said
    return "; ".join(said)


def closing_lines(lines):
    """A finished run's closing: from its last 'simulated ...' line on."""
    first = max(i for i, line in enumerate(lines) if line.startswith("simulated "))
    return lines[first:]


def too_wide(lines, *paths, width=100):
    """The lines wider than `width` columns (issue 40) once the paths given are taken out: only a
    path may run longer, the folder the run was given or its working folder."""
    def columns(line):
        for path in paths:
            line = line.replace(str(path), "")
        return len(line)
    return [line for line in lines if columns(line) > width]


def closing_text(lines):
    """A finished run's closing lines (from its 'simulated ...' line on) joined by '; ', as one
    line would say them."""
    return "; ".join(closing_lines(lines))


def messages(lines):
    """The lines as said: a warning's continuation lines (indented) joined to its first line."""
    said = []
    for line in lines:
        if line.startswith("  ") and said:
            said[-1] += " " + line.strip()
        else:
            said.append(line)
    return said


def page_data(folder):
    """The data the run's page in `folder` plays (index.html's `const run`: frames, rows, ...)."""
    text = (folder / "index.html").read_text()
    return json.loads(re.search(r"const run = (\{.*\});", text).group(1))

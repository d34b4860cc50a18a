"""index.html (page.html filled in): plays the PNG frames beside each run's figures (JSON in the
page: a page opened from a file may show images, not read files), plots.png with a cursor below."""
import html
import json
import math
from pathlib import Path

from analysis import closing, log, stick_slip
from viewer.pictures import draw

# the figures beside each frame, by log.csv's column names, each as log.csv writes it (or in the
# format given: min_distance to 5 digits)
FIGURES = {"step": None, "t": None, "newton_iterations": None, "residual": None,
           "min_distance": ".4e", "contacts_sticking": None, "contacts_sliding": None}

TEMPLATE = (Path(__file__).parent / "page.html").read_text(encoding="utf-8")


def figures(row):
    """The figures the page shows of a state, by name (FIGURES), from its named row (log.values):
    rounded as they are shown, None where there is none or it is not finite."""
    shown = {}
    for name, fmt in FIGURES.items():
        value, fmt = row[name], fmt or log.COLUMN[name].fmt
        finite = value is not None and math.isfinite(value)
        shown[name] = (int(value) if fmt == "d" else float(format(value, fmt))) if finite else None
    return shown


def header(name):
    """A figure's header in the page's table: its label, and its unit in brackets."""
    column = log.COLUMN[name]
    return f"{column.label} ({column.unit})" if column.unit else column.label


def creep_cell(track):
    """The square's creep once it sticks, in mm/s, with the closed form: '0.52 (0.70)'; '-'."""
    if track.rest_since is None:
        return "-"
    measured, exact = closing.creep_figures(track)
    return f"{measured:.2f}" + ("" if exact is None else f" ({exact:.2f})")


def run_figures(tracks):
    """page_html's keywords for what the table says of each whole run: when the square stuck
    (`rest`) and how fast it creeps since (closing.creep, `rows`); the chalk's stick-slip
    (analysis/stick_slip.py), a row per figure (`rows`); a pushed scene's closing words."""
    if tracks[0].scene.pushed is not None:
        return {"rows": [("what it showed", [closing.closing_words([t]) for t in tracks])]}
    if tracks[0].scene.hand is None:
        return {"rest": [track.rest_since for track in tracks],
                "rows": [("creeps since (mm/s; closed form)", [creep_cell(t) for t in tracks])]}
    counted = [stick_slip.of_track(track) for track in tracks]
    cells = (("stick-slip cycles", lambda r: str(len(r.slips)) if r.driven else "-"),
             ("mean slip (mm)", lambda r: f"{1e3 * r.length:.2f}" if r.slips else "-"),
             ("period (ms)", lambda r: f"{1e3 * r.period:.0f}" if len(r.slips) > 1 else "-"),
             ("tip stuck (% of the drive)", lambda r: f"{100 * r.stuck:.0f}" if r.driven else "-"),
             ("tip creeps while stuck (mm/s)",
              lambda r: "-" if math.isnan(r.creep_speed) else f"{1e3 * r.creep_speed:.2g}"),
             ("tip first slips at t (s)",
              lambda r: "never" if r.start_up is None else f"{r.start_up:.2f}"))
    rows = [(f"the whole run's stick-slip, from t = {counted[0].start:g} s", None)]
    return {"rows": rows + [(name, [text(r) for r in counted]) for name, text in cells]}


def page_html(title, labels, frame_log, fps, axis, plot_width, note="", rest=None, rows=()):
    """The page: `frame_log` (frames.FrameInfo per frame), `fps` frames per simulated second, `axis`
    (left px, right px, t_max) of plots.png's time axis; under the frame's figures when each run
    stuck (`rest`), and `rows`: (header, a text per run, or None: a heading across the table)."""
    escape = html.escape
    data = {"labels": [escape(label) for label in labels], "fps": fps,
            "rest": None if rest is None else [None if t is None else round(t, 6) for t in rest],
            "rows": [{"header": escape(name),
                      "cells": None if cells is None else [escape(c) for c in cells]}
                     for name, cells in rows],
            "figures": [{"name": name, "header": escape(header(name))} for name in FIGURES],
            "frames": [{"t": round(f.t, 6), "runs": f.runs} for f in frame_log],
            "axis": dict(zip(("left", "right", "tMax"), axis)), "plotWidth": plot_width}
    return (TEMPLATE.replace("__TITLE__", escape(title)).replace("__SIZE__", str(draw.RESOLUTION))
            .replace("__NOTE__", escape(note))
            .replace("__DATA__", json.dumps(data, allow_nan=False)))

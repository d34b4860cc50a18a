"""index.html: a page that plays the run's PNG frames from the file system, with no server:
play/pause, one frame back or forward, a time slider, the speed; beside the frame, each run's
figures of that step (FIGURES, log.csv's columns by name) and of the whole run (run_figures); below
it plots.png with a cursor at the frame's time. The figures are written into the page as JSON (a
page opened from the file system may show images, but not read other files).
"""
import html
import json
import math

from analysis import log, stick_slip
from viewer.pictures import draw

# the figures beside each frame, by log.csv's column names, each as log.csv writes it (or in the
# format given: min_distance to 5 digits)
FIGURES = {"step": None, "t": None, "newton_iterations": None, "residual": None,
           "min_distance": ".4e", "contacts_sticking": None, "contacts_sliding": None}

TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>__TITLE__</title>
<style>
  body { font-family: sans-serif; margin: 16px; }
  #top { display: flex; gap: 20px; align-items: flex-start; }
  #frame { width: __SIZE__px; height: __SIZE__px; border: 1px solid #aaa; }
  #controls { margin: 8px 0; display: flex; gap: 8px; align-items: center; }
  #slider { width: 480px; }
  #clock { display: inline-block; white-space: pre; font-variant-numeric: tabular-nums;
           text-align: left; }
  table { border-collapse: collapse; }
  td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
  th.heading { text-align: left; background: #eee; }
  #plotbox { position: relative; display: inline-block; margin-top: 12px; }
  #cursor { position: absolute; top: 0; bottom: 0; width: 2px; background: rgba(255, 0, 0, 0.6); }
</style>
</head>
<body>
<h2>__TITLE__</h2>
<div id="controls">
  <button id="play">pause</button>
  <button id="back" title="one frame back">&#9664; step</button>
  <button id="forward" title="one frame forward">step &#9654;</button>
  <input id="slider" type="range" min="0" max="0" value="0">
  <span id="clock"></span>
  <label>speed <select id="speed">
    <option value="0.1">0.1x</option><option value="0.25">0.25x</option>
    <option value="0.5">0.5x</option><option value="1" selected>1x</option>
    <option value="2">2x</option>
  </select></label>
</div>
<div id="top">
  <img id="frame" alt="frame of the run" src="frame_00000.png">
  <div><table id="figures"></table><p>__NOTE__</p></div>
</div>
__PLOTS__
<script>
"use strict";
const run = __DATA__;
const img = document.getElementById("frame"), slider = document.getElementById("slider");
const playButton = document.getElementById("play"), speed = document.getElementById("speed");
let index = 0, timer = null;
slider.max = run.frames.length - 1;

function frameName(k) { return "frame_" + String(k).padStart(5, "0") + ".png"; }

// The counter keeps one width (the controls after it stay in place): its numbers padded with
// figure spaces (as wide as a digit), its width fixed at the widest text's.
const lastFrame = run.frames.length - 1, FIGURE_SPACE = "\\u2007";
const frameDigits = String(lastFrame).length;
const timeDigits = Math.max(...run.frames.map(f => f.t.toFixed(2).length));
function clockText(k) {
  return "frame " + String(k).padStart(frameDigits, FIGURE_SPACE) + " / " + lastFrame + ", t = " +
    run.frames[k].t.toFixed(2).padStart(timeDigits, FIGURE_SPACE) + " s";
}
const clock = document.getElementById("clock");
clock.textContent = clockText(lastFrame);
clock.style.minWidth = Math.ceil(clock.getBoundingClientRect().width) + "px";

function tableRow(header, cells) {
  return "<tr><th>" + header + "</th>" + cells.map(c => "<td>" + c + "</td>").join("") + "</tr>";
}

function showFigures(frame) {
  let rows = "<tr><th></th>" + run.labels.map(l => "<th>" + l + "</th>").join("") + "</tr>";
  run.figures.forEach(figure => {
    const cells = frame.runs.map(r => (r[figure.name] === null ? "-" : r[figure.name]));
    rows += tableRow(figure.header, cells);
  });
  if (run.rest !== null) {
    const cells = run.rest.map(t => (t === null ? "not by the end" : t.toFixed(2)));
    rows += tableRow("came to rest at t (s)", cells);
  }
  const across = '<tr><th colspan="' + (run.labels.length + 1) + '" class="heading">';
  run.rows.forEach(row => {
    rows += row.cells === null ? across + row.header + "</th></tr>" :
      tableRow(row.header, row.cells);
  });
  document.getElementById("figures").innerHTML = rows;
}

function show(k) {
  index = Math.max(0, Math.min(run.frames.length - 1, k));
  const frame = run.frames[index];
  img.src = frameName(index);
  img.dataset.frame = index;
  slider.value = index;
  clock.textContent = clockText(index);
  showFigures(frame);
  const cursor = document.getElementById("cursor");
  if (cursor) {
    const left = run.axis.left + (run.axis.right - run.axis.left) * frame.t / run.axis.tMax;
    cursor.style.left = (100 * left / run.plotWidth) + "%";
  }
}

function play() {
  pause();
  playButton.textContent = "pause";
  timer = setInterval(() => show(index + 1 < run.frames.length ? index + 1 : 0),
                      1000 / (run.fps * Number(speed.value)));
}

function pause() {
  if (timer !== null) { clearInterval(timer); timer = null; }
  playButton.textContent = "play";
}

playButton.onclick = () => (timer === null ? play() : pause());
document.getElementById("back").onclick = () => { pause(); show(index - 1); };
document.getElementById("forward").onclick = () => { pause(); show(index + 1); };
slider.oninput = () => { pause(); show(Number(slider.value)); };
speed.onchange = () => { if (timer !== null) play(); };
show(0);
play();
</script>
</body>
</html>
"""


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


def run_figures(tracks):
    """page_html's keywords for what the table says of each whole run: when the square came to
    rest (`rest`); the chalk's stick-slip (analysis/stick_slip.py), a row per figure (`rows`)."""
    if tracks[0].scene.hand is None:
        return {"rest": [track.rest_since for track in tracks]}
    counted = [stick_slip.of_track(track) for track in tracks]

    def row(header, text):
        return header, [text(r) for r in counted]
    return {"rows": [
        (f"the whole run's stick-slip, from t = {counted[0].start:g} s", None),
        row("stick-slip cycles", lambda r: str(len(r.slips)) if r.driven else "-"),
        row("mean slip (mm)", lambda r: f"{1e3 * r.length:.2f}" if r.slips else "-"),
        row("period (ms)", lambda r: f"{1e3 * r.period:.0f}" if len(r.slips) > 1 else "-"),
        row("tip stuck (% of the drive)", lambda r: f"{100 * r.stuck:.0f}" if r.driven else "-"),
        row("tip first slips at t (s)",
            lambda r: "never" if r.start_up is None else f"{r.start_up:.2f}")]}


def page_html(title, labels, frame_log, fps, axis, plot_width, note="", rest=None, rows=()):
    """The page's text: `frame_log` (frames.FrameInfo per frame), `fps` frames per simulated
    second, `axis` (left px, right px, t_max) of plots.png's time axis (None: no plots); below the
    frame's figures each run's time of rest (`rest`) or `rows`, (header, a text per run or None for
    a heading across the table)."""
    escape = html.escape
    data = {"labels": [escape(label) for label in labels], "fps": fps,
            "rest": None if rest is None else [None if t is None else round(t, 6) for t in rest],
            "rows": [{"header": escape(name),
                      "cells": None if cells is None else [escape(c) for c in cells]}
                     for name, cells in rows],
            "figures": [{"name": name, "header": escape(header(name))} for name in FIGURES],
            "frames": [{"t": round(f.t, 6), "runs": f.runs} for f in frame_log],
            "axis": dict(zip(("left", "right", "tMax"), axis)) if axis else None,
            "plotWidth": plot_width}
    plots = ('<div id="plotbox"><img id="plots" src="plots.png" alt="plots of the run">'
             '<div id="cursor"></div></div>') if axis else ""
    return (TEMPLATE.replace("__TITLE__", escape(title)).replace("__SIZE__", str(draw.RESOLUTION))
            .replace("__NOTE__", escape(note)).replace("__PLOTS__", plots)
            .replace("__DATA__", json.dumps(data, allow_nan=False)))

"""index.html: a page that plays the run's PNG frames from the file system, with no server.

It opens from the output folder in any current browser (file://...): the frames are the PNG files
pygame rendered beside it, and the figures of every frame are written into the page itself as a
JavaScript array (a page opened from the file system may not read other files, but it may show
images). Play/pause, one frame back or forward, a time slider, the playback speed; beside the frame,
the figures of that step for each run; below it plots.png with a cursor at the current time.
"""
import html
import json
import math

from viewer import draw

FIGURES = ["step", "t (s)", "Newton iterations", "residual (m/s)", "min distance (m)", "contacts sticking",
           "contacts sliding"]

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
  #clock { display: inline-block; white-space: pre; font-variant-numeric: tabular-nums; text-align: left; }
  table { border-collapse: collapse; }
  td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
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
    <option value="0.1">0.1x</option><option value="0.25">0.25x</option><option value="0.5">0.5x</option>
    <option value="1" selected>1x</option><option value="2">2x</option>
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

// The counter keeps one width whatever the frame (so the controls after it stay in place): its
// numbers padded with figure spaces (as wide as a digit) to the widest, and its width fixed at
// that of the widest text.
const lastFrame = run.frames.length - 1, FIGURE_SPACE = "\\u2007";
const frameDigits = String(lastFrame).length;
const timeDigits = Math.max(...run.frames.map(f => f[0].toFixed(2).length));
function clockText(k) {
  return "frame " + String(k).padStart(frameDigits, FIGURE_SPACE) + " / " + lastFrame + ", t = " +
    run.frames[k][0].toFixed(2).padStart(timeDigits, FIGURE_SPACE) + " s";
}
const clock = document.getElementById("clock");
clock.textContent = clockText(lastFrame);
clock.style.minWidth = Math.ceil(clock.getBoundingClientRect().width) + "px";

function showFigures(frame) {
  let rows = "<tr><th></th>" + run.labels.map(l => "<th>" + l + "</th>").join("") + "</tr>";
  run.figures.forEach((name, f) => {
    rows += "<tr><th>" + name + "</th>" +
      frame[1].map(r => "<td>" + (r[f] === null ? "-" : r[f]) + "</td>").join("") + "</tr>";
  });
  rows += "<tr><th>came to rest at t (s)</th>" +
    run.rest.map(t => "<td>" + (t === null ? "not by the end" : t.toFixed(2)) + "</td>").join("") + "</tr>";
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
    const left = run.axis[0] + (run.axis[1] - run.axis[0]) * frame[0] / run.axis[2];
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


def figures(sample):
    """The figures the page shows for a state (FIGURES; None where there is none), from its Sample."""
    s = sample
    residual = s.report.residual if s.report else math.nan
    return [s.step, round(s.t, 6), s.report.newton_iterations if s.report else 0,
            float(f"{residual:.3e}") if math.isfinite(residual) else None,
            float(f"{s.min_distance:.4e}") if math.isfinite(s.min_distance) else None, s.sticking, s.sliding]


def page_html(title, labels, frame_log, fps, axis, plot_width, note="", rest=None):
    """The page's text: `frame_log` (frames.FrameInfo per frame), `fps` frames per simulated
    second, `axis` = (left px, right px, t_max) of plots.png's time axis (None: no plots), `rest` the
    time each run came to rest (None: it did not)."""
    rest = [None if t is None else round(t, 6) for t in (rest or [None] * len(labels))]
    data = {"labels": [html.escape(label) for label in labels], "figures": FIGURES, "fps": fps, "rest": rest,
            "frames": [[round(f.t, 6), f.runs] for f in frame_log],
            "axis": list(axis) if axis else None, "plotWidth": plot_width}
    plots = ('<div id="plotbox"><img id="plots" src="plots.png" alt="plots of the run">'
             '<div id="cursor"></div></div>') if axis else ""
    return (TEMPLATE.replace("__TITLE__", html.escape(title)).replace("__SIZE__", str(draw.RESOLUTION))
            .replace("__NOTE__", html.escape(note)).replace("__PLOTS__", plots)
            .replace("__DATA__", json.dumps(data, allow_nan=False)))

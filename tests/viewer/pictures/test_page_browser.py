"""index.html in a real browser: headless Chromium opens a short run's page from the file system
and the page's own script is driven as a user would: a frame is shown, frames change while it
plays, and the step button moves exactly one frame. Skips, saying why, where no browser is found
(.ci/run installs Debian's `chromium`)."""
import pytest

from helpers.browser import BROWSERS, find_browser, probe_page
import viewer.main


# Appended to a copy of the page: watches it play for a while, then pauses it and presses the
# step buttons, and writes what it saw into the DOM, which Chromium prints (--dump-dom).
PROBE = """
<script>
window.addEventListener("load", () => {
  const img = document.getElementById("frame"), seen = new Set(), out = {};
  out.loaded = img.complete ? img.naturalWidth : 0;
  out.src = img.getAttribute("src");
  const watch = setInterval(() => seen.add(img.dataset.frame), 20);
  setTimeout(() => {
    clearInterval(watch);
    out.seen = Array.from(seen);
    document.getElementById("play").click();                 // pause
    const slider = document.getElementById("slider");
    slider.value = 5;                                         // drag the time slider to frame 5
    slider.dispatchEvent(new Event("input"));
    out.slider = Number(img.dataset.frame);
    const before = Number(img.dataset.frame);
    document.getElementById("forward").click();
    out.forward = [before, Number(img.dataset.frame), img.getAttribute("src")];
    document.getElementById("back").click();
    out.back = Number(img.dataset.frame);
    setTimeout(() => {
      out.steppedLoaded = img.naturalWidth;
      const pre = document.createElement("pre");
      pre.id = "probe";
      pre.textContent = JSON.stringify(out);
      document.body.appendChild(pre);
    }, 200);
  }, 600);
});
</script>
"""


def test_index_html_plays_in_headless_chromium(tmp_path):
    if find_browser() is None:
        pytest.skip(f"no browser found (looked for {', '.join(BROWSERS)}); "
                    ".ci/run installs Debian's chromium")
    out = tmp_path / "run"
    assert viewer.main.main(["--steps", "60", "--out", str(out)]) == 0          # 21 frames
    seen = probe_page(out, PROBE, tmp_path)
    assert seen["loaded"] == 900 and seen["src"].startswith("frame_")    # a frame shown, decoded
    assert len(seen["seen"]) >= 3                                         # it changes while playing
    before, after, src = seen["forward"]
    assert after == before + 1 and src == f"frame_{after:05d}.png"        # step: exactly one frame
    assert seen["slider"] == before == 5 and seen["back"] == 5 and seen["steppedLoaded"] == 900


# Where the frame, the figures' table and plots.png are, and how wide the page is, once loaded.
PLACES = """
<script>
window.addEventListener("load", () => {
  const out = {width: document.documentElement.clientWidth,
               scrollWidth: document.documentElement.scrollWidth};
  for (const id of ["frame", "figures", "plots"]) {
    const r = document.getElementById(id).getBoundingClientRect();
    out[id] = {left: r.left, right: r.right, top: r.top, bottom: r.bottom};
  }
  const pre = document.createElement("pre");
  pre.id = "probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"""


@pytest.fixture(scope="module")
def four_runs(tmp_path_factory):
    """A 4-run tablecloth comparison's page (its table the widest: a column per run)."""
    if find_browser() is None:
        pytest.skip(f"no browser found (looked for {', '.join(BROWSERS)}); "
                    ".ci/run installs Debian's chromium")
    out = tmp_path_factory.mktemp("four") / "run"
    assert viewer.main.main(["--scene", "tablecloth", "--pull-speed", "1,2,4,8", "--steps", "10",
                             "--out", str(out)]) == 0
    return out


@pytest.mark.parametrize("width", [800, 1400, 1920])
def test_nothing_on_the_page_is_cut_at_any_window_width(four_runs, tmp_path, width):
    """Issue 40: at 1400 px the 4-run page cut its table (the frame fixed at 900 px beside it). The
    table goes below the frame where it does not fit beside it (and beside it at 1920 px), the
    frame and plots.png shrink to a window narrower than they are."""
    seen = probe_page(four_runs, PLACES, tmp_path, size=(width, 1000))
    assert seen["scrollWidth"] <= seen["width"]
    for name in ("frame", "figures", "plots"):
        assert 0 <= seen[name]["left"] and seen[name]["right"] <= seen["width"], (name, seen)
    beside = seen["figures"]["top"] < seen["frame"]["bottom"]
    assert beside == (width == 1920), seen

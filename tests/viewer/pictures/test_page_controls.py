"""index.html's controls stay in place while the page plays: headless Chromium shows frames whose
counter and time have one, two and more digits, and every control keeps its position. Skips where no
browser is found, as tests/viewer/pictures/test_page_browser.py does."""
import pytest

from helpers.browser import BROWSERS, find_browser, probe_page
import viewer.main

# Appended to a copy of the page: drags the slider to frames whose counter reads 0, 9, 10 and the
# last (t from 0.00 s to over 10 s), and writes the controls' left edges at each into the DOM.
PROBE = """
<script>
window.addEventListener("load", () => {
  document.getElementById("play").click();                  // pause
  const slider = document.getElementById("slider"), out = [];
  for (const k of [0, 9, 10, Number(slider.max)]) {
    slider.value = k;
    slider.dispatchEvent(new Event("input"));
    out.push(["play", "back", "forward", "slider", "clock", "speed"].map(
      id => document.getElementById(id).getBoundingClientRect().left));
  }
  const pre = document.createElement("pre");
  pre.id = "probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"""


def test_the_controls_stay_in_place_as_the_counter_grows(tmp_path):
    if find_browser() is None:
        pytest.skip(f"no browser found (looked for {', '.join(BROWSERS)}); "
                    ".ci/run installs Debian's chromium")
    out = tmp_path / "run"
    # 220 steps of 0.05 s, a frame every 10: frames 0 to 22, t from 0.00 to 11.00 s
    assert viewer.main.main(["--h", "0.05", "--steps", "220", "--frame-stride", "10", "--no-forces",
                           "--out", str(out)]) == 0
    positions = probe_page(out, PROBE, tmp_path, budget_ms=3000)
    assert len(positions) == 4 and all(p == positions[0] for p in positions), positions

"""A page opened in headless Chromium with a probe script appended, as browser tests drive it."""
import json
import re
import shutil
import subprocess

import pytest

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable", "chrome")


def find_browser():
    return next((path for path in map(shutil.which, BROWSERS) if path), None)


def probe_page(out, probe, tmp_path, budget_ms=5000, size=None):
    """Open `out`/index.html in headless Chromium with `probe` appended (a script that writes JSON
    into <pre id="probe">) and return what it wrote; skips where no browser is found. `size`:
    the window's (width, height) in px."""
    browser = find_browser()
    if browser is None:
        pytest.skip(f"no browser found (looked for {', '.join(BROWSERS)}); "
                    ".ci/run installs Debian's chromium")
    page = (out / "index.html").read_text()
    (out / "probe.html").write_text(page.replace("</body>", probe + "</body>"))
    command = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
               f"--user-data-dir={tmp_path / 'profile'}", f"--virtual-time-budget={budget_ms}",
               *([f"--window-size={size[0]},{size[1]}"] if size else []),
               "--dump-dom", (out / "probe.html").as_uri()]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    found = re.search(r'<pre id="probe">(.*?)</pre>', result.stdout)
    assert found, f"the page did not report (exit {result.returncode}): {result.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"'))

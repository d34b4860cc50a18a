"""What several test modules share, in one place (no test module imports another):

    command.py      the command line run in this process (run_main), tracks as a run records them
    fakes.py        failures staged on purpose (a disk that fills up)
    fd.py           finite differences, and how close a derivative must come to them
    scenes.py       scenes the stability tests build
    chalk.py        the chalk's runs, each stepped once per session, and their stick-slip
    legibility.py   text sizes, contrast and colour distances measured in drawn pixels
    browser.py      a page opened in headless Chromium with a probe script
    checkout.py     a benchmark run on a checkout of another commit

tests/ is laid out like the code: physics/ (the flat modules), scenes/, analysis/,
viewer/<package>/, figures/, benchmarks/, notebooks/.
"""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # the project

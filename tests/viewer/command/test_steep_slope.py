"""Sticking on a steep slope, as the docs give it: run as written from the command line, the
contacts stick. A square dropped axis-aligned onto a 30 degree slope lands on its uphill corner,
swings onto its face and over its downhill corner (from the face it takes only 2.4 cm of rise of the
centre of mass), and the lecture's soft square (k = 2e4) shears under the slope's pull until it
rolls over; so the example turns the scene instead: flat ground, gravity tilted by 30 degrees
(9.81 (sin 30, -cos 30)), the square resting on it 5 mm up, the 30 degree slope in its own frame."""
import csv
import math

from helpers.command import run_main

EXAMPLE = "--slope-normal 0,1 --gravity 4.905,-8.496 --center 0,-0.495 --mu 0.7 --k 1e6"


def test_the_steep_slope_example_sticks(tmp_path):
    """tan 30 = 0.577 < mu = 0.7: after settling (0.3 s), no contact node slides, at least three
    stick (the uphill one may lift: the friction at the base and the pull at the centre of mass
    tilt the load downhill), and the centre of mass creeps by less than 2 eps_v over the next
    0.7 s, where sliding without friction would take it 1.2 m."""
    assert math.isclose(math.degrees(math.atan2(4.905, 8.496)), 30.0, abs_tol=1e-3)
    code, lines = run_main(*EXAMPLE.split(), "--duration", "1", "--no-frames",
                           "--out", str(tmp_path))
    assert code == 0, lines
    with open(tmp_path / "log.csv") as f:
        settled = [r for r in csv.DictReader(f) if float(r["t"]) >= 0.3 - 1e-9]
    assert len(settled) == 71
    assert all(int(r["contacts_sliding"]) == 0 for r in settled)
    assert all(int(r["contacts_sticking"]) >= 3 for r in settled)
    creep = abs(float(settled[-1]["com_x"]) - float(settled[0]["com_x"]))
    assert creep < 2 * 1e-3 * 0.7

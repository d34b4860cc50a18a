"""Slide "Approximation: smooth dynamic-static transition": f1 replaces Coulomb's f, and
f0'(y) = f1(y / hhat). Every curve is FrictionEnergy's own f0 or f1_div_vbarnorm, at hhat = h."""
from types import SimpleNamespace

import numpy as np

import FrictionEnergy
import simulator
from figures.page import BLACK, GREY, RED, Page
from viewer.pictures.draw import run_color

EPSV_FACTORS = (0.5, 1.0, 2.0)      # eps_v as multiples of the default's


def compute(epsv=simulator.DEFAULTS["epsv"], hhat=simulator.DEFAULTS["h"], points=801):
    """f1 at three eps_v, f0, and f0'(y) = (f0(||vbar|| + d) - f0(||vbar|| - d)) / (2 d hhat)
    against f1(y / hhat), ||vbar|| > 0: truncation d^2 / (3 eps_v^2) = 3e-11, round-off ~9e-11."""
    vbarnorm = np.linspace(0.0, 4.0 * epsv, points)             # m/s
    d, checked = 1e-5 * epsv, vbarnorm[1:]
    f0_up, f0_down = (FrictionEnergy.f0(checked + s, epsv, hhat) for s in (d, -d))
    df0_dy = (f0_up - f0_down) / (2 * d * hhat)
    epsvs = [factor * epsv for factor in EPSV_FACTORS]
    f1s = [vbarnorm * FrictionEnergy.f1_div_vbarnorm(vbarnorm, e) for e in epsvs]
    f1_default = f1s[EPSV_FACTORS.index(1.0)][1:]
    return SimpleNamespace(vbarnorm=vbarnorm, checked=checked, epsv=epsv, hhat=hhat, f1s=f1s,
                           f1=f1_default, epsvs=epsvs, f0=FrictionEnergy.f0(vbarnorm, epsv, hhat),
                           df0_dy=df0_dy, max_error=float(np.abs(df0_dy - f1_default).max()))


def draw(r):
    """Coulomb's f and f1 (three eps_v); f0; f0' by differences against f1(y / hhat); their gap."""
    mm_s, um, at = 1e3 * r.vbarnorm, 1e6 * r.hhat * r.vbarnorm, 1e3 * r.checked   # y in um
    page = Page("Mollification: f1 replaces Coulomb's f, and f0'(y) = f1(y / hhat)", 4, [
        "f1 is FrictionEnergy.f1_div_vbarnorm times ||vbar||, "
        f"f0 is FrictionEnergy.f0 at hhat = h = {r.hhat:g} s.",
        "Coulomb's f jumps from the interval [0, 1] at rest to 1; "
        "f1 rises from 0 to 1 over [0, eps_v), with a continuous slope (C^1).",
        f"Checked on {len(r.checked)} points in (0, {r.checked[-1]:g}] m/s, f0' by a central "
        f"difference: max |f0'(y) - f1(y / hhat)| = {r.max_error:.1e}."])
    ax = page.axes(0, mm_s[-1], 0.0, 1.0, "f(||vbar||), no unit, against ||vbar|| (mm/s)", "mm/s",
                   "f")
    ax.line([0.0, 0.0, mm_s[-1]], [0.0, 1.0, 1.0], BLACK, 3)    # [0, 1] at rest, then 1
    ax.legend(BLACK, "Coulomb's f")
    for i, (epsv, values) in enumerate(zip(r.epsvs, r.f1s)):
        ax.line(mm_s, values, run_color(i + 1))
        star = " *" if epsv == r.epsv else ""
        ax.legend(run_color(i + 1), f"f1, eps_v = {1e3 * epsv:g} mm/s{star}")
    ax.legend((255, 255, 255), "* the default")
    ax = page.axes(1, mm_s[-1], 0.0, um[-1], "f0(y) (micrometres) against ||vbar|| (mm/s), "
                   "y = ||vbar|| hhat", "mm/s", "f0 (um)")
    ax.line(mm_s, um, GREY, 1)
    ax.legend(GREY, "y (Coulomb's: f0 = y)")
    ax.line(mm_s, 1e6 * r.f0, run_color(2))
    ax.legend(run_color(2), "f0, default eps_v")
    ax = page.axes(2, mm_s[-1], 0.0, 1.0,
                   "f0'(y) by finite differences, on f1(y / hhat), against ||vbar|| (mm/s)", "mm/s",
                   "f0', f1")
    ax.line(at, r.f1, run_color(2), 3)
    ax.legend(run_color(2), "f1(y / hhat)")
    ax.markers(at[7::16], r.df0_dy[7::16], BLACK)
    ax.legend(BLACK, "f0'(y), every 16th point")
    ax = page.axes(3, mm_s[-1], 1e-16, 1e-6, "|f0'(y) - f1(y / hhat)| (log) against ||vbar|| "
                   "(mm/s)", "mm/s", "difference", log=True)
    ax.dots(at, np.maximum(np.abs(r.df0_dy - r.f1), 1e-16), BLACK)
    ax.legend(BLACK, "at each point (0: at 1e-16)")
    ax.hline(1e-8, RED, "1e-8, the test's bound")
    return page

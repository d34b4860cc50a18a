"""Project contracts: CI runs the README's test command; importing opens no window."""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def readme_commands():
    text = open(os.path.join(ROOT, "README.md")).read()
    return re.findall(r"```sh\n(.*?)\n```", text, re.S)


def test_ci_runs_exactly_the_readme_test_command():
    main_job, tests = readme_commands()[:2]
    assert main_job.endswith("python simulator.py") and tests.endswith("python -m pytest -q")
    ci = open(os.path.join(ROOT, ".ci", "run")).read().splitlines()
    assert tests in ci


def test_importing_every_module_needs_no_display_and_no_pygame():
    code = ("import sys, InertiaEnergy, MassSpringEnergy, GravityEnergy, BarrierEnergy, FrictionEnergy, "
            "time_integrator, square_mesh, utils, simulator; print('pygame' in sys.modules)")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "SDL_VIDEODRIVER")}
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == "False", out.stderr

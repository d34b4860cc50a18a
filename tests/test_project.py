"""Project contracts: CI runs the README's test command; importing opens no window; imports run
one way; modules and test files stay small."""
import ast
import glob
import os
import re
import subprocess
import sys

from helpers import ROOT

TESTS = os.path.join(ROOT, "tests")


def readme_commands():
    text = open(os.path.join(ROOT, "README.md")).read()
    return re.findall(r"```sh\n(.*?)\n```", text, re.S)


def test_ci_runs_exactly_the_readme_test_command():
    main_job, tests = readme_commands()[:2]
    assert main_job.endswith("python simulator.py") and tests.endswith("python -m pytest -q")
    ci = open(os.path.join(ROOT, ".ci", "run")).read().splitlines()
    assert tests in ci


def test_importing_every_module_needs_no_display_and_no_pygame():
    code = ("import sys, InertiaEnergy, MassSpringEnergy, GravityEnergy, BarrierEnergy, "
            "FrictionEnergy, HandEnergy, FingerEnergy, time_integrator, square_mesh, utils, "
            "simulator; "
            "print('pygame' in sys.modules)")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "SDL_VIDEODRIVER")}
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == "False", out.stderr


# the layers, lowest first: a module imports only from layers below its own, or its own package
# (FingerEnergy is BarrierEnergy through moving planes: one layer above the energies)
ENERGIES = {"InertiaEnergy", "MassSpringEnergy", "GravityEnergy", "BarrierEnergy", "FrictionEnergy",
            "HandEnergy", "square_mesh"}
LAYERS = [{"utils"}, ENERGIES, {"FingerEnergy"}, {"time_integrator", "scenes"}, {"simulator"},
          {"closed_forms"}, {"analysis"}, {"viewer.output"}, {"viewer.pictures"},
          {"viewer.command"}, {"viewer.demo"}, {"viewer.main"}, {"benchmarks", "figures"}]
PACKAGES = ("scenes", "analysis", "viewer", "viewer/output", "viewer/pictures", "viewer/command",
            "viewer/demo", "figures", "benchmarks")
PRIVATE_READS = ("simulator", "time_integrator", "utils", "BarrierEnergy", "FrictionEnergy",
                 "recording", "run", "files", "cli", "draw", "window", "live", "newton_view",
                 "frames", "progress", "run_pictures", "log", "page", "marks", "diagnostics",
                 "stick_slip", "closing", "scene")


def layer(module):
    """The layer of `module` (dotted), by its package: viewer's by its sub-package."""
    parts = module.split(".")
    names = [".".join(parts[:2])] if parts[0] == "viewer" and len(parts) > 1 else []
    return next((i for name in names + [parts[0]] for i, layer_names in enumerate(LAYERS)
                 if name in layer_names), None)


def package(module):
    """The package a module belongs to ('' for the flat files); viewer's by its sub-package."""
    parts = module.split(".")[:-1]
    return ".".join(parts[:2])


def sources():
    """Every project module outside tests/, as (path, dotted name)."""
    paths = [p for folder in ("",) + PACKAGES
             for p in glob.glob(os.path.join(ROOT, folder, "*.py"))]
    return [(p, os.path.relpath(p, ROOT)[:-3].replace(os.sep, ".")) for p in paths]


def project_imports(path):
    """(module imported, names taken from it, line) for each import of a project module in the
    file, but those under `if __name__ == "__main__":` (the command line's entry)."""
    tree = ast.parse(open(path).read())
    main_blocks = [node for node in tree.body
                   if isinstance(node, ast.If) and "__main__" in ast.unparse(node.test)]
    skip = {id(n) for block in main_blocks for n in ast.walk(block)}
    found = []
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            found += [(alias.name, [], node.lineno) for alias in node.names
                      if layer(alias.name) is not None]
        elif isinstance(node, ast.ImportFrom) and node.module and layer(node.module) is not None:
            found.append((node.module, [alias.name for alias in node.names], node.lineno))
    return found


def imported_modules(path):
    """Every module the file imports (an `import a.b` or a `from a.b import c`: 'a.b')."""
    found = []
    for node in ast.walk(ast.parse(open(path).read())):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            found.append(node.module or "")
    return found


def test_imports_run_one_way_and_take_no_private_names():
    """figures, benchmarks -> viewer (main -> demo -> command -> pictures -> output) -> analysis ->
    closed_forms -> simulator -> time_integrator, scenes -> energies -> utils: never upward
    (within a package, any way), never a module's private `_name`."""
    found = sources()
    assert len(found) > 40
    for path, module in found:
        for imported, names, line in project_imports(path):
            same = package(module) != "" and imported.startswith(package(module))
            where = f"{module}:{line} imports"
            assert layer(imported) < layer(module) or same, f"{where} {imported} (upward)"
            assert not [n for n in names if n.startswith("_")], f"{where} private {names}"
        text = open(path).read()
        for other in PRIVATE_READS:
            assert not re.search(rf"\b{other}\._[a-z]", text), \
                f"{module} reads a private name of {other}"


def test_the_readme_notebook_code_runs_as_written():
    """README's Python blocks, run from the repository's folder as it says."""
    blocks = re.findall(r"```python\n(.*?)```", open(os.path.join(ROOT, "README.md")).read(), re.S)
    assert len(blocks) >= 2
    for code in blocks:
        out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                             text=True, timeout=120,
                             env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
        assert out.returncode == 0, out.stderr


def test_rooms_stay_small_and_tests_import_no_other_test():
    """No module outside tests/ over 400 lines (one job per module); no test module imports another
    test module (what they share lives in tests/helpers/); neither a shared helper nor a test of
    the physics imports benchmarks (only a benchmark's own test may)."""
    sizes = [(os.path.relpath(p, ROOT), len(open(p).read().splitlines())) for p, _ in sources()]
    long = [f"{path} ({n})" for path, n in sizes if n > 400]
    assert not long, f"modules over 400 lines: {long}"
    every = glob.glob(os.path.join(TESTS, "**", "*.py"), recursive=True)
    test_modules = {os.path.basename(p)[:-3] for p in every
                    if os.path.basename(p).startswith("test_")}
    benchmark_tests = os.path.join(TESTS, "benchmarks", "")
    for path in every:
        name = os.path.basename(path)[:-3]
        for module in imported_modules(path):
            assert module.split(".")[-1] not in test_modules, \
                f"{name} imports the test module {module}"
            if module.split(".")[0] == "benchmarks":
                assert path.startswith(benchmark_tests), \
                    f"{name} imports {module}: only a benchmark's test"


def test_tests_are_laid_out_like_the_code_and_the_physics_needs_no_pygame():
    """tests/ mirrors the packages; no test file over 500 lines; the tests of the physics (the flat
    modules, tests/physics) and of the scenes import nothing that draws, so that they run without
    pygame: `python -m pytest tests/physics tests/scenes` (README)."""
    for folder in ("physics", "scenes", "analysis", "viewer/command", "viewer/pictures",
                   "viewer/demo", "viewer/output", "figures", "benchmarks", "notebooks"):
        assert glob.glob(os.path.join(TESTS, folder, "test_*.py")), folder
    files = glob.glob(os.path.join(TESTS, "**", "*.py"), recursive=True)
    long = [os.path.relpath(p, TESTS) for p in files if len(open(p).read().splitlines()) > 500]
    assert not long, f"test files over 500 lines: {long}"
    drawing = ("viewer", "figures", "benchmarks", "pygame", "helpers.command", "helpers.fakes",
               "helpers.legibility", "helpers.browser")
    physics = glob.glob(os.path.join(TESTS, "physics", "*.py"))
    for path in physics + glob.glob(os.path.join(TESTS, "scenes", "*.py")):
        for name in imported_modules(path):
            assert not name.startswith(drawing), f"{os.path.relpath(path, TESTS)} imports {name}"

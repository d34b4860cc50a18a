"""notebooks/lecture.ipynb: every cell runs in a real Jupyter kernel of this interpreter, from the
notebook's folder; the saved notebook carries its outputs (it reads on GitHub without being run)
and they are the outputs it gives now. A copy elsewhere runs its cells up to the long runs (the mu
comparison on): they read and write no file, so where the notebook is changes nothing in them, and
the run in place checks their numbers. The two run at once, each in a kernel of its own.

After editing the notebook, execute it and save it with its outputs:
python tests/notebooks/test_notebook.py
"""
import asyncio
import contextlib
import json
import math
import os
import re
import sys
import tempfile

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FOLDER = os.path.join(ROOT, "notebooks")
NOTEBOOK = os.path.join(FOLDER, "lecture.ipynb")
CELL_TIMEOUT = 600      # s per cell; the slowest, three runs of 600 steps, takes about 5 s here
MAX_BYTES = 300_000     # the saved notebook, its one picture included
INTERPRETER = "import sys, json; print(json.dumps([sys.executable, sys.prefix]))"
REST = re.compile(r"mu = (\S+)\s*: (?:sticks at t = (\S+) s, creeps \S+ mm/s|never sticks)")


def jupyter():
    """nbformat and nbclient, or a failure saying how to install them (the test command does)."""
    try:
        import ipykernel  # noqa: F401  (the kernel the notebook runs in)
        import nbclient
        import nbformat
    except ImportError as err:
        pytest.fail(f"{err}: the notebook's test needs nbclient and ipykernel, "
                    "pip install -r requirements-test.txt")
    return nbformat, nbclient


@contextlib.contextmanager
def this_interpreter(kernelspec):
    """The notebook names its kernel ("python3", as Jupyter does); within this block that name
    is a kernelspec of sys.executable, first on JUPYTER_PATH, so that a "python3" spec of another
    Python (a user's own, ~/.local/share/jupyter/kernels) cannot run it instead."""
    saved = os.environ.get("JUPYTER_PATH")
    with tempfile.TemporaryDirectory() as path:
        spec = os.path.join(path, "kernels", kernelspec.name)
        os.makedirs(spec)
        argv = [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]
        with open(os.path.join(spec, "kernel.json"), "w") as f:
            json.dump({"argv": argv, "display_name": kernelspec.display_name,
                       "language": "python"}, f)
        os.environ["JUPYTER_PATH"] = path if saved is None else os.pathsep.join([path, saved])
        try:
            yield
        finally:
            if saved is None:
                del os.environ["JUPYTER_PATH"]
            else:
                os.environ["JUPYTER_PATH"] = saved


def execute(*runs):
    """Run every cell of each (notebook, folder, environment) in `runs` (in place), all at once,
    each in a kernel of this interpreter started in its folder with its environment. Returns, for
    each, None or the exception it raised."""
    _, nbclient = jupyter()
    clients = [nbclient.NotebookClient(nb, timeout=CELL_TIMEOUT, record_timing=False,
                                       resources={"metadata": {"path": folder}})
               for nb, folder, _ in runs]

    async def all_at_once():
        return await asyncio.gather(*(client.async_execute(env=env)
                                      for client, (_, _, env) in zip(clients, runs)),
                                    return_exceptions=True)
    with this_interpreter(runs[0][0].metadata.kernelspec):
        done = asyncio.run(all_at_once())
    return [error if isinstance(error, BaseException) else None for error in done]


def text(cell):
    """A code cell's printed text (stream outputs and plain-text results), joined."""
    return "".join(out.get("text", "") + out.get("data", {}).get("text/plain", "")
                   for out in cell.outputs)


def rest_times(nb):
    """{mu: when the mu comparison prints it sticks (and creeps), None for never} of a run
    notebook."""
    found = [m for cell in nb.cells if cell.cell_type == "code" for m in REST.finditer(text(cell))]
    return {float(mu): None if t is None else float(t) for mu, t in (m.groups() for m in found)}


def long_runs(nb):
    """The index of the cell of the mu comparison, the first of the long runs (three runs of 600
    steps, then the tablecloth's and the grasp's: about 5 of the notebook's 6 s of CPU): the
    first whose saved output says a rest time."""
    return next(i for i, cell in enumerate(nb.cells)
                if cell.cell_type == "code" and REST.search(text(cell)))


def read(path=NOTEBOOK):
    nbformat, _ = jupyter()
    return nbformat.read(path, as_version=4)


def listing():
    """The files of the repository's folder and of notebooks/, but Python's bytecode caches."""
    return [sorted(set(os.listdir(folder)) - {"__pycache__"}) for folder in (ROOT, FOLDER)]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The notebook run twice at once: from its own folder with no PYTHONPATH (its first cell
    finds the repository above it), with a last cell added that prints which Python ran it; and
    a copy in another folder (one with a space and a non-ASCII letter) with PYTHONPATH naming the
    repository, its cells before the mu comparison (`long_runs`). {"here", "copy": (the run
    notebook, its error or None)}, the copy's folder, and the listing of the repository before
    and after."""
    nbformat, _ = jupyter()
    here = read()
    here.cells.append(nbformat.v4.new_code_cell(INTERPRETER))      # the copy in memory only
    folder = tmp_path_factory.mktemp("notes") / "my notes é"
    folder.mkdir()
    nbformat.write(read(), str(folder / "lecture.ipynb"))
    there = read(str(folder / "lecture.ipynb"))
    del there.cells[long_runs(there):]                              # in memory only
    no_path = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    before = listing()
    errors = execute((here, FOLDER, no_path), (there, str(folder), {**no_path, "PYTHONPATH": ROOT}))
    return {"here": (here, errors[0]), "copy": (there, errors[1])}, folder, before, listing()


def ran(result, what):
    """The run notebook, or a failure naming the cell that failed."""
    nb, error = result
    _, nbclient = jupyter()
    if isinstance(error, nbclient.exceptions.CellExecutionError):
        pytest.fail(f"a cell of {what} failed:\n{error}")
    if error is not None:
        raise error
    return nb


def test_the_saved_notebook_carries_its_outputs():
    """Every code cell was run, in order from the top in one kernel, without an error, and shows
    what it printed; the file stays small enough to read on GitHub."""
    code = [cell for cell in read().cells if cell.cell_type == "code"]
    assert len(code) >= 10
    counts = [cell.execution_count for cell in code]
    assert counts == list(range(1, len(code) + 1)), "not saved executed, in order"
    for cell in code:
        assert cell.outputs, f"a cell saved without output: {cell.source[:80]!r}"
        errors = [out for out in cell.outputs if out.output_type == "error"]
        assert not errors, f"an error saved: {cell.source[:80]!r}"
    pictures = [out for cell in code for out in cell.outputs if "image/png" in out.get("data", {})]
    assert pictures, "the mollifier's figure"
    assert set(rest_times(read())) == {0.1, 0.11, 0.2}
    assert os.path.getsize(NOTEBOOK) < MAX_BYTES


def tolerance(mu):
    """How far two machines' times of sticking may differ. Newton stops once ||p||_inf / h <= tol,
    so the two runs' velocities may differ by about tol (m/s); a rigid block decelerates on the
    slope at g (mu cos - sin), so its stop moves by tol / that, plus one step h for where eps_v is
    crossed: 0.11 s for mu = 0.11, 0.02 s for mu = 0.2."""
    import simulator
    g = math.hypot(*simulator.DEFAULTS["gravity"])
    nx, ny = simulator.DEFAULTS["slope"]
    cos, sin = ny / math.hypot(nx, ny), nx / math.hypot(nx, ny)
    return simulator.DEFAULTS["tol"] / (g * (mu * cos - sin)) + simulator.DEFAULTS["h"]


def test_the_notebook_runs_in_a_kernel_and_gives_its_saved_numbers(runs):
    """From its own folder, with nothing set: its first cell finds the repository above it."""
    results, _, before, after = runs
    nb = ran(results["here"], NOTEBOOK)
    assert json.loads(text(nb.cells[-1])) == [sys.executable, sys.prefix]
    assert after == before, "the notebook wrote into the repository"
    now, then = rest_times(nb), rest_times(read())
    assert now[0.1] is None and then[0.1] is None                 # the lecture: 0.1 keeps sliding
    for mu in (0.11, 0.2):
        assert abs(now[mu] - then[mu]) <= tolerance(mu), (mu, now[mu], then[mu])
    # docs/command-line.md: about 5.5 s and 2.8 s
    assert 5.3 < now[0.11] < 5.8 and 2.6 < now[0.2] < 3.0


def test_a_copy_elsewhere_runs_with_the_repository_on_pythonpath(runs):
    """README: a copy of the notebook in another folder runs once PYTHONPATH names the
    repository, and writes nothing into either folder: each cell it ran (those before the long
    runs) printed what the same cell printed in place, but the line naming the repository."""
    results, folder, before, after = runs
    nb = ran(results["copy"], "the copy")
    assert os.path.samefile(folder / text(nb.cells[2]).split(": ", 1)[1].strip(), ROOT)
    in_place = ran(results["here"], NOTEBOOK)
    assert len(nb.cells) == long_runs(read()) > 20
    for cell, same in zip(nb.cells[3:], in_place.cells[3:]):
        assert cell.source == same.source, cell.source[:80]
        if cell.cell_type == "code":
            assert text(cell) == text(same), cell.source[:80]
    assert after == before and os.listdir(folder) == ["lecture.ipynb"]


if __name__ == "__main__":      # execute the notebook and save it with its outputs
    sys.path.insert(0, ROOT)
    nb = read()
    (error,) = execute((nb, FOLDER, dict(os.environ)))
    if error is not None:
        raise error
    jupyter()[0].write(nb, NOTEBOOK)
    print(f"{NOTEBOOK}: executed and saved, {os.path.getsize(NOTEBOOK)} bytes, "
          f"rest times {rest_times(nb)}")

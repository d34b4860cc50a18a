"""notebooks/lecture.ipynb: every cell runs in a real Jupyter kernel of this interpreter, from the
notebook's folder; the saved notebook carries its outputs (it reads on GitHub without being run) and
they are the outputs it gives now.

After editing the notebook, execute it and save it with its outputs: python tests/notebooks/test_notebook.py
"""
import copy
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
CELL_TIMEOUT = 600          # s per cell; the slowest, three runs of 600 steps, takes about 5 s here
MAX_BYTES = 300_000         # the saved notebook, its one picture included
INTERPRETER = "import sys, json; print(json.dumps([sys.executable, sys.prefix]))"
REST = re.compile(r"mu = (\S+)\s*: (?:comes to rest at t = (\S+) s|never comes to rest)")


def jupyter():
    """nbformat and nbclient, or a failure saying how to install them (the test command does)."""
    try:
        import ipykernel  # noqa: F401  (the kernel the notebook runs in)
        import nbclient
        import nbformat
    except ImportError as err:
        pytest.fail(f"{err}: the notebook's test needs nbclient and ipykernel, pip install -r requirements-test.txt")
    return nbformat, nbclient


def execute(nb, folder=FOLDER):
    """Run every cell of `nb` (in place) in a kernel of this interpreter, started in `folder`.

    The notebook names the kernel "python3", as Jupyter does; here that name is resolved through a
    kernelspec written for sys.executable, first on JUPYTER_PATH, so a "python3" spec of another Python
    (a user's own, ~/.local/share/jupyter/kernels) cannot run it instead."""
    nbformat, nbclient = jupyter()
    saved_path = os.environ.get("JUPYTER_PATH")
    with tempfile.TemporaryDirectory() as path:
        spec = os.path.join(path, "kernels", nb.metadata.kernelspec.name)
        os.makedirs(spec)
        with open(os.path.join(spec, "kernel.json"), "w") as f:
            json.dump({"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
                       "display_name": nb.metadata.kernelspec.display_name, "language": "python"}, f)
        os.environ["JUPYTER_PATH"] = path if saved_path is None else os.pathsep.join([path, saved_path])
        try:
            nbclient.NotebookClient(nb, timeout=CELL_TIMEOUT, record_timing=False,
                                    resources={"metadata": {"path": folder}}).execute()
        finally:
            if saved_path is None:
                del os.environ["JUPYTER_PATH"]
            else:
                os.environ["JUPYTER_PATH"] = saved_path
    return nb


def text(cell):
    """A code cell's printed text (stream outputs and plain-text results), joined."""
    return "".join(out.get("text", "") + out.get("data", {}).get("text/plain", "") for out in cell.outputs)


def rest_times(nb):
    """{mu: the time the mu comparison prints it comes to rest, None for never} from a run notebook."""
    found = [m for cell in nb.cells if cell.cell_type == "code" for m in REST.finditer(text(cell))]
    return {float(mu): None if t is None else float(t) for mu, t in (m.groups() for m in found)}


def read():
    nbformat, _ = jupyter()
    return nbformat.read(NOTEBOOK, as_version=4)


def test_the_saved_notebook_carries_its_outputs():
    """Every code cell was run, in order from the top in one kernel, without an error, and shows what it
    printed; the file stays small enough to read on GitHub."""
    nb = read()
    code = [cell for cell in nb.cells if cell.cell_type == "code"]
    assert len(code) >= 10
    assert [cell.execution_count for cell in code] == list(range(1, len(code) + 1)), "not saved executed, in order"
    for cell in code:
        assert cell.outputs, f"a cell saved without output: {cell.source[:80]!r}"
        assert not [out for out in cell.outputs if out.output_type == "error"], f"an error saved: {cell.source[:80]!r}"
    assert any("image/png" in out.get("data", {}) for cell in code for out in cell.outputs), "the mollifier's figure"
    assert set(rest_times(nb)) == {0.1, 0.11, 0.2}
    assert os.path.getsize(NOTEBOOK) < MAX_BYTES


def listing():
    """The files of the repository's folder and of notebooks/, but Python's bytecode caches."""
    return [sorted(set(os.listdir(folder)) - {"__pycache__"}) for folder in (ROOT, FOLDER)]


def tolerance(mu):
    """How far two machines' rest times may differ. Newton stops once ||p||_inf / h <= tol, so the two
    runs' velocities may differ by about tol (m/s); a rigid block decelerates on the slope at
    g (mu cos - sin), so its stop moves by tol / that, plus one step h for where eps_v is crossed:
    0.11 s for mu = 0.11, 0.02 s for mu = 0.2."""
    import simulator
    g = math.hypot(*simulator.DEFAULTS["gravity"])
    nx, ny = simulator.DEFAULTS["slope"]
    cos, sin = ny / math.hypot(nx, ny), nx / math.hypot(nx, ny)
    return simulator.DEFAULTS["tol"] / (g * (mu * cos - sin)) + simulator.DEFAULTS["h"]


def test_the_notebook_runs_in_a_kernel_and_gives_its_saved_numbers(monkeypatch):
    """From its own folder, with nothing set: its first cell finds the repository above it."""
    monkeypatch.delenv("PYTHONPATH", raising=False)
    saved = read()
    nbformat, nbclient = jupyter()
    nb = copy.deepcopy(saved)
    nb.cells.append(nbformat.v4.new_code_cell(INTERPRETER))      # which Python ran it (the copy only)
    before = listing()
    try:
        execute(nb)
    except nbclient.exceptions.CellExecutionError as err:
        pytest.fail(f"a cell of {NOTEBOOK} failed:\n{err}")
    assert json.loads(text(nb.cells[-1])) == [sys.executable, sys.prefix]
    assert listing() == before, "the notebook wrote into the repository"

    now, then = rest_times(nb), rest_times(saved)
    assert now[0.1] is None and then[0.1] is None                 # the lecture: 0.1 keeps sliding
    for mu in (0.11, 0.2):
        assert abs(now[mu] - then[mu]) <= tolerance(mu), (mu, now[mu], then[mu])
    assert 5.3 < now[0.11] < 5.8 and 2.6 < now[0.2] < 3.0           # docs/command-line.md: about 5.5 s and 2.8 s


if __name__ == "__main__":          # python tests/notebooks/test_notebook.py: execute the notebook and save it with its outputs
    sys.path.insert(0, ROOT)
    nb = execute(read())
    jupyter()[0].write(nb, NOTEBOOK)
    print(f"{NOTEBOOK}: executed and saved, {os.path.getsize(NOTEBOOK)} bytes, rest times {rest_times(nb)}")


def test_a_copy_elsewhere_runs_with_the_repository_on_pythonpath(tmp_path, monkeypatch):
    """README: a copy of the notebook in another folder (here one with a space and a non-ASCII letter)
    runs once PYTHONPATH names the repository, and writes nothing into either folder."""
    folder = tmp_path / "my notes é"
    folder.mkdir()
    nbformat, nbclient = jupyter()
    nbformat.write(read(), str(folder / "lecture.ipynb"))
    monkeypatch.setenv("PYTHONPATH", ROOT)
    before = listing()
    try:
        nb = execute(nbformat.read(str(folder / "lecture.ipynb"), as_version=4), str(folder))
    except nbclient.exceptions.CellExecutionError as err:
        pytest.fail(f"a cell of the copy failed:\n{err}")
    assert os.path.samefile(folder / text(nb.cells[2]).split(": ", 1)[1].strip(), ROOT)
    assert set(rest_times(nb)) == {0.1, 0.11, 0.2}
    assert listing() == before and os.listdir(folder) == ["lecture.ipynb"]

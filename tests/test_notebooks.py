"""Every notebook in notebooks/ runs top to bottom, headless (no viewer, no browser).

The notebooks of one test process share one kernel (started once: its Python, Pinocchio and
matplotlib imports are most of a small notebook's cost). Each notebook starts from an empty
namespace (``%reset -f``) in its own working folder, so none can lean on a name or a file another
one left behind; what stays is only the kernel's already-imported modules.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

pytestmark = [pytest.mark.integration, pytest.mark.slow]

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))


@pytest.fixture(scope="module")
def kernel():
    """A python3 kernel, headless (Agg figures, no viewer), shut down after the module's notebooks."""
    from jupyter_client.manager import KernelManager

    km = KernelManager(kernel_name="python3")
    km.start_kernel(env={**os.environ, "MPLBACKEND": "Agg", "PASIBOT_HEADLESS": "1"})
    try:
        yield km
    finally:
        km.shutdown_kernel(now=True)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, tmp_path, kernel):
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert not cell.get("outputs"), f"{path.name} is committed with outputs"
    fresh = f"%reset -f\nimport os\nos.chdir({str(tmp_path)!r})\ndel os"
    nb.cells.insert(0, nbformat.v4.new_code_cell(fresh))
    client = NotebookClient(nb, km=kernel, timeout=600, kernel_name="python3")
    client.execute()
    assert client.owns_km is False  # the shared kernel stays up for the next notebook

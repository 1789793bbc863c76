"""The default bed case's run stays lean: what it imports with --no-plots, and the runner's bed
surface by the element lengths it is given equal to the one that works them out."""
import subprocess
import sys

import numpy as np
import pytest

from twofluid import postprocess as pp

# the command's main in a process of its own; at its end (Signals.leave) the modules it imported
RUN = r"""
import os, sys
sys.argv = ["twofluid", "run", "fluidized-bed-step", "--no-plots", "--quiet", "--out", sys.argv[1]]
from twofluid.cli import main
from twofluid.command_signals import Signals

def leave(rc):
    names = ("logging", "threading", "importlib.resources", "zipfile", "matplotlib", "scipy", "tqdm")
    print("IMPORTED", sorted(m for m in names if m in sys.modules), flush=True)
    os._exit(rc)

Signals.leave = staticmethod(leave)
sys.exit(main())
"""


def test_a_bed_run_without_plots_imports_none_of_what_it_does_not_use(tmp_path):
    r = subprocess.run([sys.executable, "-c", RUN, str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    line = [ln for ln in r.stdout.splitlines() if ln.startswith("IMPORTED")]
    assert line == ["IMPORTED []"], r.stdout


@pytest.mark.parametrize("seed", range(20))
def test_interface_height_with_the_element_lengths_is_the_same_number(seed):
    rng = np.random.default_rng(seed)
    ne = int(rng.integers(1, 40))
    faces = np.cumsum(np.concatenate([[0.3], rng.uniform(0.01, 0.1, ne)]))  # uneven elements
    n = rng.choice([rng.uniform(0.4, 0.7, ne), np.ones(ne), np.minimum(rng.uniform(0.4, 1.3, ne), 1.0)])
    if seed % 5 == 0:
        n[-1] = 0.5  # the top element in the bed
    lengths = faces[1:] - faces[:-1]
    for thr in (0.75, 0.95, 0.3):
        a = pp.interface_height(faces, n, thr)
        b = pp.interface_height(faces, n, thr, lengths)
        assert a == b or (np.isnan(a) and np.isnan(b))
        below = np.flatnonzero(n < thr)
        if below.size:  # the definition, written out: the highest element below the threshold holds it
            k = int(below[-1])
            r = max(k - 1, 0)
            solids = float(np.dot(1.0 - np.minimum(n[k:], 1.0), faces[k + 1:] - faces[k:-1]))
            assert a == float(faces[k] + solids / (1.0 - n[r]) - faces[0])
        else:
            assert a == 0.0

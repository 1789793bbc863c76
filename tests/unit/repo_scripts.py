"""The repository's scripts (scripts/, benchmarks/) loaded as modules for the tests that check them."""
import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def load_script(relative: str):
    """The module of the script at ``relative`` (from the repository's root, e.g.
    ``"scripts/idealised_spreads.py"``), executed afresh."""
    path = ROOT / relative
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

"""Options of the test suite: ``--update-golden`` rewrites the golden outputs of tests/golden/
(tests/cases/test_golden_1d.py) instead of comparing with them: the one way they change."""


def pytest_addoption(parser):
    parser.addoption("--update-golden", action="store_true", default=False,
                     help="rewrite tests/golden/*.json from this run (review the diff before committing)")

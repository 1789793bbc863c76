"""The 1D runner's test of whether a step landed on an output time: the same answers as the plain
scan over every output time it replaces."""
import numpy as np

from twofluid.runners.column_1d import _at_output_time


def _scan(t, out_times):
    return any(abs(t - tt) < 1e-9 * max(1.0, tt) for tt in out_times)


def test_the_same_as_the_scan_over_every_output_time():
    rng = np.random.default_rng(7)
    for end in (0.5, 1.0, 80.0, 3600.0):
        out_times = sorted({0.0, end, *(float(x) for x in rng.uniform(0.0, end, 6)), 1e-10, 1.0 - 5e-10})
        near = 1e-9 * max(1.0, out_times[-1])
        probes = [tt + d * 1e-9 * max(1.0, tt) for tt in out_times for d in (-1.5, -1.0, -0.99, -0.3, 0.0, 0.3,
                                                                                0.99, 1.0, 1.5)]
        probes += [float(x) for x in rng.uniform(0.0, end, 200)] + [tt * (1 + 1e-15) for tt in out_times]
        for t in probes:
            assert _at_output_time(t, out_times, near) == _scan(t, out_times), (t, out_times)

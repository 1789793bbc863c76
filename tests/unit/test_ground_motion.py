"""Ground-motion input: AT2 and CSV readers, scaling, baseline correction, errors."""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.io import ground_motion as gm

EL_CENTRO = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


@pytest.fixture(scope="module")
def el_centro():
    return gm.load(gm.bundled_record(EL_CENTRO))


def test_el_centro_header_and_peak(el_centro):
    assert el_centro.npts == 5372
    assert el_centro.dt == pytest.approx(0.01)
    assert el_centro.time[-1] == pytest.approx(5371 * 0.01)
    assert el_centro.pga_g == pytest.approx(0.281, rel=0.005)
    # stored in SI: the peak in m/s² is the peak in g times standard gravity
    assert el_centro.pga == pytest.approx(el_centro.pga_g * 9.80665)


def test_first_value_converted_from_g(el_centro):
    assert el_centro.acceleration[0] == pytest.approx(0.9984852e-03 * 9.80665, rel=1e-12)


def test_scale_to_pga(el_centro):
    scaled = gm.scale_to_pga(el_centro, 0.1)
    assert scaled.pga_g == pytest.approx(0.1, rel=1e-12)
    ratio = scaled.acceleration[np.abs(el_centro.acceleration) > 0] / \
        el_centro.acceleration[np.abs(el_centro.acceleration) > 0]
    assert np.allclose(ratio, 0.1 / el_centro.pga_g)


def test_csv_round_trip(el_centro, tmp_path):
    for units in ("g", "m/s2"):
        path = gm.write_csv(el_centro, tmp_path / f"rec_{units.replace('/', '')}.csv", units=units)
        back = gm.load(path, units=units)
        assert back.npts == el_centro.npts
        assert back.dt == pytest.approx(0.01)
        assert np.allclose(back.acceleration, el_centro.acceleration, rtol=1e-8, atol=1e-12)


def test_csv_comments_header_and_units(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("# a comment\ntime_s, accel\n0.0, 0.5  # trailing comment\n\n"
                    "0.1, -1.0\n0.2, 0.0\n")
    g = gm.read_csv(path, units="g")
    si = gm.read_csv(path, units="m/s2")
    assert np.allclose(g.acceleration, [0.5 * 9.80665, -9.80665, 0.0])
    assert np.allclose(si.acceleration, [0.5, -1.0, 0.0])
    assert si.dt == pytest.approx(0.1)


def test_value_at_interpolates_and_is_zero_after_end(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("0.0,0.0\n1.0,2.0\n2.0,4.0\n")
    m = gm.read_csv(path, units="m/s2")
    assert np.allclose(gm.value_at(m, [0.5, 1.5, 2.0, 2.5, 10.0]), [1.0, 3.0, 4.0, 0.0, 0.0])


def test_baseline_correction_reduces_velocity_drift(el_centro):
    # a record with an artificial constant offset drifts in velocity
    shifted = gm.GroundMotion(el_centro.time, el_centro.acceleration + 0.02, "x", "", 0.01)

    def final_velocity(m):
        return abs(np.trapezoid(m.acceleration, m.time))

    corrected = gm.baseline_correct(shifted, order=1)
    assert final_velocity(shifted) > 1.0
    assert final_velocity(corrected) < 0.05 * final_velocity(shifted)
    # a drift growing linearly in time needs the quadratic velocity fit
    ramp = gm.GroundMotion(el_centro.time, el_centro.acceleration + 1e-3 * el_centro.time,
                           "y", "", 0.01)
    assert final_velocity(gm.baseline_correct(ramp, order=2)) < 0.05 * final_velocity(ramp)
    # the shipped record is already processed: correcting it changes it little
    assert np.max(np.abs(gm.baseline_correct(el_centro).acceleration - el_centro.acceleration)) \
        < 1e-3 * el_centro.pga


def _at2(tmp_path, header4: str, body: str, name="bad.AT2"):
    path = tmp_path / name
    path.write_text("PEER NGA\nrecord\nACCELERATION IN G\n" + header4 + "\n" + body)
    return path


@pytest.mark.parametrize("header4, body, line, words", [
    ("POINTS=  3, STEP= .01 SEC", "0.1 0.2 0.3\n", 4, "NPTS"),
    ("NPTS= x3, DT= .01 SEC", "0.1 0.2 0.3\n", 4, "NPTS"),
    ("NPTS=  3, DT= -.01 SEC", "0.1 0.2 0.3\n", 4, "DT"),
    ("NPTS=  3, DT= .01 SEC", "0.1 0.2\n0.3 abc\n", 6, "non-numeric"),
    ("NPTS=  4, DT= .01 SEC", "0.1 0.2\n0.3\n", 6, "fewer values"),
    ("NPTS=  2, DT= .01 SEC", "0.1 0.2\n0.3\n", 6, "more values"),
])
def test_malformed_at2_names_file_and_line(tmp_path, header4, body, line, words):
    path = _at2(tmp_path, header4, body)
    with pytest.raises(gm.GroundMotionError) as info:
        gm.load(path)
    message = str(info.value)
    assert str(path) in message
    assert f"line {line}" in message
    assert words in message


def test_older_peer_header_layout(tmp_path):
    for header in ("  3    .0200    NPTS, DT", "NPTS=  3 DT= .02 SEC"):
        m = gm.read_at2(_at2(tmp_path, header, "0.1 -0.2\n0.05\n"))
        assert m.npts == 3 and m.dt == pytest.approx(0.02)
        assert np.allclose(m.acceleration, np.array([0.1, -0.2, 0.05]) * 9.80665)


def test_truncated_at2_header(tmp_path):
    path = tmp_path / "short.at2"
    path.write_text("PEER\nonly two lines\n")
    with pytest.raises(gm.GroundMotionError, match=r"short\.at2, line 3: truncated header"):
        gm.read_at2(path)


@pytest.mark.parametrize("text, line, words", [
    ("t,a\n0.0,1.0\n0.1,x\n", 3, "non-numeric"),
    ("0.0,1.0\n0.1,2.0\n0.1,3.0\n", 3, "non-increasing"),
    ("0.0,1.0\n0.2,2.0\n0.1,3.0\n", 3, "non-increasing"),
    ("0.0,1.0\n0.1,2.0,5.0\n", 2, "2 columns"),
])
def test_malformed_csv_names_file_and_line(tmp_path, text, line, words):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(gm.GroundMotionError) as info:
        gm.load(path, units="g")
    message = str(info.value)
    assert str(path) in message and f"line {line}" in message and words in message


def test_unknown_units_and_format(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("0,0\n1,1\n")
    with pytest.raises(gm.GroundMotionError, match="units"):
        gm.read_csv(path, units="ft/s2")
    with pytest.raises(gm.GroundMotionError, match="format"):
        gm.load(tmp_path / "rec.xyz")
    with pytest.raises(FileNotFoundError, match="RSN6"):
        gm.bundled_record("nope.AT2")


def test_a_record_read_again_is_the_one_kept_until_the_file_changes(tmp_path):
    import os

    p = tmp_path / "r.csv"
    p.write_text("time_s,acceleration_g\n0,0.1\n0.01,0.2\n")
    first = gm.load(p)
    assert gm.load(p) is first  # kept: validation and the run read it once
    with pytest.raises(ValueError, match="read-only"):
        first.acceleration[0] = 1.0  # shared by its readers: nobody may change it in place
    p.write_text("time_s,acceleration_g\n0,0.3\n0.01,0.2\n")  # same size, new contents
    os.utime(p, ns=(0, os.stat(p).st_mtime_ns + 1_000_000))
    again = gm.load(p)
    assert again is not first and again.acceleration[0] == pytest.approx(0.3 * gm.G_STANDARD)
    assert gm.load(p, units="m/s2").acceleration[0] == pytest.approx(0.3)  # other units: read again

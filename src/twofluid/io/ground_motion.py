"""Earthquake ground motions: reading PEER NGA AT2 and two-column CSV records.

Records enter the program here and leave this module in SI units: time [s],
acceleration [m/s²]. A record given in g is converted with standard gravity
g = 9.80665 m/s² (the unit of the record, not the gravity of a case).

>>> m = load(bundled_record("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"))
>>> m.npts, m.dt, round(m.pga_g, 3)
(5372, 0.01, 0.281)
>>> round(scale_to_pga(m, 0.1).pga_g, 6)
0.1
>>> bundled("RSN1120_KOBE_TAK000.AT2").magnitude
6.9
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from .tables import TableError, read_columns

__all__ = ["G_STANDARD", "GroundMotion", "GroundMotionError", "read_at2", "read_csv",
           "load", "scale_to_pga", "baseline_correct", "value_at", "interpolator", "bundled_record",
           "write_csv", "BundledRecord", "BUNDLED", "bundled", "liquefied_site_record"]

G_STANDARD = 9.80665  # [m/s²] the unit "g" of strong-motion records
_HEADER = re.compile(r"NPTS\s*=\s*([^,\s]+)\s*,?\s*DT\s*=\s*([^\s,]+)", re.IGNORECASE)
# the older PEER layout: "  5372    .0100    NPTS, DT"
_HEADER_OLD = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT", re.IGNORECASE)


class GroundMotionError(ValueError):
    """A ground-motion file that cannot be read; the message names file and line."""


@dataclass(frozen=True)
class GroundMotion:
    """An acceleration record.

    Attributes
    ----------
    time : ndarray
        Sample times [s], strictly increasing.
    acceleration : ndarray
        Ground acceleration [m/s²].
    name : str
        Short name (file stem by default).
    source : str
        Path the record was read from ("" if built in memory).
    dt : float or None
        Constant sample interval [s], or None for an uneven record.
    """

    time: np.ndarray
    acceleration: np.ndarray
    name: str = ""
    source: str = ""
    dt: float | None = None

    @property
    def npts(self) -> int:
        return int(self.time.size)

    @property
    def duration(self) -> float:
        """Time of the last sample [s]."""
        return float(self.time[-1])

    @property
    def pga(self) -> float:
        """Peak absolute acceleration [m/s²]."""
        return float(np.max(np.abs(self.acceleration)))

    @property
    def pga_g(self) -> float:
        """Peak absolute acceleration in units of standard gravity [g]."""
        return self.pga / G_STANDARD


def _fail(path, line: int | None, what: str) -> GroundMotionError:
    where = f"{path}" if line is None else f"{path}, line {line}"
    return GroundMotionError(f"{where}: {what}")


def read_at2(path: str | Path) -> GroundMotion:
    """Read a PEER NGA ``.AT2`` file (acceleration in g) into SI units.

    Format: four header lines, the fourth holding ``NPTS= <int>, DT= <float> SEC``
    (or, in the older PEER layout, ``<int> <float> NPTS, DT``),
    then ``NPTS`` values in g, any number per line (five in PEER files).
    Values beyond NPTS are an error, as are fewer values than NPTS.
    """
    path = Path(path)
    lines = path.read_text(errors="replace").splitlines()
    if len(lines) < 4:
        raise _fail(path, len(lines) + 1, "truncated header: an AT2 file has 4 header lines")
    match = _HEADER.search(lines[3]) or _HEADER_OLD.search(lines[3])
    if match is None:
        raise _fail(path, 4, f"expected 'NPTS=..., DT=...' in the header, found {lines[3]!r}")
    try:
        npts = int(match.group(1))
        dt = float(match.group(2))
    except ValueError:
        raise _fail(path, 4, f"bad NPTS/DT header values {match.group(0)!r}") from None
    if npts <= 0 or not dt > 0.0 or not np.isfinite(dt):
        raise _fail(path, 4, f"NPTS must be > 0 and DT > 0, got NPTS={npts}, DT={dt}")
    values: list[float] = []
    for number, line in enumerate(lines[4:], start=5):
        for token in line.split():
            try:
                values.append(float(token))
            except ValueError:
                raise _fail(path, number, f"non-numeric value {token!r}") from None
            if not np.isfinite(values[-1]):
                raise _fail(path, number, f"non-finite value {token!r}")
        if len(values) > npts:
            raise _fail(path, number, f"more values than NPTS={npts}")
    if len(values) < npts:
        raise _fail(path, len(lines), f"fewer values ({len(values)}) than NPTS={npts}")
    accel = np.asarray(values) * G_STANDARD
    return GroundMotion(np.arange(npts) * dt, accel, path.stem, str(path), dt)


def read_csv(path: str | Path, units: str = "g") -> GroundMotion:
    """Read a two-column ``time_s, acceleration`` CSV file.

    ``units`` is the unit of the acceleration column: ``"g"`` or ``"m/s2"``.
    Blank lines and text after ``#`` are ignored; the first data line may be a
    header (it is skipped if its first field is not a number). Times must be
    strictly increasing.
    """
    path = Path(path)
    factor = _unit_factor(units, path)
    times: list[float] = []
    accel: list[float] = []
    try:
        rows = read_columns(path.read_text(errors="replace"), 2)
    except TableError as exc:
        raise _fail(path, exc.line, exc.what) from None
    for number, (t, a) in rows:
        if not (np.isfinite(t) and np.isfinite(a)):
            raise _fail(path, number, f"non-finite value in {t}, {a}")
        if times and t <= times[-1]:
            raise _fail(path, number, f"non-increasing time {t} after {times[-1]}")
        times.append(t)
        accel.append(a)
    if len(times) < 2:
        raise _fail(path, None, f"needs at least 2 samples, found {len(times)}")
    time = np.asarray(times)
    steps = np.diff(time)
    dt = float(steps[0]) if np.allclose(steps, steps[0], rtol=1e-6, atol=0.0) else None
    return GroundMotion(time, np.asarray(accel) * factor, path.stem, str(path), dt)


def _unit_factor(units: str, path) -> float:
    key = units.strip().lower().replace("²", "2").replace("^", "").replace(" ", "")
    if key == "g":
        return G_STANDARD
    if key in ("m/s2", "m/s/s", "si"):
        return 1.0
    raise _fail(path, None, f"unknown acceleration units {units!r}; use 'g' or 'm/s2'")


def load(path: str | Path, units: str | None = None) -> GroundMotion:
    """Read a record, choosing the reader by extension (``.at2`` or ``.csv``/``.txt``).

    AT2 records are always in g; ``units`` applies to CSV (default ``"g"``). A run validates its
    case and then builds it, each reading the record: the last few records read are kept (their
    arrays read-only) and given again while the file's size and modification time are unchanged.
    """
    path = Path(path)
    try:
        st = path.stat()
    except OSError:
        return _load(path, units)  # the reader names the problem
    return _load_cached(str(path.resolve()), st.st_mtime_ns, st.st_size, units)


@lru_cache(maxsize=8)
def _load_cached(path: str, mtime_ns: int, size: int, units: str | None) -> GroundMotion:
    m = _load(Path(path), units)
    m.time.flags.writeable = False
    m.acceleration.flags.writeable = False
    return m


def _load(path: Path, units: str | None) -> GroundMotion:
    suffix = path.suffix.lower()
    if suffix == ".at2":
        if units is not None and _unit_factor(units, path) != G_STANDARD:
            raise _fail(path, None, "AT2 records are in g; units must be 'g' or omitted")
        return read_at2(path)
    if suffix in (".csv", ".txt", ".dat"):
        return read_csv(path, units or "g")
    raise _fail(path, None, f"unknown ground-motion format {suffix!r}; use .AT2 or .csv")


def write_csv(motion: GroundMotion, path: str | Path, units: str = "m/s2") -> Path:
    """Write ``time_s, acceleration`` with a header (round trip of :func:`read_csv`)."""
    path = Path(path)
    factor = _unit_factor(units, path)
    data = np.column_stack([motion.time, motion.acceleration / factor])
    label = "acceleration_g" if factor != 1.0 else "acceleration_m_s2"
    np.savetxt(path, data, delimiter=",", header=f"time_s,{label}", comments="", fmt="%.10g")
    return path


def scale_to_pga(motion: GroundMotion, pga_g: float, polarity: int = 1) -> GroundMotion:
    """Return the record multiplied so that its peak |a| is ``pga_g`` [g], with the sign
    ``polarity`` (1: as recorded, -1: reversed, a → −a; a suite run with both polarities sees each
    record's asymmetric pulses in both directions).

    >>> m = GroundMotion(np.array([0.0, 0.01, 0.02]), np.array([0.0, 2.0, -1.0]))
    >>> scale_to_pga(m, 0.1, polarity=-1).acceleration / G_STANDARD
    array([-0.  , -0.1 ,  0.05])
    """
    if polarity not in (1, -1) or isinstance(polarity, bool):
        raise ValueError(f"scale_to_pga: polarity must be 1 or -1, got {polarity!r}")
    if motion.pga == 0.0:
        raise GroundMotionError(f"{motion.source or motion.name}: cannot scale a zero record")
    factor = polarity * pga_g * G_STANDARD / motion.pga
    return replace(motion, acceleration=motion.acceleration * factor)


def baseline_correct(motion: GroundMotion, order: int = 1) -> GroundMotion:
    """Remove a polynomial trend from the velocity (classic baseline correction).

    The velocity v(t) = ∫ a dt (trapezoidal) is fitted in least squares by a
    polynomial p(t) of degree ``order`` [m/s]; the corrected acceleration is
    a − dp/dt. A constant (order 0) fit of v removes nothing from a, so
    ``order`` must be ≥ 1: order 1 removes a constant acceleration offset, order 2
    also a linear drift. The corrected record ends with a much smaller velocity
    (and displacement) drift, which is what a shaking base should do.

    Reference: Boore, D. M. (2001), Effect of baseline corrections on
    displacements and response spectra, BSSA 91(5), 1199–1211.
    """
    if order < 1:
        raise ValueError("baseline_correct: order must be >= 1")
    t, a = motion.time, motion.acceleration
    velocity = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    coeffs = np.polynomial.polynomial.polyfit(t, velocity, order)
    trend = np.polynomial.polynomial.polyval(t, np.polynomial.polynomial.polyder(coeffs))
    return replace(motion, acceleration=a - trend)


def value_at(motion: GroundMotion, t) -> np.ndarray:
    """Acceleration [m/s²] at time(s) ``t`` [s]: linear interpolation, 0 outside the record."""
    return np.interp(t, motion.time, motion.acceleration, left=0.0, right=0.0)


def interpolator(motion: GroundMotion):
    """``t -> value_at(motion, t)`` as one callable with no Python call of its own before NumPy's
    (what a run reads its record with, once per step).

    >>> m = GroundMotion(np.array([0.0, 1.0]), np.array([0.0, 2.0]))
    >>> interpolator(m)(np.array([0.5, 2.0])).tolist() == value_at(m, np.array([0.5, 2.0])).tolist()
    True
    """
    return partial(np.interp, xp=motion.time, fp=motion.acceleration, left=0.0, right=0.0)


@dataclass(frozen=True)
class BundledRecord:
    """What the package says of one shipped record (``data/ground_motions/PROVENANCE.md`` gives the
    sources, distances, site classes and how each record enters a run).

    Attributes
    ----------
    path : str
        Path under ``twofluid/data/ground_motions``.
    earthquake, station, component : str
        The earthquake and station; the component as the PEER file's header gives it.
    magnitude : float
        Moment magnitude M_w of the earthquake (PEER NGA-West2): the value of ``[ground_motion]
        magnitude`` (the simplified procedure's magnitude scaling factor) for this record.
    site_class : str
        NEHRP site class of the recording station (from its V_s30).
    input_motion : bool
        False for a record made at a site that itself liquefied: it carries that site's
        liquefied response and ships as an example of such a surface record, not as an input.
    """

    path: str
    earthquake: str
    station: str
    component: str
    magnitude: float
    site_class: str
    input_motion: bool = True

    @property
    def name(self) -> str:
        """File name (the name a case file gives in ``[ground_motion] file``)."""
        return self.path.rsplit("/", 1)[-1]


_SHIPPED = (
    BundledRecord("RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "Imperial Valley-02, 1940", "El Centro Array #9",
                  "180", 6.95, "D"),
    BundledRecord("RSN1120_KOBE_TAK000.AT2", "Kobe, Japan, 1995", "Takatori", "0", 6.9, "D"),
    BundledRecord("RSN779_LOMAP_LGP000.AT2", "Loma Prieta, 1989", "LGPC (Los Gatos Presentation Center)",
                  "0", 6.93, "C"),
    BundledRecord("RSN1180_CHICHI_CHY002-N.AT2", "Chi-Chi, Taiwan, 1999", "CHY002", "N", 7.62, "D"),
    BundledRecord("RSN1762_HECTOR_ABY360.AT2", "Hector Mine, 1999", "Amboy", "360", 7.13, "C"),
    BundledRecord("liquefied-site/RSN8119_CCHURCH_PRPCS.AT2", "Christchurch, New Zealand, 2011",
                  "Pages Road Pumping Station (PRPC)", "S", 6.2, "D", input_motion=False),
)
#: The shipped records by file name (the input suite, then the liquefied-site example).
BUNDLED: dict[str, BundledRecord] = {b.name: b for b in _SHIPPED}


def bundled(name: str) -> BundledRecord | None:
    """The shipped record called ``name`` (its file name, or its path under
    ``data/ground_motions``), or None if no shipped record has that name.

    >>> bundled("liquefied-site/RSN8119_CCHURCH_PRPCS.AT2").input_motion
    False
    >>> bundled("my-record.csv") is None
    True
    """
    entry = BUNDLED.get(Path(name).name)
    return entry if entry is not None and name in (entry.name, entry.path) else None


def liquefied_site_record(path: str | Path) -> BundledRecord | None:
    """The shipped record of a site that itself liquefied whose file name ``path`` has (wherever
    the file lies: a copy is the same recording), else None.

    >>> liquefied_site_record("/some/where/RSN8119_CCHURCH_PRPCS.AT2").station
    'Pages Road Pumping Station (PRPC)'
    >>> liquefied_site_record("RSN1120_KOBE_TAK000.AT2") is None
    True
    """
    entry = BUNDLED.get(Path(path).name)
    return entry if entry is not None and not entry.input_motion else None


def bundled_record(name: str) -> Path:
    """Path of a record shipped in ``twofluid/data/ground_motions`` (see PROVENANCE.md there): by
    file name, or by path under that folder (``liquefied-site/RSN8119_CCHURCH_PRPCS.AT2``)."""
    folder = Path(__file__).parent.parent / "data" / "ground_motions"  # (the package installed as files)
    if not folder.is_dir():  # a zipped package (importlib.resources: ~10 ms of imports a run does not pay otherwise)
        from importlib import resources

        folder = resources.files("twofluid") / "data" / "ground_motions"
    entry = bundled(name)
    target = folder.joinpath(*(entry.path if entry else name).split("/"))
    if not target.is_file():
        shipped = [b.path for b in _SHIPPED]
        raise FileNotFoundError(f"no bundled record {name!r}; shipped: {', '.join(shipped)}")
    return Path(str(target))

"""Write the record-format test fixtures in tests/data/records/ from a real bundled record.

The samples are those of El Centro 1940 NS (SLAMMER ``ImperialValley_1940_ELC-180.txt``,
3949 values in g at dt = 0.01 s, data/records/slammer/); only the *layout* is that of each
format, copied from real files:

- ``ELC180_ngawest2.AT2`` — PEER NGA-West2 header (``NPTS=  3949, DT=   .0100 SEC,``), values in
  Fortran ``E15.7`` style (``  .6403180E-02``), 5 per row;
- ``ELC180_peer2000.AT2`` — the older PEER / NGA-West1 header (``3949   0.01000   NPTS, DT``,
  ``ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: ...``);
- ``ELC180.V2`` — COSMOS V2 (format v01.20) modelled on a CESMD/USGS processed file (USGS
  gmprocess test data ``us1000hyfh ... .acc.V2c``): 13 text lines, 100 integer and 100 real
  header values, comments with ``<SCNL>``, the acceleration in cm/s² as ``(1E15.6)``, then a
  velocity record (cm/s, ``(8F10.4)``) that readers must skip;
- ``ELC180.knet`` — K-NET ASCII (as ObsPy's ``obspy/io/nied/tests/data/test.knet``): 17 header
  lines, counts 8 per row with ``Scale Factor 3920(gal)/6182761``.

The event/station header values describe the 1940 record; the COSMOS network/channel codes and
the K-NET station code are invented for the layout. Run from the repository root::

    python scripts/make_record_fixtures.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "data" / "records" / "slammer" / "ImperialValley_1940_ELC-180.txt"
OUT = ROOT / "tests" / "data" / "records"
G_GAL = 980.665
DT = 0.01


def fortran_e(x: float, digits: int = 7, width: int = 15) -> str:
    """``x`` as Fortran prints ``E{width}.{digits}``, mantissa in [0.1, 1): ``.6403180E-02``."""
    if x == 0:
        text = "." + "0" * digits + "E+00"
    else:
        exponent = math.floor(math.log10(abs(x))) + 1
        mantissa = round(abs(x) / 10.0**exponent, digits)
        if mantissa >= 1.0:
            mantissa, exponent = mantissa / 10.0, exponent + 1
        text = ("-" if x < 0 else "") + f"{mantissa:.{digits}f}"[1:] + f"E{exponent:+03d}"
    return text.rjust(width)


def rows(values, per_row: int, fmt) -> list[str]:
    return [
        "".join(fmt(v) for v in values[i : i + per_row]) for i in range(0, len(values), per_row)
    ]


def write_at2(acc_g: np.ndarray) -> None:
    n = acc_g.size
    body = rows(acc_g, 5, fortran_e)
    west2 = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Imperial Valley-02, 5/19/1940, El Centro Array #9, 180",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS={n:6d}, DT=   .{round(DT * 1e4):04d} SEC,",
    ]
    (OUT / "ELC180_ngawest2.AT2").write_text("\n".join(west2 + body) + "\n")
    old = [
        "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.",
        "IMPERIAL VALLEY 05/19/40 0439, EL CENTRO ARRAY #9, 180",
        "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.2 Hz LP=15.0 Hz",
        f" {n}   {DT:.5f}   NPTS, DT",
    ]
    (OUT / "ELC180_peer2000.AT2").write_text("\n".join(old + body) + "\n")


def _cosmos_record(kind: str, values: np.ndarray, unit_code: int, unit_text: str, fmt) -> str:
    n = values.size
    ints = np.full(100, -999, dtype=int)
    ints[[0, 1, 2, 3, 4]] = [2, {"acceleration": 1, "velocity": 2}[kind], unit_code, 120, 1]
    ints[[10, 11]] = [2, 2]  # network operating / owning the station: USGS
    ints[[39, 40, 41, 42, 43, 44]] = [1940, 140, 5, 19, 4, 36]  # start: year, julday, ..., min
    ints[45] = 5  # time quality
    ints[49] = 1  # station channel number
    ints[53] = 180  # sensor azimuth, degrees from north
    reals = np.full(100, -999.0)
    reals[[0, 1]] = [32.794, -115.549]
    reals[[9, 10, 11, 12]] = [32.733, -115.5, 16.0, 6.95]
    reals[16] = 12.99  # epicentral distance, km
    reals[29] = 40.0  # start second
    reals[33] = DT  # sampling interval of the recorded data, s
    reals[34] = n * DT
    reals[61] = DT * 1000.0  # sample interval of this series, ms
    reals[62] = n * DT  # record length = npts * dt
    peak = int(np.argmax(np.abs(values)))
    reals[63], reals[64] = values[peak], peak * DT
    reals[65] = values.mean()
    unit_short = "cm/sec2" if kind == "acceleration" else "cm/sec"
    text = [
        f"{'Corrected ' + kind:<26}(Format v01.20 with 13 text lines) floorslide fixture",
        "Record of Imperial Valley Earthquake of Sun May 19, 1940 04:36 UTC",
        "Hypocenter: 32.733 -115.500 H= 16km Mw=6.95",
        "Origin: 1940/05/19 04:36:40    UTC",
        f"{'Statn No: 02-00117':<20}Code:{'NP-ELC':<10}{'USGS':<5}El Centro Array #9",
        "Coords: 32.7940 -115.5490  Site geology: Alluvium",
        "Recorder: (see cmnt)      ( 1 Chns of   3 at Sta) Sensor: (see comment)",
        "Rcrd start time: 1940/05/19 04:36:40.000 UTC (Q=5) RcrdId: (see comment)",
        "Sta Chan   1: 180 deg (Rcrdr Chan  1) Location: Free field",
        f"Raw record length = {n * DT:7.3f} sec, Uncor max =   -999, at   -999 sec.",
        f"Processed:2024-01-01 00:00:00 GMT, USGS, Max = {values[peak]:8.3f} {unit_short} "
        f"at {peak * DT:7.3f} sec",
        "Record filtered below -999 Hz (periods over -999 secs), and above -999 Hz",
        "Values used when parameter or data value is unknown/unspecified:   -999, -999.00",
    ]
    lines = list(text)
    lines.append(" 100 Integer-header values follow on  10 lines, Format= (10I8)")
    lines += rows(ints, 10, lambda v: f"{v:8d}")
    lines.append(" 100 Real-header values follow on  20 lines, Format= (5F15.6)")
    lines += rows(reals, 5, lambda v: f"{v:15.6f}")
    lines.append('   3 Comment line(s) follow, each starting with a "|":')
    lines.append("| Sensor: optical-mechanical accelerograph")
    lines.append("| RcrdId: floorslide fixture, values of SLAMMER ImperialValley_1940_ELC-180")
    lines.append("|<SCNL>ELC.HNN.NP.--    <AUTH> 2024/01/01 00:00:00.000")
    per_row, spec = fmt
    lines.append(
        f"{n:8d} {kind} pts, approx {round(n * DT):4d} secs, units={unit_text}({unit_code:02d}),"
        f"Format=({spec})"
    )
    lines += rows(values, per_row, fmt=lambda v: f"{v:15.6e}" if per_row == 1 else f"{v:10.4f}")
    lines.append(f"End-of-data for Chan  1 {kind}")
    return "\n".join(lines) + "\n"


def write_cosmos(acc_g: np.ndarray) -> None:
    acc = acc_g * G_GAL  # cm/s²
    vel = np.concatenate(([0.0], np.cumsum(0.5 * DT * (acc[1:] + acc[:-1]))))  # cm/s
    text = _cosmos_record("acceleration", acc, 4, "cm/sec2", (1, "1E15.6"))
    text += _cosmos_record("velocity", vel, 5, "cm/sec ", (8, "8F10.4"))
    (OUT / "ELC180.V2").write_text(text)


SCALE_GAL, SCALE_COUNTS = 3920, 6182761


def write_knet(acc_g: np.ndarray) -> None:
    counts = np.rint(acc_g * G_GAL * SCALE_COUNTS / SCALE_GAL).astype(int)
    peak = np.abs(counts).max() * SCALE_GAL / SCALE_COUNTS
    header = [
        ("Origin Time", "1940/05/19 13:36:40"),  # JST, as K-NET files give it
        ("Lat.", "32.733"),
        ("Long.", "-115.500"),
        ("Depth. (km)", "16"),
        ("Mag.", "7.0"),
        ("Station Code", "ELC180"),
        ("Station Lat.", "32.7940"),
        ("Station Long.", "-115.5490"),
        ("Station Height(m)", "-12"),
        ("Record Time", "1940/05/19 13:36:55"),
        ("Sampling Freq(Hz)", "100Hz"),
        ("Duration Time(s)", f"{round(acc_g.size * DT)}"),
        ("Dir.", "N-S"),
        ("Scale Factor", f"{SCALE_GAL}(gal)/{SCALE_COUNTS}"),
        ("Max. Acc. (gal)", f"{peak:.3f}"),
        ("Last Correction", "1940/05/19 13:36:40"),
        ("Memo.", "floorslide fixture: El Centro 1940 NS (SLAMMER ELC-180) values"),
    ]
    lines = [f"{key:<18}{value}" for key, value in header]
    lines += rows(counts, 8, lambda v: f"{v:8d} ")
    (OUT / "ELC180.knet").write_text("\n".join(lines) + "\n")


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    acc_g = np.loadtxt(SOURCE)
    write_at2(acc_g)
    write_cosmos(acc_g)
    write_knet(acc_g)
    for path in sorted(OUT.iterdir()):
        print(f"{path.relative_to(ROOT)}  {path.stat().st_size:,} bytes")


if __name__ == "__main__":
    main()

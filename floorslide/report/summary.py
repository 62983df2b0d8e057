"""The compact summary of a study: what ``floorslide run`` and ``floorslide demo`` print last,
``floorslide table --summary`` prints again and the HTML report opens with.

Per record set and content on a floor: one row per building, its median PFA at that floor
(g) and the median peak slide (mm) over every record of the set at each friction value,
with how many records made the object rock (and overturn it at that friction value, where
the file holds rocking results). It is read from the design tables
(:func:`floorslide.report.design_tables`); it computes nothing of its own.

Rocking follows the tables' rule (docs/design.md §10): an object that rocks under a record is
simulated as a slide–rock block (it rocks, and slides while it rocks where friction gives
way), not as a slider, and never counts as 0 slide; it is its own
outcome, ranked above every slide. A cell reads ``rocks (k/n)`` when the median falls on
rocking records, and a median that does not is followed by ``(k rock)`` when some records
rock; where the file holds rocking results (the ``rocking`` table) both say how many of them
overturned: ``rocks (k/n; m overturn)``, ``(k rock; m overturn)``.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass

from floorslide.report.columns import MIN_RECORDS, ROCK, DesignTables

MAX_FRICTION_COLUMNS = 8
"""At most this many friction values per summary table (evenly picked, first and last kept;
the heading says how many of how many, and the ``slides`` table has them all)."""

LEGEND_SIMULATED = (
    "('rocks (k/n; m overturn)': the median record rocks — k of n records rock (simulated as "
    "slide–rock blocks; m of them overturn); rocking records never count as 0 slide and rank "
    "above every slide; '(k rock; m overturn)': k records rock; their rotations and impacts: "
    "the rocking table)"
)
LEGEND_OLDER = (
    "('rocks (k/n)': the median record rocks — rocking objects are not simulated as sliders "
    "and never count as 0; '(k rock)': k records rock, ranked above every slide)"
)


@dataclass(frozen=True)
class SummaryRow:
    """One building of a :class:`SummaryBlock`: its median PFA at the floor (g; NaN when not
    stored) and one cell of text per friction value of the block."""

    building: str
    pfa_g: float
    cells: tuple[str, ...]


@dataclass(frozen=True)
class SummaryBlock:
    """The summary of one content on one floor under one record set."""

    record_set: str
    content: str
    floor: int
    n_records: int
    heading: str
    legend: str
    caution: str
    friction: tuple[tuple[float, float], ...]
    friction_all: int
    rows: tuple[SummaryRow, ...]

    @property
    def friction_labels(self) -> tuple[str, ...]:
        """``mu 0.1``, or ``mu 0.1/0.15`` (mu_k/mu_s) where some pair has mu_s ≠ mu_k."""
        split = any(abs(k - s) > 1e-12 for k, s in self.friction)
        return tuple(f"mu {k:g}/{s:g}" if split else f"mu {k:g}" for k, s in self.friction)


def _pick(items: Sequence, cap: int) -> list:
    if len(items) <= cap:
        return list(items)
    idx = sorted({round(i * (len(items) - 1) / (cap - 1)) for i in range(cap)})
    return [items[i] for i in idx]


def _cell(r: dict, over: str) -> str:
    med, k = r["peak_slide_median"], r["n_rock"]
    if r["median_outcome"] == ROCK:
        return f"rocks ({k}/{r['n_records']}{over})"
    if med != med:
        return "—"
    return f"{1000 * med:.1f}" + (f" ({k} rock{over})" if k else "")


def summary_blocks(tables: DesignTables) -> list[SummaryBlock]:
    """The summary of `tables`, one :class:`SummaryBlock` per record set, content and floor in
    the tables' order."""
    groups: dict = defaultdict(list)
    for row in tables["slides"]:
        groups[(row["record_set"], row["content"], row["floor"])].append(row)
    pfa = {(r["record_set"], r["building"], r["floor"]): r for r in tables["pfa"]}
    rocking = {
        (r["record_set"], r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"]): r
        for r in (tables["rocking"] if "rocking" in tables.tables else [])
    }
    rocking_objects = {k[:4] for k in rocking}
    blocks = []
    for (rset, content, floor), rows in groups.items():
        pairs_all = sorted({(r["mu_k"], r["mu_s"]) for r in rows})
        pairs = _pick(pairs_all, MAX_FRICTION_COLUMNS)
        buildings = list(dict.fromkeys(r["building"] for r in rows))
        n = max(r["n_records"] for r in rows)
        what = "base of the 2-DOF oscillator" if rows[0]["model"] == "oscillator" else "object"
        simulated = any((rset, b, floor, content) in rocking_objects for b in buildings)
        shown = (
            f"; {len(pairs)} of {len(pairs_all)} friction values (all: the slides table)"
            if len(pairs) < len(pairs_all)
            else ""
        )
        heading = (
            f"{rset} ({n} records) — {content!r} on floor {floor}: median peak slide of the "
            f"{what} over all {n} records, mm{shown}"
        )
        if simulated:
            legend = LEGEND_SIMULATED
        elif any(r["n_rock"] for r in rows):  # a file written before rocking was simulated
            legend = LEGEND_OLDER
        else:
            legend = ""
        caution = f"(caution: {n} < {MIN_RECORDS} records per set)" if n < MIN_RECORDS else ""
        out_rows = []
        for b in buildings:
            cells = []
            for mu_k, mu_s in pairs:
                rock = rocking.get((rset, b, floor, content, mu_k, mu_s))
                over = f"; {rock['n_overturn']} overturn" if rock else ""
                r = next(
                    (
                        x
                        for x in rows
                        if x["building"] == b and x["mu_k"] == mu_k and x["mu_s"] == mu_s
                    ),
                    None,
                )
                cells.append("—" if r is None else _cell(r, over))
            p = pfa.get((rset, b, floor))
            pfa_g = float(p["pfa_g_median"]) if p else math.nan
            out_rows.append(SummaryRow(b, pfa_g, tuple(cells)))
        blocks.append(
            SummaryBlock(
                record_set=rset,
                content=content,
                floor=int(floor),
                n_records=int(n),
                heading=heading,
                legend=legend,
                caution=caution,
                friction=tuple(pairs),
                friction_all=len(pairs_all),
                rows=tuple(out_rows),
            )
        )
    return blocks


def quality_lines(rows: Sequence[dict]) -> list[str]:
    """One line per quality check that tripped: how many records, which; from the ``records``
    table."""
    from collections import Counter

    counts: Counter = Counter()
    names: dict[str, list[str]] = {}
    for row in rows:
        for code in filter(None, row["qa_flags"].split(",")):
            counts[code] += 1
            names.setdefault(code, []).append(row["record"])
    n = len({(r["record_set"].split("@")[0], r["record"]) for r in rows})
    if not counts:
        return [f"quality checks: no flags on the {n} records"]
    out = [f"quality checks on the {n} records (details: the records table):"]
    for code, k in counts.items():
        shown = ", ".join(names[code][:4]) + (", …" if k > 4 else "")
        out.append(f"  {code}: {k} records ({shown})")
    return out


def _pfa_text(value: float) -> str:
    return "—" if value != value else f"{value:.2f}"


def format_summary(tables: DesignTables) -> str:
    """The summary as text: per record set, content and floor a heading, the line that
    explains the rocking cells (under the first table that has them; none when nothing
    rocks), a caution below 8 records and a
    Markdown table (building, PFA (g), one column per friction value); then the records'
    quality checks. INCOMPLETE first when the run is not finished."""
    out = []
    if getattr(tables, "status", ""):
        out += [tables.status, ""]
    said: set[str] = set()
    for b in summary_blocks(tables):
        out.append(b.heading)
        if b.legend and b.legend not in said:  # once, under the first table it explains
            out.append(b.legend)
            said.add(b.legend)
        if b.caution:
            out.append(b.caution)
        out.append("| building | PFA (g) | " + " | ".join(b.friction_labels) + " |")
        out.append("|" + "---|" * (len(b.friction) + 2))
        for r in b.rows:
            out.append(f"| {r.building} | {_pfa_text(r.pfa_g)} | " + " | ".join(r.cells) + " |")
        out.append("")
    out += quality_lines(tables["records"]) if "records" in tables.tables else []
    return "\n".join(out)


def summary_rows(tables: DesignTables) -> list[dict]:
    """The summary as rows for JSON (SI values): per record set, building, floor, content and
    friction pair the median peak slide (m; None where the median is ``rock``), the median
    outcome, ``n_records``, ``n_rock``, ``n_overturn`` (None without rocking results) and the
    median PFA (m/s² and g) at the floor."""
    pfa = {(r["record_set"], r["building"], r["floor"]): r for r in tables["pfa"]}
    rocking = {
        (r["record_set"], r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"]): r
        for r in (tables["rocking"] if "rocking" in tables.tables else [])
    }

    def num(x):
        return None if x is None or x != x else float(x)

    out = []
    for r in tables["slides"]:
        p = pfa.get((r["record_set"], r["building"], r["floor"]))
        rock = rocking.get(
            (r["record_set"], r["building"], r["floor"], r["content"], r["mu_k"], r["mu_s"])
        )
        out.append(
            dict(
                record_set=r["record_set"],
                building=r["building"],
                floor=int(r["floor"]),
                content=r["content"],
                mu_k=float(r["mu_k"]),
                mu_s=float(r["mu_s"]),
                n_records=int(r["n_records"]),
                median_outcome=r["median_outcome"],
                peak_slide_median=num(r["peak_slide_median"]),
                n_rock=int(r["n_rock"]),
                n_overturn=int(rock["n_overturn"]) if rock else None,
                pfa_median=num(p["pfa_median"]) if p else None,
                pfa_g_median=num(p["pfa_g_median"]) if p else None,
            )
        )
    return out
